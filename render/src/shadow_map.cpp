#include "hedra/render/shadow_map.h"

#include <algorithm>
#include <cmath>
#include <numbers>

#include "hedra/core/parallel.h"
#include "hedra/visibility/occlusion.h"
#include "detail/triangle_raster.h"

namespace hedra {
namespace {

// A unit vector orthogonal to f.
Vec3 orthogonal(const Vec3& f) {
  const Vec3 a = std::abs(f.x()) < 0.6 ? Vec3::UnitX() : (std::abs(f.y()) < 0.6 ? Vec3::UnitY() : Vec3::UnitZ());
  return f.cross(a).normalized();
}

constexpr int kMapTile = 64;

}  // namespace

ShadowMap::ShadowMap(const SceneGeometry& geometry, const Light& light, int resolution, double bias)
    : position_(light.position), bias_(bias) {
  const Eigen::AlignedBox3d box = geometry.bbox();
  const double diagonal = box.isEmpty() ? 1.0 : std::max(box.diagonal().norm(), 1e-300);
  const int n = resolution;
  if (light.at_infinity()) {
    // One parallel view along the light, fitted to the scene's box with a one-texel margin.
    const Vec3 f = light.direction.normalized();
    const Vec3 right = orthogonal(f);
    const Vec3 down = f.cross(right);
    double u0 = INFINITY, u1 = -INFINITY, v0 = INFINITY, v1 = -INFINITY, w0 = INFINITY, w1 = -INFINITY;
    for (int i = 0; i < 8; ++i) {
      const Vec3 c = box.corner(static_cast<Eigen::AlignedBox3d::CornerType>(i));
      u0 = std::min(u0, c.dot(right)), u1 = std::max(u1, c.dot(right));
      v0 = std::min(v0, c.dot(down)), v1 = std::max(v1, c.dot(down));
      w0 = std::min(w0, c.dot(f)), w1 = std::max(w1, c.dot(f));
    }
    const double du = std::max(u1 - u0, 1e-9 * diagonal), dv = std::max(v1 - v0, 1e-9 * diagonal);
    const Vec3 origin = 0.5 * (u0 + u1) * right + 0.5 * (v0 + v1) * down + 0.5 * (w0 + w1) * f;
    views_.push_back({RasterView::parallel(origin, f, right, down, (n - 2) / du, (n - 2) / dv,
                                           0.5 * n, 0.5 * n, n, n), {}});
  } else {
    double far = 0;
    for (int i = 0; i < 8; ++i)
      far = std::max(far, (box.corner(static_cast<Eigen::AlignedBox3d::CornerType>(i)) - light.position).norm());
    const double near = 1e-6 * std::max(far, diagonal);
    if (light.type == Light::Type::Spot) {
      const Vec3 f = light.direction.normalized();
      const Vec3 right = orthogonal(f);
      const double scale = 0.5 * n / std::tan(light.cone_deg * std::numbers::pi / 180);
      views_.push_back({RasterView::perspective(light.position, f, right, f.cross(right), scale,
                                                scale, 0.5 * n, 0.5 * n, n, n, near), {}});
    } else {
      // A cube of six 90° views: +x, −x, +y, −y, +z, −z.
      cube_ = true;
      for (int axis = 0; axis < 6; ++axis) {
        Vec3 f = Vec3::Zero();
        f[axis / 2] = axis % 2 ? -1 : 1;
        const Vec3 right = orthogonal(f);
        views_.push_back({RasterView::perspective(light.position, f, right, f.cross(right), 0.5 * n,
                                                  0.5 * n, 0.5 * n, 0.5 * n, n, n, near), {}});
      }
    }
  }
  // Pass 1: every face except those edge-on to the light.
  const Viewpoint from = Viewpoint::of(light);
  std::vector<uint8_t> draw(geometry.faces.size());
  for (size_t f = 0; f < geometry.faces.size(); ++f) {
    const SceneGeometry::FaceRef& face = geometry.faces[f];
    draw[f] = facing(geometry.bodies[face.body].body->body, face.face, from) != Facing::EdgeOn;
  }
  for (View& v : views_) render_view(geometry, draw, v);
}

void ShadowMap::render_view(const SceneGeometry& geometry, const std::vector<uint8_t>& draw, View& v) {
  const detail::TriangleRaster raster = detail::prepare_triangles(geometry, v.view, draw, 1, kMapTile);
  const int width = v.view.width();
  v.depth.assign(static_cast<size_t>(width) * v.view.height(), INFINITY);
  const bool perspective = v.view.is_perspective();
  parallel_for(static_cast<size_t>(raster.bins.count()), 0, [&](size_t index) {
    const int tile = static_cast<int>(index);
    const detail::TileRect rect = detail::tile_rect(raster, tile);
    std::vector<double> key(static_cast<size_t>(rect.size()));
    std::vector<int> polygon(key.size());
    std::vector<double> scratch;
    detail::depth_tile(raster, rect, key.data(), polygon.data(), scratch);
    for (int r = rect.r0; r < rect.r1; ++r)
      for (int c = rect.c0; c < rect.c1; ++c) {
        const double k = key[static_cast<size_t>((r - rect.r0) * rect.columns() + (c - rect.c0))];
        if (k == INFINITY) continue;
        v.depth[static_cast<size_t>(r) * width + c] = static_cast<float>(perspective ? -1 / k : k);
      }
  });
}

int ShadowMap::select(const Vec3& p) const {
  if (!cube_) return 0;
  const Vec3 d = p - position_;
  int axis = 0;
  if (std::abs(d.y()) > std::abs(d[axis])) axis = 1;
  if (std::abs(d.z()) > std::abs(d[axis])) axis = 2;
  return 2 * axis + (d[axis] < 0 ? 1 : 0);
}

bool ShadowMap::shadowed(const Vec3& p) const {
  const View& v = views_[static_cast<size_t>(select(p))];
  const RasterView& view = v.view;
  const double w = view.depth(p);
  if (view.is_perspective() && !(w > view.near())) return false;  // behind the light
  const Eigen::Vector2d s = view.project(p);
  int x = static_cast<int>(std::floor(s.x())), y = static_cast<int>(std::floor(s.y()));
  const int n = view.width();
  if (cube_) {
    // Points on the 45° planes between two faces may land just outside either.
    x = std::clamp(x, 0, n - 1);
    y = std::clamp(y, 0, n - 1);
  } else if (!(s.x() >= 0 && s.y() >= 0) || x >= n || y >= view.height()) {
    return false;  // outside the light's view (a spot light's cone): lit as far as the map knows
  }
  const double stored = v.depth[static_cast<size_t>(y) * n + x];
  // One texel's size in world units at the point's depth.
  const double texel = view.is_perspective() ? w / view.scale_x()
                                             : std::max(1 / view.scale_x(), 1 / view.scale_y());
  return w - bias_ * texel > stored;
}

}  // namespace hedra
