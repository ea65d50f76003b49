// Level of detail: how finely a curved primitive must be modeled for a given picture.
#pragma once

#include <string>

#include "hedra/scene/camera.h"

namespace hedra {

/// Chordal tolerance (world units) that keeps a curved body's chordal error under
/// `pixel_tolerance` pixels on the picture of `camera`: pixel_tolerance times the size of a
/// pixel at the body's point nearest to the eye (bounding sphere `centre`, `radius`, already in
/// world coordinates). `view_height` is the visible height of a parallel view in world units
/// (ignored in perspective). `note` receives a one-line explanation for reports.
/// \throw InvalidInput when pixel_tolerance is not positive or the body reaches the eye.
double chordal_tolerance_for_pixels(double pixel_tolerance, const Vec3& centre, double radius,
                                    const Camera& camera, double view_height, std::string* note);

/// Visible height (world units) of a parallel view of the box, fitted with kViewMargin.
double parallel_view_height(const Camera& camera, const Eigen::AlignedBox3d& box);

}  // namespace hedra
