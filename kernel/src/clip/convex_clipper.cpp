#include "hedra/clip/convex_clipper.h"

#include <string>

#include "hedra/mesh/convexity.h"
#include "hedra/core/error.h"

namespace hedra {

ConvexClipper::ConvexClipper(const Body& body) : scale_(body.scale()) {
  const ConvexityReport report = convexity(body);
  if (!report.convex) {
    std::string faces;
    for (size_t i = 0; i < report.nonconvex_faces.size() && i < 8; ++i)
      faces += (i ? ", " : "") + std::to_string(report.nonconvex_faces[i]);
    if (report.nonconvex_faces.size() > 8) faces += ", ...";
    const bool one = report.nonconvex_faces.size() == 1;
    throw InvalidInput("the clipper is not convex: vertices lie outside the plane" +
                       std::string(one ? " of face " : "s of faces ") + faces);
  }
  planes_.reserve(static_cast<size_t>(body.face_count()));
  const auto& v = body.vertices();
  for (int f = 0; f < body.face_count(); ++f) {
    const auto& s = body.support(f);
    // face_side(f, p) = −orient3d(v[s0], v[s1], v[s2], p): ExactPlane::through's convention.
    planes_.push_back(ExactPlane::through(v[s[0]], v[s[1]], v[s[2]]));
  }
}

ConvexClipper ConvexClipper::from_matrix(const BodyMatrix& matrix) {
  if (matrix.cols() == 0) throw InvalidInput("a clipper needs at least one plane");
  ConvexClipper c;
  c.planes_.reserve(static_cast<size_t>(matrix.cols()));
  for (Eigen::Index j = 0; j < matrix.cols(); ++j) {
    try {
      c.planes_.push_back(ExactPlane::from_coefficients(Plane(Vec4(matrix.col(j)))));
    } catch (const InvalidInput& e) {
      throw InvalidInput("body matrix column " + std::to_string(j) + ": " + e.what());
    }
  }
  return c;
}

ConvexClipper ConvexClipper::from_planes(std::vector<ExactPlane> planes) {
  if (planes.empty()) throw InvalidInput("a clipper needs at least one plane");
  ConvexClipper c;
  c.planes_ = std::move(planes);
  return c;
}

bool ConvexClipper::contains(const Vec3& p) const {
  for (const ExactPlane& f : planes_)
    if (side_of_plane(f, p) == Sign::Negative) return false;
  return true;
}

}  // namespace hedra
