// The shadow z-buffer (docs/algorithms.md §7.5, the course's two-pass algorithm): pass 1 renders
// the depth of the scene as the light sees it; pass 2 (the renderer) takes each visible point into
// the light's view and compares its depth with the stored one. Resolution and bias are the accuracy
// knobs; their failure modes are the method's own: acne (self-shadowing stripes when the bias is
// too small for the surface's slope), light leaking and detached shadows when it is too large,
// blocky edges (aliasing) at low resolution.
#pragma once

#include <vector>

#include "hedra/scene/light.h"
#include "hedra/render/raster_view.h"
#include "hedra/render/scene_geometry.h"

namespace hedra {

class ShadowMap {
 public:
  /// Pass 1 for one light. Directional light and sun: one parallel view along the light
  /// fitted to the box of the scene, resolution² texels. Spot light: one perspective view
  /// along its axis whose field of view is its cone. Point light: a cube of six 90° views.
  /// Every face of the scene is drawn except those edge-on to the light.
  /// `bias` is in texels. Cost O(triangles + views · resolution²), parallel over tiles.
  ShadowMap(const SceneGeometry& geometry, const Light& light, int resolution, double bias);

  /// Pass 2: whether world point p lies behind the depth stored for its texel by more than
  /// the bias. Points outside every view of the light are lit. Cost O(1).
  bool shadowed(const Vec3& p) const;

  int view_count() const { return static_cast<int>(views_.size()); }
  const RasterView& view(int i) const { return views_[static_cast<size_t>(i)].view; }
  /// Stored depth of texel (x, y) of view i (+∞ where nothing was drawn).
  float depth(int i, int x, int y) const {
    const View& v = views_[static_cast<size_t>(i)];
    return v.depth[static_cast<size_t>(y) * v.view.width() + x];
  }

 private:
  struct View {
    RasterView view;
    std::vector<float> depth;  // parallel: the depth key; perspective: the depth w
  };
  void render_view(const SceneGeometry& geometry, const std::vector<uint8_t>& draw, View& v);
  int select(const Vec3& p) const;

  bool cube_ = false;
  Vec3 position_ = Vec3::Zero();
  double bias_ = 0;
  std::vector<View> views_;
};

}  // namespace hedra
