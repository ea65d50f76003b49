#include "hedra/baselines/hidden_lines_brute_force.h"

#include <vector>

#include "hedra/core/predicates.h"
#include "visibility/roberts_exact.h"

namespace hedra {

std::optional<HiddenPart> hidden_part_brute_force(const Body& convex_body, const Viewpoint& view,
                                                  const Vec3& p1, const Vec3& p2) {
  std::vector<ExactPlane> planes;
  for (int f = 0; f < convex_body.face_count(); ++f) planes.push_back(exact_face_plane(convex_body, f));
  const auto part = detail::hidden_by_planes_brute_force(planes, view, p1, p2);
  if (!part) return std::nullopt;
  return HiddenPart{part->first, part->second};
}

}  // namespace hedra
