// The shaded raster renderer: a scan-line z-buffer over square tiles (docs/algorithms.md §9),
// lighting and flat, Gouraud or Phong shading (§8), and cast shadows by one of three
// interchangeable methods (§7): exact shadow polygons drawn as surface detail of their faces,
// a shadow z-buffer per light, or shadow rays through a BVH. docs/rendering.md has the
// details, the conventions and the failure modes of each method.
//
// Pipeline. (1) Back faces are culled by the body matrix and the viewer vector (exact,
// hedra/visibility/occlusion.h facing()). (2) Each remaining face's triangles are clipped to the
// view volume in homogeneous raster coordinates — near plane included, so a body that straddles the
// eye plane is cut there — and binned to tiles. (3) Per tile, in parallel: the z-buffer keeps, per
// sample, the nearest triangle (depth is the face plane's exact affine depth key, evaluated
// directly at each sample); exact shadow polygons mark the samples of their own face; every sample
// is shaded at its world point; samples are averaged into pixels. Output depends neither on the
// number of threads nor on the tiling.
#pragma once

#include <array>
#include <cstdint>
#include <string>
#include <vector>

#include "hedra/core/progress.h"
#include "hedra/scene/scene.h"
#include "hedra/render/raster_view.h"

namespace hedra {

enum class Shading { Flat, Gouraud, Phong };

/// Distance attenuation of the light intensities I_l (docs/algorithms.md §8).
struct Attenuation {
  enum class Model { None, Linear, Quadratic };
  Model model = Model::None;
  /// Linear, the course's: I_l/(d + K), d = the point's distance from the eye (perspective)
  /// or its depth beyond the scene's nearest point (parallel view), for every light.
  double k = 1;
  /// Quadratic, the textbook's: I_l/(a + b·d + c·d²), d = the point's distance from a point
  /// or spot light; lights at infinity (directional, sun) are not attenuated.
  double a = 1, b = 0, c = 0;
  /// "none", "linear:K" or "quadratic:A,B,C". \throw InvalidInput naming the text.
  static Attenuation parse(const std::string& text);
};

/// How cast shadows are found.
struct ShadowSettings {
  enum class Method { None, Exact, Map, Rays };
  Method method = Method::None;
  /// Map: the shadow z-buffer is resolution × resolution texels per light (six such faces
  /// of a cube for a point light).
  int map_resolution = 2048;
  /// Map: depth bias in texels (a point is shadowed when it lies more than bias × the size of
  /// one texel behind the depth stored for its texel). 0 shows acne; large values leak light.
  double map_bias = 1.5;
  /// Rays: shadow probes per image sample, spread over the sample's footprint on the
  /// visible face (1: at the sample itself).
  int ray_samples = 1;

  /// "none", "exact", "map[:RES[:BIAS]]" or "rays[:SPP]" (RES 16…16384, BIAS ≥ 0,
  /// SPP 1…256). \throw InvalidInput naming the text.
  static ShadowSettings parse(const std::string& text);
  std::string to_string() const;
};

/// Exact shadow polygons of one light on one face, as surface detail: closed loops in 3D on the
/// face's plane whose even–odd interior is the shadowed part (hedra/visibility/shadows.h gives
/// them; tests may give their own). `body` indexes Scene::bodies().
struct SurfaceShadow {
  int body = 0, face = 0;
  std::vector<std::vector<Vec3>> loops;
};
/// Per light (in the order of Scene::lights), its surface shadows.
using SurfaceShadows = std::vector<std::vector<SurfaceShadow>>;

/// Most pixels of one image (8192²): bounds the image buffers (3 bytes per pixel) whatever
/// the scene file or the options ask for.
constexpr long long kMaxImagePixels = 1LL << 26;
/// Most shadow-map texels of one render, all lights together (a point light has six maps):
/// `map:16384` with one point light would need 1.6 G texels.
constexpr long long kMaxShadowMapTexels = 1LL << 28;

struct RenderOptions {
  /// Image size; 0 takes the scene camera's (the scene file's "image").
  int width = 0, height = 0;
  Shading shading = Shading::Phong;
  /// Exact shadow polygons by default, as `hedra render`.
  ShadowSettings shadows{ShadowSettings::Method::Exact};
  /// Samples per pixel: 1, 4 (2 × 2) or 16 (4 × 4), averaged (supersampling).
  int aa = 1;
  /// Ambient intensity I_a (white).
  double ambient = 1;
  Attenuation attenuation;
  /// Worker threads; 0: all available.
  int threads = 0;
  /// Tile side in pixels (affects speed only, never the picture).
  int tile_size = 32;
  /// Exact method: the shadow polygons to draw. Null: computed with hedra/visibility/shadows.h.
  const SurfaceShadows* exact_polygons = nullptr;
  /// Progress and cancellation (hedra/core/progress.h): the fraction done, on the calling
  /// thread; returning false stops with hedra::Cancelled and no image. The tiles and the exact
  /// shadow polygons report; shadow maps and the ray BVH are built without reports.
  ProgressCallback progress;
};

/// An 8-bit RGB image, rows top to bottom.
struct Image {
  int width = 0, height = 0;
  std::vector<uint8_t> rgb;
  std::array<uint8_t, 3> pixel(int x, int y) const {
    const size_t i = 3 * (static_cast<size_t>(y) * width + x);
    return {rgb[i], rgb[i + 1], rgb[i + 2]};
  }
};

/// What the camera pass saw at each sample, for tests and the benchmark's error measures.
/// Samples form a (width·g) × (height·g) grid, g² = aa, sample (c, r) at raster point
/// ((c + ½)/g, (r + ½)/g).
struct SampleRecord {
  int columns = 0, rows = 0, lights = 0;
  RasterView view;
  /// Index into Scene::bodies() and face number; −1 for the background.
  std::vector<int> body, face;
  /// Per sample and light ([sample · lights + light]): the fraction of the light blocked,
  /// 0 (lit) … 1 (shadowed); faces turned away from the light count as shadowed (self
  /// shadow); 0 everywhere with shadows off.
  std::vector<float> shadow;
  /// Depth key of the visible point (RasterView), +∞ for the background.
  std::vector<double> key;
};

struct RenderStats {
  double setup_ms = 0;    // culling, clipping, binning, shading set-up
  double shadows_ms = 0;  // exact polygons, shadow maps or the BVH
  double raster_ms = 0;   // the tiles: z-buffer, shadow tests, shading, resolve
  int triangles = 0;      // triangles drawn (after culling and clipping)
  int shadow_polygons = 0;
};

/// Renders the visible bodies of the scene with its camera and lights.
/// \throw InvalidInput for bad options (aa not 1/4/16, sizes out of 1…65536 or more than
///   kMaxImagePixels pixels, more than 32
///   lights with shadows on) or a bad camera. Cost O(faces + pixels·aa·lights) plus the
///   shadow method's (rays: O(log faces) per probe).
Image render(const Scene& scene, const RenderOptions& options, SampleRecord* record = nullptr,
             RenderStats* stats = nullptr);

/// The exact shadow polygons of every light of the scene from hedra/visibility/shadows.h, in the
/// renderer's form. \throw InvalidInput when hedra/visibility/shadows.h is not part of this
/// build. `progress` as ShadowOptions::progress.
SurfaceShadows exact_shadow_polygons(const Scene& scene, const ProgressCallback& progress = {});

/// The camera view render() uses for the scene on a width × height image (the parallel view
/// fitted to the visible bodies' box).
RasterView scene_view(const Scene& scene, int width, int height);

/// Draws 2D segments (raster coordinates) into the image, `width` pixels wide, in `colour`,
/// with coverage anti-aliasing. Cost O(total length · width).
void draw_segments(Image& image, const std::vector<std::array<Eigen::Vector2d, 2>>& segments,
                   const Vec3& colour, double width = 1.0);

/// The hidden-line overlay: the visible edges and junction lines of hedra/visibility/roberts.h's
/// hidden_lines(scene), projected with scene_view and drawn on an image of the scene.
/// \throw InvalidInput from hidden_lines (e.g. a perspective eye inside a body).
void draw_hidden_lines(Image& image, const Scene& scene, const Vec3& colour = Vec3(0.08, 0.08, 0.1),
                       double width = 1.0);

}  // namespace hedra
