#include "hedra/baselines/cyrus_beck_double.h"

#include <algorithm>

namespace hedra {

std::optional<std::pair<double, double>> cyrus_beck_double(const BodyMatrix& matrix, const Vec3& p1,
                                                           const Vec3& p2) {
  // Step 3: D = P2 − P1; step 4: t_low = 0, t_up = 1.
  const Vec3 d = p2 - p1;
  double t_low = 0, t_up = 1;
  for (Eigen::Index i = 0; i < matrix.cols(); ++i) {
    // Step 5, with the face point folded into the plane offset: W·N = N·P1 + d_i.
    const double nx = matrix(0, i), ny = matrix(1, i), nz = matrix(2, i);
    const double wn = ((nx * p1.x() + ny * p1.y()) + nz * p1.z()) + matrix(3, i);
    const double dn = (nx * d.x() + ny * d.y()) + nz * d.z();
    if (dn == 0) {
      if (wn < 0) return std::nullopt;  // a point or parallel, outside
      continue;
    }
    const double t = -wn / dn;
    if (dn > 0) {
      if (t > 1) return std::nullopt;
      t_low = std::max(t, t_low);
    } else {
      if (t < 0) return std::nullopt;
      t_up = std::min(t, t_up);
    }
  }
  // Step 6.
  if (t_low > t_up) return std::nullopt;
  return std::make_pair(t_low, t_up);
}

}  // namespace hedra
