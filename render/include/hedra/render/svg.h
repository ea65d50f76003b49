// The hidden-line drawing as SVG (hedra/visibility/roberts.h): visible lines solid, hidden lines
// dashed on request, junction lines in their own class; framed by the renderer's view of the
// scene (so the drawing lies exactly over `hedra render`'s image) or fitted to the image with a
// margin.
#pragma once

#include <string>

#include <Eigen/Geometry>

#include <optional>

#include "hedra/render/raster_view.h"
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
  /// The framing: world points map to pixels through this view (scene_view() of raster.h: the
  /// camera, field of view and image size exactly as render() uses them). Empty: the picture
  /// box is fitted to the image with `margin` (`--fit`).
  std::optional<RasterView> view;
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

/// Where a point of the drawing lands in the image: through style.view when set (world point,
/// the renderer's projection to the last bit), else through the fit of result.picture_box
/// (picture-plane point). Value type; cost O(1) per point.
class SvgFrame {
 public:
  SvgFrame(const SvgStyle& style, const HlrResult& result)
      : view_(style.view),
        fit_(fit_picture(result.picture_box, style.width, style.height, style.margin)) {}
  /// Pixels of the point with world coordinates `world` and picture-plane ones `picture`.
  Vec2 pixels(const Vec3& world, const Vec2& picture) const {
    return view_ ? Vec2(view_->project(world)) : fit_.to_pixels(picture);
  }

 private:
  std::optional<RasterView> view_;
  PictureFit fit_;
};

/// The SVG document: a background rectangle, then groups `hidden` (dashed, when asked),
/// `visible` and `junction`, each one path of straight segments with round caps and joins, so
/// lines meeting at a T-junction close. Framed by style.view, or else fitted by
/// result.picture_box (the whole scene); either way drawings of one scene with and without
/// hidden lines coincide. Cost O(segments).
std::string hidden_lines_svg(const HlrResult& result, const SvgStyle& style);

}  // namespace hedra
