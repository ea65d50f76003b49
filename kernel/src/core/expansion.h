// Exact sign of a 3 × 3 determinant of doubles by floating-point expansions (Shewchuk,
// "Adaptive precision floating-point arithmetic and fast robust geometric predicates", DCG 18,
// 1997, §2 and the stage of orient3dadapt that is exact when the differences are). An
// expansion is a sum of doubles of increasing magnitude that do not overlap; sums and products
// by a double are exact, with round-to-nearest and no overflow or underflow.
//
// Why: orient3d's filter cannot decide an exactly zero determinant (four exactly coplanar
// points: every exactly planar quadrilateral a Body's constructor and the convexity
// certificate check), and its exact stage is Mpzf, a few hundred ns with its bookkeeping. Here
// it is about sixty double operations and no memory.
#pragma once

#include <cmath>
#include <optional>
#include <utility>

#include "hedra/core/predicates.h"

namespace hedra::internal::expansion {

// x + y = a + b exactly, x = fl(a + b) (Knuth's TwoSum).
inline void two_sum(double a, double b, double& x, double& y) {
  x = a + b;
  const double bv = x - a, av = x - bv;
  y = (a - av) + (b - bv);
}

// x + y = a + b exactly, where |a| ≥ |b| or a = 0 (Dekker's FastTwoSum).
inline void fast_two_sum(double a, double b, double& x, double& y) {
  x = a + b;
  y = b - (x - a);
}

// hi + lo = a, each with at most 26 significant bits (Dekker's split; |a| < 2^996).
inline void split(double a, double& hi, double& lo) {
  constexpr double kSplitter = 134217729.0;  // 2^27 + 1
  const double c = kSplitter * a;
  hi = c - (c - a);
  lo = a - hi;
}

// x + y = a · b exactly, x = fl(a · b) (Dekker's TwoProduct, no fused multiply-add).
inline void two_product(double a, double b, double& x, double& y) {
  x = a * b;
  double ahi, alo, bhi, blo;
  split(a, ahi, alo);
  split(b, bhi, blo);
  y = alo * blo - (((x - ahi * bhi) - alo * bhi) - ahi * blo);
}

// h = e + b, zero components left out; returns h's length (≥ 1; {0} for zero). h may not be e.
inline int grow(int elen, const double* e, double b, double* h) {
  double q = b;
  int n = 0;
  for (int i = 0; i < elen; ++i) {
    double sum, err;
    two_sum(q, e[i], sum, err);
    q = sum;
    if (err != 0) h[n++] = err;
  }
  if (q != 0 || n == 0) h[n++] = q;
  return n;
}

// h = e + f, zero components left out (Shewchuk's EXPANSION-SUM): at most elen + flen terms.
inline int sum(int elen, const double* e, int flen, const double* f, double* h) {
  double a[32], b[32];
  int n = elen;
  for (int i = 0; i < n; ++i) a[i] = e[i];
  double* from = a;
  double* to = b;
  for (int j = 0; j < flen; ++j) {
    n = grow(n, from, f[j], to);
    std::swap(from, to);
  }
  for (int i = 0; i < n; ++i) h[i] = from[i];
  return n;
}

// h = e · b, zero components left out (Shewchuk's SCALE-EXPANSION): at most 2·elen terms.
inline int scale(int elen, const double* e, double b, double* h) {
  double q, err;
  two_product(e[0], b, q, err);
  int n = 0;
  if (err != 0) h[n++] = err;
  for (int i = 1; i < elen; ++i) {
    double p1, p0, s;
    two_product(e[i], b, p1, p0);
    two_sum(q, p0, s, err);
    if (err != 0) h[n++] = err;
    fast_two_sum(p1, s, q, err);
    if (err != 0) h[n++] = err;
  }
  if (q != 0 || n == 0) h[n++] = q;
  return n;
}

// a·b − c·d exactly, as an expansion of at most 4 terms.
inline int minor2(double a, double b, double c, double d, double* h) {
  double p[2], q[2];
  two_product(a, b, p[1], p[0]);
  two_product(c, d, q[1], q[0]);
  q[0] = -q[0];
  q[1] = -q[1];
  return sum(2, p, 2, q, h);
}

// Whether every non-zero value lies in [2^-150, 2^150]. Then each is a multiple of 2^-202, so
// every component and every intermediate product of the determinant's expansion is a multiple
// of 2^-606 (far above the normal range's 2^-1022: no underflow) and below 2^460 (no
// overflow), and split() is exact.
inline bool in_range(const double* x, int n) {
  for (int i = 0; i < n; ++i) {
    const double m = std::abs(x[i]);
    if (m != 0 && !(m >= 0x1p-150 && m <= 0x1p150)) return false;
  }
  return true;
}

// The exact sign of det[u; v; w] for rows of doubles in range (in_range), from its expansion.
inline Sign det3_sign(const double u[3], const double v[3], const double w[3]) {
  double m[3][4], t[3][8], uv[16], all[24];
  const int m0 = minor2(v[1], w[2], v[2], w[1], m[0]);
  const int m1 = minor2(v[2], w[0], v[0], w[2], m[1]);
  const int m2 = minor2(v[0], w[1], v[1], w[0], m[2]);
  const int t0 = scale(m0, m[0], u[0], t[0]);
  const int t1 = scale(m1, m[1], u[1], t[1]);
  const int t2 = scale(m2, m[2], u[2], t[2]);
  const int n01 = sum(t0, t[0], t1, t[1], uv);
  const int n = sum(n01, uv, t2, t[2], all);
  const double top = all[n - 1];  // the largest component carries the sign
  return top > 0 ? Sign::Positive : top < 0 ? Sign::Negative : Sign::Zero;
}

// orient3d(a, b, c, d) = sign det[b − a; c − a; d − a] exactly, when the nine differences are
// exact in double and in range; nullopt otherwise (the caller's Mpzf decides). With
// `d_is_point` false, d is a direction and the last row is d itself (orient_direction).
inline std::optional<Sign> orient3d(const double* a, const double* b, const double* c, const double* d,
                                    bool d_is_point) {
  double rows[9];
  for (int i = 0; i < 3; ++i) {
    double err;
    two_sum(b[i], -a[i], rows[i], err);
    if (err != 0) return std::nullopt;
    two_sum(c[i], -a[i], rows[3 + i], err);
    if (err != 0) return std::nullopt;
    if (d_is_point) {
      two_sum(d[i], -a[i], rows[6 + i], err);
      if (err != 0) return std::nullopt;
    } else {
      rows[6 + i] = d[i];
    }
  }
  if (!in_range(rows, 9)) return std::nullopt;
  return det3_sign(rows, rows + 3, rows + 6);
}

}  // namespace hedra::internal::expansion
