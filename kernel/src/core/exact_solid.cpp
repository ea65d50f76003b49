#include "core/exact_solid.h"

#include <gmpxx.h>

#include <bit>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <algorithm>
#include <optional>
#include <utility>

#include "core/normal_index.h"
#include "hedra/core/error.h"

#include "hedra/core/predicates.h"
#include "hedra/core/tolerance.h"

namespace hedra::internal {

namespace {

using FT = ExactKernel::FT;
using P3 = ExactKernel::Point_3;

// p · m in the row-vector convention, exactly: x'_j = x·m(0, j) + y·m(1, j) + z·m(2, j) + m(3, j).
// Terms with a zero factor are left out and unit factors not multiplied: each operation is a
// node of the lazy number, evaluated (and synchronised) on its own when a test needs the exact
// value, and a translation's image is then one sum per coordinate instead of six operations.
P3 image(const P3& p, const Mat4& m) {
  std::array<FT, 3> q;
  const FT in[3] = {p.x(), p.y(), p.z()};
  for (int j = 0; j < 3; ++j) {
    std::optional<FT> sum;
    for (int i = 0; i < 4; ++i) {
      const double f = m(i, j);
      if (f == 0) continue;
      FT term = i == 3 ? FT(f) : (f == 1 ? in[i] : in[i] * f);
      sum = sum ? *sum + term : term;
    }
    q[j] = sum ? *sum : FT(0);
  }
  return P3(q[0], q[1], q[2]);
}

// Reverses every triangle (the image of a reflection keeps its faces outward).
void reverse(std::vector<ExactSolid::Tri>& triangles) {
  for (ExactSolid::Tri& tri : triangles) std::swap(tri.v[1], tri.v[2]);
}

}  // namespace

const ExactSolid& materialized(const ExactSolid& solid) {
  if (!solid.pending) return solid;
  std::call_once(solid.once, [&solid] {
    const ExactSolid::Pending& from = *solid.pending;
    auto out = std::make_shared<ExactSolid>();
    out->rounded = solid.rounded;
    out->points.reserve(from.corners->size());
    for (const Vec3& p : *from.corners) {
      P3 q(p.x(), p.y(), p.z());
      for (const Mat4& m : from.maps) q = image(q, m);
      out->points.push_back(std::move(q));
    }
    out->triangles = *from.triangles;
    if (from.reflected) reverse(out->triangles);
    solid.made = std::move(out);
  });
  return *solid.made;
}

std::shared_ptr<const ExactSolid> transformed(const ExactSolid& solid, const Transform& t) {
  auto out = std::make_shared<ExactSolid>();
  out->rounded = solid.rounded;
  if (solid.pending) {
    out->pending = solid.pending;
    out->pending->maps.push_back(t.matrix());
    if (t.linear_determinant() < 0) out->pending->reflected = !out->pending->reflected;
    return out;
  }
  out->points.reserve(solid.points.size());
  for (const P3& p : solid.points) out->points.push_back(image(p, t.matrix()));
  out->triangles = solid.triangles;
  out->body_vertex = solid.body_vertex;
  if (t.linear_determinant() < 0) reverse(out->triangles);
  return out;
}

namespace {

// The body's triangles, each with the face it lies in.
std::vector<ExactSolid::Tri> triangles_of(const Body& body) {
  std::vector<ExactSolid::Tri> out;
  out.reserve(body.triangles().size());
  for (const Triangle& t : body.triangles()) out.push_back({t.v, t.face});
  return out;
}

// The pending exact image of `corners` (with `body`'s triangles, exactly planar faces) under
// `map`.
std::shared_ptr<ExactSolid> pending_image(std::vector<Vec3> corners, const Body& body, const Transform& map) {
  auto out = std::make_shared<ExactSolid>();
  out->rounded = false;  // a moved double body, as any other (ExactSolid::rounded)
  out->pending = ExactSolid::Pending{std::make_shared<const std::vector<Vec3>>(std::move(corners)),
                                     std::make_shared<const std::vector<ExactSolid::Tri>>(triangles_of(body)),
                                     {map.matrix()}, map.linear_determinant() < 0};
  return out;
}

}  // namespace

std::shared_ptr<const ExactSolid> moved_exactly(const Body& body, const Transform& t) {
  const auto& v = body.vertices();
  for (int f = 0; f < body.face_count(); ++f) {
    const auto& loops = body.faces()[static_cast<size_t>(f)].loops;
    if (loops.size() == 1 && loops[0].size() == 3) continue;  // a triangle is planar
    const auto& s = body.support(f);
    for (const auto& loop : loops)
      for (int w : loop)
        if (orient3d(v[s[0]], v[s[1]], v[s[2]], v[w]) != Sign::Zero) return nullptr;
  }
  return pending_image(body.vertices(), body, t);
}

namespace {

// How far plane_solid() may move a vertex, in rounding guards: a vertex lies within one guard
// of each of its faces' planes, and where its planes meet at angles down to about 4° their
// intersection is within 16 guards of it.
constexpr double kPlaneSolidReach = 16;

}  // namespace

std::shared_ptr<const ExactSolid> plane_solid(const Body& body) {
  if (body.faces_off_plane().empty() || body.two_sided()) return nullptr;
  using PL = ExactKernel::Plane_3;
  const auto& v = body.vertices();
  const double guard = kRoundingPlanarity * body.scale();
  const auto exact = [](const Vec3& p) { return P3(p.x(), p.y(), p.z()); };
  // The planes: per plane its first face's outward double plane and exact support plane.
  struct Group {
    int creator;
    Plane approx;
    PL plane;
  };
  std::vector<Group> groups;
  NormalIndex normals;  // of the groups' planes
  std::vector<int> group(static_cast<size_t>(body.face_count()));
  for (int f = 0; f < body.face_count(); ++f) {
    const Plane outward = body.plane(f).flipped();
    const Vec3 n = outward.normal();
    const auto& s = body.support(f);
    const Vec3 &a = v[static_cast<size_t>(s[0])], &b = v[static_cast<size_t>(s[1])], &c = v[static_cast<size_t>(s[2])];
    // A plane with the support triangle within the guard turns from its normal by at most
    // about 2·guard over the triangle's smallest height (as decompose's grouping).
    const double longest = std::max({(b - a).norm(), (c - b).norm(), (a - c).norm()});
    const double eps = 8 * guard / ((b - a).cross(c - a).norm() / longest) + 1e-9;
    int found = -1;
    for (int g : normals.near(n, eps, false)) {
      const Plane& p = groups[static_cast<size_t>(g)].approx;
      if (p.normal().dot(n) < 0.5) continue;
      bool same = true;
      for (const auto& loop : body.faces()[static_cast<size_t>(f)].loops)
        for (int w : loop) same = same && std::abs(p.value(v[static_cast<size_t>(w)])) <= guard;
      if (same) {
        found = g;
        break;
      }
    }
    if (found < 0) {
      found = static_cast<int>(groups.size());
      groups.push_back({f, outward, PL(exact(a), exact(b), exact(c))});
      normals.add(n);
    }
    group[static_cast<size_t>(f)] = found;
  }
  // Per vertex, its planes, and whether it lies on all of them exactly.
  std::vector<std::vector<int>> on(v.size());
  std::vector<char> loose(v.size(), 0);
  for (int f = 0; f < body.face_count(); ++f) {
    const int g = group[static_cast<size_t>(f)];
    const auto& s = body.support(groups[static_cast<size_t>(g)].creator);
    for (const auto& loop : body.faces()[static_cast<size_t>(f)].loops)
      for (int w : loop) {
        auto& list = on[static_cast<size_t>(w)];
        const auto at = std::lower_bound(list.begin(), list.end(), g);
        if (at != list.end() && *at == g) continue;
        list.insert(at, g);
        if (orient3d(v[static_cast<size_t>(s[0])], v[static_cast<size_t>(s[1])], v[static_cast<size_t>(s[2])],
                     v[static_cast<size_t>(w)]) != Sign::Zero)
          loose[static_cast<size_t>(w)] = 1;
      }
  }
  auto solid = std::make_shared<ExactSolid>();
  solid->points.reserve(v.size());
  const double reach = kPlaneSolidReach * guard;
  const auto normal = [&](int g) { return groups[static_cast<size_t>(g)].approx.normal(); };
  const auto plane = [&](int g) -> const PL& { return groups[static_cast<size_t>(g)].plane; };
  for (size_t i = 0; i < v.size(); ++i) {
    const P3 p = exact(v[i]);
    if (!loose[i]) {
      solid->points.push_back(p);
      continue;
    }
    const std::vector<int>& planes = on[i];
    P3 q;
    if (planes.size() == 1) {
      q = plane(planes[0]).projection(p);
    } else {
      // The best-conditioned pair, then third (a plane through p across their line for two).
      const int a = planes[0];
      int b = -1;
      double best = -1;
      for (int c : planes)
        if (c != a && normal(a).cross(normal(c)).norm() > best) best = normal(a).cross(normal(c)).norm(), b = c;
      const auto along = CGAL::cross_product(plane(a).orthogonal_vector(), plane(b).orthogonal_vector());
      if (CGAL::is_zero(along.squared_length())) return nullptr;  // one plane twice: no line
      PL third(p, along);
      if (planes.size() > 2) {
        const Vec3 ab = normal(a).cross(normal(b));
        int c3 = -1;
        best = -1;
        for (int c : planes)
          if (c != a && c != b && std::abs(ab.dot(normal(c))) > best) best = std::abs(ab.dot(normal(c))), c3 = c;
        third = plane(c3);
      }
      const auto meet = CGAL::intersection(plane(a), plane(b), third);
      if (!meet) return nullptr;
      const P3* point = boost::get<P3>(&*meet);
      if (!point) return nullptr;
      q = *point;
      for (int c : planes)
        if (plane(c).oriented_side(q) != CGAL::ON_ORIENTED_BOUNDARY) return nullptr;
    }
    const Vec3 moved(CGAL::to_double(q.x()), CGAL::to_double(q.y()), CGAL::to_double(q.z()));
    if (!((moved - v[i]).norm() <= reach)) return nullptr;
    solid->points.push_back(q);
  }
  // Every triangle turning as its plane, outward.
  solid->triangles = triangles_of(body);
  for (const ExactSolid::Tri& t : solid->triangles) {
    const P3 &a = solid->points[static_cast<size_t>(t.v[0])], &b = solid->points[static_cast<size_t>(t.v[1])],
             &c = solid->points[static_cast<size_t>(t.v[2])];
    if (CGAL::sign(CGAL::cross_product(b - a, c - a) * plane(group[static_cast<size_t>(t.face)]).orthogonal_vector()) !=
        CGAL::POSITIVE)
      return nullptr;
  }
  solid->rounded = true;  // its corners off the doubles are not the body's vertices
  return solid;
}

void attach_translated_image(Body& body, std::vector<Vec3> corners, const Vec3& offset) {
  attach_exact_solid(body, pending_image(std::move(corners), body, Transform::translation(offset)));
}

void attach_frustum_solid(Body& body, const Vec3& apex, double z0, double z1) {
  using FT = ExactKernel::FT;
  const auto& v = body.vertices();
  const size_t k = v.size() / 2;
  const FT s = (FT(z1) - FT(z0)) / (FT(apex.z()) - FT(z0));
  auto solid = std::make_shared<ExactSolid>();
  solid->rounded = false;
  solid->points.reserve(v.size());
  for (size_t i = 0; i < k; ++i) solid->points.emplace_back(v[i].x(), v[i].y(), v[i].z());
  for (size_t i = 0; i < k; ++i) {
    const FT x = FT(v[i].x()) + s * (FT(apex.x()) - FT(v[i].x()));
    const FT y = FT(v[i].y()) + s * (FT(apex.y()) - FT(v[i].y()));
    const auto &ex = CGAL::exact(x), &ey = CGAL::exact(y);
    const double dx = CGAL::to_double(ex), dy = CGAL::to_double(ey);
    if (ex == dx && ey == dy) {
      solid->points.emplace_back(dx, dy, z1);  // a double exactly (see boolean.cpp)
    } else {
      solid->points.emplace_back(x, y, FT(z1));
      solid->rounded = true;
    }
  }
  if (!solid->rounded) return;
  solid->triangles = triangles_of(body);
  attach_exact_solid(body, std::move(solid));
}

namespace {

static_assert(std::endian::native == std::endian::little, "exact solid bytes are written little-endian");

struct Writer {
  std::string out;
  template <class T>
  void put(const T& x) {
    out.append(reinterpret_cast<const char*>(&x), sizeof x);
  }
  void text(const std::string& s) {
    put(static_cast<std::uint32_t>(s.size()));
    out += s;
  }
  void triangles(const std::vector<ExactSolid::Tri>& t) {
    put(static_cast<std::uint64_t>(t.size()));
    for (const ExactSolid::Tri& x : t) {
      for (int v : x.v) put(static_cast<std::int32_t>(v));
      put(static_cast<std::int32_t>(x.face));
    }
  }
};

struct Reader {
  std::string_view in;
  size_t at = 0;
  [[noreturn]] void fail(const std::string& what) const {
    throw InvalidInput("exact solid bytes: " + what + " at byte " + std::to_string(at));
  }
  template <class T>
  T get() {
    if (in.size() - at < sizeof(T)) fail("truncated");
    T x;
    std::memcpy(&x, in.data() + at, sizeof x);
    at += sizeof x;
    return x;
  }
  // A count of items of `size` bytes each that must fit in what is left.
  size_t count(size_t size) {
    const auto n = get<std::uint64_t>();
    if (n > (in.size() - at) / size) fail("a count beyond the bytes left");
    return static_cast<size_t>(n);
  }
  std::string text() {
    const auto n = get<std::uint32_t>();
    if (n > in.size() - at) fail("truncated");
    std::string s(in.substr(at, n));
    at += n;
    return s;
  }
  std::vector<ExactSolid::Tri> triangles(size_t points, int faces) {
    std::vector<ExactSolid::Tri> t(count(16));
    for (ExactSolid::Tri& x : t) {
      for (int& v : x.v) {
        v = get<std::int32_t>();
        if (v < 0 || static_cast<size_t>(v) >= points) fail("a corner index out of range");
      }
      x.face = get<std::int32_t>();
      if (x.face < 0 || x.face >= faces) fail("a face index out of range");
    }
    return t;
  }
};

}  // namespace

std::string exact_solid_bytes(const ExactSolid& solid) {
  Writer w;
  w.out = "HXS1";
  w.put(static_cast<std::uint8_t>(solid.rounded));
  w.put(static_cast<std::uint8_t>(solid.pending.has_value()));
  if (solid.pending) {
    const ExactSolid::Pending& p = *solid.pending;
    w.put(static_cast<std::uint64_t>(p.corners->size()));
    for (const Vec3& c : *p.corners) w.put(c);
    w.triangles(*p.triangles);
    w.put(static_cast<std::uint64_t>(p.maps.size()));
    for (const Mat4& m : p.maps)
      for (int r = 0; r < 4; ++r)
        for (int c = 0; c < 4; ++c) w.put(m(r, c));
    w.put(static_cast<std::uint8_t>(p.reflected));
    return std::move(w.out);
  }
  w.put(static_cast<std::uint64_t>(solid.points.size()));
  for (const P3& q : solid.points) {
    const auto& e = CGAL::exact(q);
    for (const auto& x : {e.x(), e.y(), e.z()}) w.text(x.get_str(16));
  }
  w.triangles(solid.triangles);
  w.put(static_cast<std::uint64_t>(solid.body_vertex.size()));
  for (int v : solid.body_vertex) w.put(static_cast<std::int32_t>(v));
  return std::move(w.out);
}

std::shared_ptr<const ExactSolid> exact_solid_from_bytes(std::string_view bytes, const Body& body) {
  Reader r{bytes};
  if (bytes.substr(0, 4) != "HXS1") r.fail("not hedra's exact solid format 1");
  r.at = 4;
  auto out = std::make_shared<ExactSolid>();
  out->rounded = r.get<std::uint8_t>() != 0;
  const bool pending = r.get<std::uint8_t>() != 0;
  const size_t vertices = static_cast<size_t>(body.vertex_count());
  if (pending) {
    ExactSolid::Pending p;
    auto corners = std::make_shared<std::vector<Vec3>>(r.count(24));
    if (corners->size() != vertices) r.fail("a pending image of another body (" + std::to_string(corners->size()) + " corners)");
    for (Vec3& c : *corners) {
      const double x = r.get<double>(), y = r.get<double>(), z = r.get<double>();  // in this order
      c = Vec3(x, y, z);
      if (!c.allFinite()) r.fail("a corner not finite");
    }
    p.triangles = std::make_shared<const std::vector<ExactSolid::Tri>>(r.triangles(corners->size(), body.face_count()));
    p.corners = std::move(corners);
    p.maps.resize(r.count(128));
    for (Mat4& m : p.maps)
      for (int i = 0; i < 4; ++i)
        for (int j = 0; j < 4; ++j) {
          m(i, j) = r.get<double>();
          if (!std::isfinite(m(i, j))) r.fail("a map not finite");
        }
    p.reflected = r.get<std::uint8_t>() != 0;
    out->pending = std::move(p);
  } else {
    out->points.reserve(r.count(12));
    const size_t n = out->points.capacity();
    for (size_t i = 0; i < n; ++i) {
      mpq_class c[3];
      for (mpq_class& x : c) {
        const std::string t = r.text();
        if (t.empty() || x.set_str(t, 16) != 0 || sgn(x.get_den()) <= 0) r.fail("a corner that is not a rational");
        x.canonicalize();
      }
      out->points.emplace_back(ExactKernel::FT(c[0]), ExactKernel::FT(c[1]), ExactKernel::FT(c[2]));
    }
    out->triangles = r.triangles(out->points.size(), body.face_count());
    out->body_vertex.resize(r.count(4));
    for (int& v : out->body_vertex) {
      v = r.get<std::int32_t>();
      if (v < -1 || v >= body.vertex_count()) r.fail("a body vertex out of range");
    }
    if (!out->body_vertex.empty() && out->body_vertex.size() != out->points.size()) r.fail("a vertex map of another size");
    if (out->body_vertex.empty() && out->points.size() != vertices) r.fail("a solid of another body");
  }
  if (r.at != bytes.size()) r.fail("bytes after the end");
  return out;
}

ExactKernel::FT::ET six_volume(const Body& body) {
  using ET = ExactKernel::FT::ET;
  ET sum = 0;
  // Summed in the exact number type: a lazy sum of many terms recurses once per term.
  using E3 = std::array<ET, 3>;
  const auto add = [&sum](const E3& a, const E3& b, const E3& c) {
    sum += a[0] * (b[1] * c[2] - b[2] * c[1]) - a[1] * (b[0] * c[2] - b[2] * c[0]) +
           a[2] * (b[0] * c[1] - b[1] * c[0]);
  };
  if (body.exact_solid()) {
    const ExactSolid& solid = materialized(*body.exact_solid());
    std::vector<E3> e(solid.points.size());
    for (size_t i = 0; i < e.size(); ++i) {
      const auto& p = CGAL::exact(solid.points[i]);
      e[i] = {p.x(), p.y(), p.z()};
    }
    for (const ExactSolid::Tri& t : solid.triangles) add(e[t.v[0]], e[t.v[1]], e[t.v[2]]);
    return sum;
  }
  const auto& v = body.vertices();
  for (const Triangle& t : body.triangles()) {
    const Vec3 &p = v[t.v[0]], &q = v[t.v[1]], &r = v[t.v[2]];
    add(E3{p.x(), p.y(), p.z()}, E3{q.x(), q.y(), q.z()}, E3{r.x(), r.y(), r.z()});
  }
  return sum;
}

}  // namespace hedra::internal
