// The hidden-line drawing as SVG (hedra/visibility/roberts.h): visible lines solid, hidden lines
// dashed on request, junction lines in their own class; the picture fitted to the image with a
// margin.
#pragma once

#include <string>

#include <Eigen/Geometry>

#include "hedra/scene/camera.h"
#include "hedra/visibility/roberts.h"

namespace hedra {

struct SvgStyle {
  int width = 800, height = 600;   // pixels
  /// Stroke widths in pixels of the image, whatever the scene's size (the drawing is placed in
  /// pixel coordinates and the strokes do not scale with the viewBox either).
  double visible_px = 1.5;
  double junction_px = 1.5;
  double hidden_px = 1.0;
  double outline_px = 1.5;         // outlines of smooth parts (HlrResult::has_smooth())
  double smooth_px = 0.75;         // smooth edges (HlrResult::smooth_listed)
  bool hidden = false;             // draw HlrResult::hidden, dashed
  double margin = kViewMargin;     // free fraction of the image on each side
  Vec3 background = Vec3(1, 1, 1);
  std::string title;               // <title>, when not empty
};

/// Picture-plane coordinates → pixels: uniform scale, centred, y down, the box fitted inside
/// the image less the margin on every side.
struct PictureFit {
  double scale = 1;
  Vec2 offset = Vec2::Zero();
  int height = 0;
  Vec2 to_pixels(const Vec2& p) const { return {offset.x() + scale * p.x(), height - (offset.y() + scale * p.y())}; }
};
PictureFit fit_picture(const Eigen::AlignedBox2d& box, int width, int height, double margin);

/// The SVG document: a background rectangle, then groups `hidden` (dashed, when asked),
/// `visible` and `junction`, each one path of straight segments with round caps and joins, so
/// lines meeting at a T-junction close. The picture is fitted by result.picture_box (the whole
/// scene), so drawings of one scene with and without hidden lines coincide.
std::string hidden_lines_svg(const HlrResult& result, const SvgStyle& style);

}  // namespace hedra
