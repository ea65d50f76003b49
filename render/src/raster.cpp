#include "hedra/render/raster.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdlib>
#include <memory>
#include <numbers>
#include <optional>

#include "hedra/core/error.h"
#include "hedra/core/parallel.h"
#include "hedra/visibility/occlusion.h"
#include "hedra/core/tolerance.h"
#include "detail/scan.h"
#include "detail/triangle_raster.h"
#include "hedra/render/ray_shadows.h"
#include "hedra/render/scene_geometry.h"
#include "hedra/render/shadow_map.h"

#include "hedra/visibility/roberts.h"
#include "hedra/visibility/shadows.h"

namespace hedra {
namespace {

using detail::ScanEdge;
using detail::ScanPolygon;
using Clock = std::chrono::steady_clock;

double ms_since(Clock::time_point t) {
  return std::chrono::duration<double, std::milli>(Clock::now() - t).count();
}

// ---- Parsing ----

bool parse_number(const std::string& s, double& out) {
  if (s.empty()) return false;
  char* end = nullptr;
  out = std::strtod(s.c_str(), &end);
  return end == s.c_str() + s.size() && std::isfinite(out);
}

bool parse_int(const std::string& s, int& out) {
  double x;
  if (!parse_number(s, x) || x != std::floor(x) || std::abs(x) > 1e9) return false;
  out = static_cast<int>(x);
  return true;
}

std::vector<std::string> split(const std::string& s, char sep) {
  std::vector<std::string> parts;
  size_t start = 0;
  for (;;) {
    const size_t at = s.find(sep, start);
    parts.push_back(s.substr(start, at == std::string::npos ? std::string::npos : at - start));
    if (at == std::string::npos) return parts;
    start = at + 1;
  }
}

// ---- Lights and the lighting model (docs/algorithms.md §8) ----

// x^n: by repeated squaring for the usual integer exponents (a few ulps from std::pow, and
// several times faster), std::pow otherwise.
double power(double x, double n) {
  if (n >= 0 && n <= 1024 && n == std::floor(n)) {
    double result = 1, base = x;
    for (unsigned k = static_cast<unsigned>(n); k; k >>= 1, base *= base)
      if (k & 1) result *= base;
    return result;
  }
  return std::pow(x, n);
}

struct LightInfo {
  bool at_infinity;
  bool spot;
  Vec3 towards;    // at infinity: unit vector towards the light
  Vec3 position;   // point, spot
  Vec3 axis;       // spot: unit direction of the cone
  double cos_cone = -1, falloff = 0;
  Vec3 rgb;        // I_l per channel: intensity × colour
};

class Lighting {
 public:
  Lighting(const Scene& scene, const RasterView& view, const RenderOptions& options,
           const Eigen::AlignedBox3d& box)
      : view_(view), ambient_(options.ambient), attenuation_(options.attenuation) {
    for (const Light& l : scene.lights) {
      LightInfo info;
      info.at_infinity = l.at_infinity();
      info.spot = l.type == Light::Type::Spot;
      info.towards = -l.direction.normalized();
      info.position = l.position;
      info.axis = l.type == Light::Type::Point ? Vec3::UnitZ() : Vec3(l.direction.normalized());
      if (info.spot) {
        info.cos_cone = std::cos(l.cone_deg * std::numbers::pi / 180);
        info.falloff = l.falloff;
      }
      info.rgb = l.intensity * l.color;
      lights_.push_back(info);
    }
    // Parallel view: the course's d is the depth beyond the scene's nearest point.
    nearest_depth_ = INFINITY;
    for (int i = 0; i < 8; ++i)
      nearest_depth_ = std::min(nearest_depth_, view.depth(box.corner(static_cast<Eigen::AlignedBox3d::CornerType>(i))));
    if (!std::isfinite(nearest_depth_)) nearest_depth_ = 0;
  }

  int light_count() const { return static_cast<int>(lights_.size()); }
  const LightInfo& light(int j) const { return lights_[static_cast<size_t>(j)]; }

  /// Unit vector from p towards the viewer.
  Vec3 to_eye(const Vec3& p) const {
    return view_.is_perspective() ? Vec3((view_.eye() - p).normalized()) : Vec3(-view_.forward());
  }

  Vec3 ambient(const Material& m) const { return ambient_ * m.ka * m.color; }

  /// The course's linear attenuation factor 1/(d + K) (1 for the other models): it depends
  /// on the viewer only, so it multiplies every light's term.
  double viewer_factor(const Vec3& p) const {
    if (attenuation_.model != Attenuation::Model::Linear) return 1;
    const double d = view_.is_perspective() ? (p - view_.eye()).norm()
                                            : std::max(0.0, view_.depth(p) - nearest_depth_);
    return 1 / (d + attenuation_.k);
  }

  /// Light j's diffuse and specular term at p with unit normal n, unit view vector v,
  /// before shadows: I_l·f·[k_d (n̂·L̂) C + k_s (R̂·Ŝ)^n] per channel, f the spot and
  /// quadratic-attenuation factor.
  Vec3 direct(int j, const Material& m, const Vec3& p, const Vec3& n, const Vec3& v) const {
    const LightInfo& l = lights_[static_cast<size_t>(j)];
    Vec3 to_light;
    double factor = 1;
    if (l.at_infinity) {
      to_light = l.towards;
    } else {
      to_light = l.position - p;
      const double d = to_light.norm();
      if (!(d > 0)) return Vec3::Zero();
      to_light /= d;
      if (l.spot) {
        const double c = -to_light.dot(l.axis);
        if (c < l.cos_cone) return Vec3::Zero();
        factor = l.falloff == 0 ? 1.0 : std::pow(c, l.falloff);
      }
      if (attenuation_.model == Attenuation::Model::Quadratic)
        factor /= attenuation_.a + attenuation_.b * d + attenuation_.c * d * d;
    }
    const double ndotl = n.dot(to_light);
    if (!(ndotl > 0)) return Vec3::Zero();
    Vec3 term = m.kd * ndotl * m.color;
    if (m.ks > 0) {
      const Vec3 r = 2 * ndotl * n - to_light;  // reflection of L about n
      const double rv = r.dot(v);
      if (rv > 0) term.array() += m.ks * power(rv, m.shininess);
    }
    return factor * l.rgb.cwiseProduct(term);
  }

 private:
  const RasterView& view_;
  double ambient_;
  Attenuation attenuation_;
  double nearest_depth_ = 0;
  std::vector<LightInfo> lights_;
};

// ---- Per-triangle shading set-up ----

// Barycentric coordinates of a point p of the triangle's plane as affine functions:
// λ_b = gb·(p − a), λ_c = gc·(p − a), λ_a = 1 − λ_b − λ_c.
struct Barycentric {
  Vec3 a, gb, gc;
  static Barycentric of(const Vec3& a, const Vec3& b, const Vec3& c) {
    const Vec3 e1 = b - a, e2 = c - a, n = e1.cross(e2);
    const double nn = n.squaredNorm();
    Barycentric r;
    r.a = a;
    r.gb = nn > 0 ? Vec3(e2.cross(n) / nn) : Vec3::Zero();
    r.gc = nn > 0 ? Vec3(n.cross(e1) / nn) : Vec3::Zero();
    return r;
  }
};

// Exact shadow polygons of one light on one face, prepared for scan conversion. Polygons with
// many edges (a city's ground shadow is one polygon with thousands) keep, per band of tile
// rows, the edges that cross the band.
struct MaskPolygon {
  ScanPolygon polygon;
  int face;
  uint32_t bit;
  int band0 = 0, band_first = -1;  // banded: first band, index into band_offsets
};

// A run of samples c0 ≤ c < c1 of sample row `row` inside mask polygon `polygon`.
struct MaskSpan {
  int row, c0, c1;
  uint32_t polygon;
};

struct ExactMask {
  std::vector<ScanEdge> edges;
  std::vector<MaskPolygon> polygons;
  std::vector<uint32_t> band_offsets;
  std::vector<ScanEdge> band_edges;
  int tiles_x = 0, tiles_y = 0;
  std::vector<std::vector<uint32_t>> band_lists;  // polygons meeting each band of tile rows
  std::vector<std::vector<MaskSpan>> tile_spans;  // spans cut to each tile
};

constexpr uint32_t kBandedEdges = 24;

ExactMask prepare_mask(const SurfaceShadows& shadows, const SceneGeometry& geometry,
                       const RasterView& view, const std::vector<uint8_t>& drawn,
                       const std::vector<uint8_t>& self_shadow, int lights, int tile_size) {
  ExactMask mask;
  mask.tiles_x = (view.width() + tile_size - 1) / tile_size;
  mask.tiles_y = (view.height() + tile_size - 1) / tile_size;
  mask.band_lists.resize(static_cast<size_t>(mask.tiles_y));
  const double guard = std::max(view.width(), view.height());
  std::vector<Eigen::Vector3d> ring, scratch;
  std::vector<detail::Point2> clipped;
  for (int j = 0; j < static_cast<int>(shadows.size()) && j < lights; ++j) {
    for (const SurfaceShadow& s : shadows[static_cast<size_t>(j)]) {
      if (s.body < 0 || s.body >= static_cast<int>(geometry.body_of_scene_index.size())) continue;
      const int b = geometry.body_of_scene_index[static_cast<size_t>(s.body)];
      if (b < 0 || s.face < 0 || s.face >= geometry.bodies[b].body->body.face_count()) continue;
      const int f = geometry.face_index(b, s.face);
      // Faces the camera does not see, and faces wholly in their own shadow, need no detail.
      if (!drawn[f] || self_shadow[static_cast<size_t>(f) * lights + j]) continue;
      MaskPolygon m;
      m.face = f;
      m.bit = 1u << j;
      detail::begin_polygon(m.polygon, mask.edges);
      for (const auto& loop : s.loops) {
        if (loop.size() < 3) continue;
        ring.clear();
        for (const Vec3& p : loop) ring.push_back(view.homogeneous(p));
        detail::clip_ring(ring, view, guard, clipped, scratch);
        if (clipped.size() >= 3) detail::add_ring(m.polygon, clipped, mask.edges);
      }
      if (m.polygon.edge_count == 0) continue;
      const int band0 = std::max(0, static_cast<int>(std::floor(m.polygon.ymin / tile_size)));
      const int band1 = std::min(mask.tiles_y - 1, static_cast<int>(std::floor(m.polygon.ymax / tile_size)));
      if (band0 > band1) continue;
      if (m.polygon.edge_count > kBandedEdges) {
        m.band0 = band0;
        m.band_first = static_cast<int>(mask.band_offsets.size());
        for (int k = band0; k <= band1; ++k) {
          mask.band_offsets.push_back(static_cast<uint32_t>(mask.band_edges.size()));
          const double y0 = k * tile_size, y1 = (k + 1) * tile_size;
          for (uint32_t e = 0; e < m.polygon.edge_count; ++e) {
            const ScanEdge& edge = mask.edges[m.polygon.first_edge + e];
            if (edge.y1 > y0 && edge.y0 < y1) mask.band_edges.push_back(edge);
          }
        }
        mask.band_offsets.push_back(static_cast<uint32_t>(mask.band_edges.size()));
      }
      for (int k = band0; k <= band1; ++k)
        mask.band_lists[static_cast<size_t>(k)].push_back(static_cast<uint32_t>(mask.polygons.size()));
      mask.polygons.push_back(m);
    }
  }
  return mask;
}

// Scan conversion of the mask polygons, one band of tile rows at a time (each sample row is
// scanned once across the whole width, not once per tile), the spans cut to the tiles.
void scan_mask(ExactMask& mask, const detail::SampleGrid& grid, int tile_size) {
  mask.tile_spans.assign(static_cast<size_t>(mask.tiles_x) * mask.tiles_y, {});
  const int tile_samples = tile_size * grid.g;
  parallel_for(static_cast<size_t>(mask.tiles_y), 0, [&](size_t band_index) {
    const int band = static_cast<int>(band_index);
    const int r0 = band * tile_samples, r1 = std::min(r0 + tile_samples, grid.rows);
    std::vector<double> xs;
    for (uint32_t index : mask.band_lists[static_cast<size_t>(band)]) {
      const MaskPolygon& m = mask.polygons[index];
      auto span = [&](int r, int c0, int c1) {
        for (int t = c0 / tile_samples; t * tile_samples < c1; ++t)
          mask.tile_spans[static_cast<size_t>(band) * mask.tiles_x + t].push_back(
              {r, std::max(c0, t * tile_samples), std::min(c1, (t + 1) * tile_samples), index});
      };
      if (m.band_first < 0) {
        detail::scan_polygon(m.polygon, mask.edges, grid, r0, r1, 0, grid.columns, xs, span);
      } else {
        const size_t k = static_cast<size_t>(m.band_first + band - m.band0);
        const uint32_t e0 = mask.band_offsets[k], e1 = mask.band_offsets[k + 1];
        detail::scan_edges(mask.band_edges.data() + e0, e1 - e0, m.polygon.ymin, m.polygon.ymax,
                           grid, r0, r1, 0, grid.columns, xs, span);
      }
    }
  });
}

// Hammersley points: a deterministic, well-spread set of n points in the unit square.
std::vector<Eigen::Vector2d> hammersley(int n) {
  std::vector<Eigen::Vector2d> points;
  for (int i = 0; i < n; ++i) {
    double v = 0, f = 0.5;
    for (unsigned k = static_cast<unsigned>(i); k; k >>= 1, f *= 0.5)
      if (k & 1) v += f;
    points.emplace_back((i + 0.5) / n, n == 1 ? 0.5 : v + 0.5 / n);
  }
  return points;
}

uint8_t to_byte(double v) {
  return static_cast<uint8_t>(std::clamp(v, 0.0, 1.0) * 255 + 0.5);
}

}  // namespace

Attenuation Attenuation::parse(const std::string& text) {
  const auto fail = [&]() -> Attenuation {
    throw InvalidInput("attenuation '" + text +
                       "': expected none, linear:K (K > 0) or quadratic:A,B,C (A, B, C >= 0, A > 0)");
  };
  Attenuation a;
  const std::vector<std::string> parts = split(text, ':');
  if (parts[0] == "none" && parts.size() == 1) return a;
  if (parts[0] == "linear" && parts.size() == 2) {
    a.model = Model::Linear;
    if (!parse_number(parts[1], a.k) || !(a.k > 0)) fail();
    return a;
  }
  if (parts[0] == "quadratic" && parts.size() == 2) {
    a.model = Model::Quadratic;
    const std::vector<std::string> abc = split(parts[1], ',');
    if (abc.size() != 3 || !parse_number(abc[0], a.a) || !parse_number(abc[1], a.b) ||
        !parse_number(abc[2], a.c) || !(a.a > 0) || a.b < 0 || a.c < 0)
      fail();
    return a;
  }
  return fail();
}

ShadowSettings ShadowSettings::parse(const std::string& text) {
  const auto fail = [&](const std::string& why) -> ShadowSettings {
    throw InvalidInput("shadows '" + text + "': " + why);
  };
  ShadowSettings s;
  const std::vector<std::string> parts = split(text, ':');
  const std::string& name = parts[0];
  if (name == "none" || name == "exact") {
    if (parts.size() != 1) fail("'" + name + "' takes no parameters");
    s.method = name == "none" ? Method::None : Method::Exact;
  } else if (name == "map") {
    s.method = Method::Map;
    if (parts.size() > 3) fail("expected map[:RES[:BIAS]]");
    if (parts.size() > 1 && (!parse_int(parts[1], s.map_resolution) || s.map_resolution < 16 ||
                             s.map_resolution > 16384))
      fail("RES must be an integer from 16 to 16384");
    if (parts.size() > 2 && (!parse_number(parts[2], s.map_bias) || s.map_bias < 0))
      fail("BIAS must be a number >= 0 (texels)");
  } else if (name == "rays") {
    s.method = Method::Rays;
    if (parts.size() > 2) fail("expected rays[:SPP]");
    if (parts.size() > 1 && (!parse_int(parts[1], s.ray_samples) || s.ray_samples < 1 ||
                             s.ray_samples > 256))
      fail("SPP must be an integer from 1 to 256");
  } else {
    fail("expected exact, map[:RES[:BIAS]], rays[:SPP] or none");
  }
  return s;
}

std::string ShadowSettings::to_string() const {
  char buf[64];
  switch (method) {
    case Method::None: return "none";
    case Method::Exact: return "exact";
    case Method::Map:
      std::snprintf(buf, sizeof buf, "map:%d:%g", map_resolution, map_bias);
      return buf;
    case Method::Rays:
      return "rays:" + std::to_string(ray_samples);
  }
  return "none";
}

SurfaceShadows exact_shadow_polygons(const Scene& scene, const ProgressCallback& progress) {
  ShadowOptions options;
  options.counts = false;
  options.progress = progress;
  const ShadowResult result = compute_shadows(scene, options);
  SurfaceShadows out(result.lights.size());
  for (size_t l = 0; l < result.lights.size(); ++l)
    for (const FaceShadow& f : result.lights[l].faces) {
      if (f.to_light != Facing::Front || f.polygons.empty()) continue;
      SurfaceShadow s;
      s.body = f.body;
      s.face = f.face;
      for (const ShadowPolygon& p : f.polygons) {
        s.loops.push_back(p.outer);
        for (const Polygon3& h : p.holes) s.loops.push_back(h);
      }
      out[l].push_back(std::move(s));
    }
  return out;
}

Image render(const Scene& scene, const RenderOptions& options, SampleRecord* record,
             RenderStats* stats) {
  const auto t_start = Clock::now();
  RenderStats local_stats;
  RenderStats& st = stats ? *stats : local_stats;
  st = RenderStats();

  // ---- Options ----
  const int width = options.width > 0 ? options.width : scene.camera.width;
  const int height = options.height > 0 ? options.height : scene.camera.height;
  if (width < 1 || height < 1 || width > 65536 || height > 65536)
    throw InvalidInput("image size must be between 1 and 65536 pixels");
  if (options.aa != 1 && options.aa != 4 && options.aa != 16)
    throw InvalidInput("--aa must be 1, 4 or 16 samples per pixel");
  if (options.tile_size < 4 || options.tile_size > 1024)
    throw InvalidInput("tile size must be between 4 and 1024 pixels");
  if (!(options.ambient >= 0) || !std::isfinite(options.ambient))
    throw InvalidInput("ambient intensity must be >= 0");
  const ShadowSettings::Method method = options.shadows.method;
  const bool shadows_on = method != ShadowSettings::Method::None;
  const int lights = static_cast<int>(scene.lights.size());
  if (shadows_on && lights > 32)
    throw InvalidInput("shadows support at most 32 lights; the scene has " + std::to_string(lights));
  for (const Light& l : scene.lights) l.validate();
  const int g = options.aa == 1 ? 1 : options.aa == 4 ? 2 : 4;

  Image image;
  // RenderOptions::progress: set-up 5 %, the shadow method 45 % (the exact polygons report
  // through it), the tiles the rest.
  ProgressMeter meter(options.progress, "rendering cancelled");
  meter.stage(0, 0.05, 1);
  with_threads(options.threads, [&] {
    // ---- Set-up: geometry, view, culling (docs/algorithms.md §6.1 by the body matrix) ----
    const SceneGeometry geometry = SceneGeometry::of(scene);
    const Eigen::AlignedBox3d box = geometry.bbox();
    const RasterView view = scene_view(scene, width, height);
    const Viewpoint eye = Viewpoint::of(scene.camera);
    const size_t faces = geometry.faces.size();
    std::vector<uint8_t> drawn(faces), self_shadow(faces * static_cast<size_t>(lights), 0);
    std::vector<Viewpoint> light_points;
    for (const Light& l : scene.lights) light_points.push_back(Viewpoint::of(l));
    parallel_for(faces, 0, [&](size_t f) {
      const SceneGeometry::FaceRef& face = geometry.faces[f];
      const Body& body = geometry.bodies[face.body].body->body;
      drawn[f] = facing(body, face.face, eye) == Facing::Front;
      // Self shadow: the face turns its back or its edge to the light (§7, L·V ≤ 0).
      if (shadows_on && drawn[f])
        for (int j = 0; j < lights; ++j)
          self_shadow[f * lights + j] = facing(body, face.face, light_points[j]) != Facing::Front;
    });
    const detail::TriangleRaster raster = detail::prepare_triangles(geometry, view, drawn, g, options.tile_size);
    st.triangles = static_cast<int>(raster.polygons.size());
    const Lighting lighting(scene, view, options, box);

    // Shading set-up per drawn triangle: barycentric maps; Gouraud: each corner's light terms;
    // Flat: each face's light terms at its centroid.
    const Shading shading = options.shading;
    const size_t polygons = raster.polygons.size();
    std::vector<Barycentric> bary(shading == Shading::Flat ? 0 : polygons);
    std::vector<Vec3> corner_terms(shading == Shading::Gouraud ? polygons * 3 * lights : 0);
    std::vector<Vec3> corner_ambient(shading == Shading::Gouraud ? polygons * 3 : 0);
    std::vector<Vec3> face_terms(shading == Shading::Flat ? faces * lights : 0);
    std::vector<Vec3> face_ambient(shading == Shading::Flat ? faces : 0);
    auto material_of = [&](int f) -> const Material& {
      return geometry.bodies[geometry.faces[f].body].body->material;
    };
    parallel_for(polygons, 0, [&](size_t i) {
      if (shading == Shading::Flat) return;
      const SceneGeometry::Tri& tri = geometry.triangles[raster.triangle[i]];
      const Vec3 &a = geometry.positions[tri.v[0]], &b = geometry.positions[tri.v[1]],
                 &c = geometry.positions[tri.v[2]];
      bary[i] = Barycentric::of(a, b, c);
      if (shading != Shading::Gouraud) return;
      const Material& m = material_of(tri.face);
      for (int k = 0; k < 3; ++k) {
        const Vec3& p = geometry.positions[tri.v[k]];
        const double f = lighting.viewer_factor(p);
        corner_ambient[3 * i + k] = lighting.ambient(m);
        for (int j = 0; j < lights; ++j)
          corner_terms[(i * lights + j) * 3 + k] = f * lighting.direct(j, m, p, tri.normal[k], lighting.to_eye(p));
      }
    });
    if (shading == Shading::Flat)
      parallel_for(faces, 0, [&](size_t f) {
        if (!drawn[f]) return;
        const SceneGeometry::FaceRef& face = geometry.faces[f];
        const Material& m = material_of(static_cast<int>(f));
        const double factor = lighting.viewer_factor(face.centroid);
        face_ambient[f] = lighting.ambient(m);
        for (int j = 0; j < lights; ++j)
          face_terms[f * lights + j] =
              factor * lighting.direct(j, m, face.centroid, face.outward, lighting.to_eye(face.centroid));
      });
    st.setup_ms = ms_since(t_start);
    meter.finish_stage();
    meter.stage(0.05, 0.5, 1);

    // ---- Shadow method set-up ----
    const auto t_shadows = Clock::now();
    std::optional<ExactMask> mask;
    std::vector<std::unique_ptr<ShadowMap>> maps;
    std::optional<ShadowBvh> bvh;
    if (method == ShadowSettings::Method::Exact) {
      SurfaceShadows computed;
      const SurfaceShadows* polygons_in = options.exact_polygons;
      if (!polygons_in) {
        ProgressCallback sub;
        if (options.progress)
          sub = [&options](double f) { return options.progress(0.05 + 0.45 * f); };
        computed = exact_shadow_polygons(scene, sub);
        polygons_in = &computed;
      }
      mask = prepare_mask(*polygons_in, geometry, view, drawn, self_shadow, lights, options.tile_size);
      scan_mask(*mask, raster.grid, options.tile_size);
      st.shadow_polygons = static_cast<int>(mask->polygons.size());
    } else if (method == ShadowSettings::Method::Map) {
      // All maps live at once: bounded before any is allocated (a point light takes six).
      const long long side = options.shadows.map_resolution;
      long long texels = 0;
      for (const Light& l : scene.lights) texels += (l.type == Light::Type::Point ? 6 : 1) * side * side;
      if (texels > kMaxShadowMapTexels)
        throw InvalidInput("shadow maps of " + std::to_string(side) + "² texels for " +
                           std::to_string(scene.lights.size()) + " light(s) need " +
                           std::to_string(texels) + " texels, more than " +
                           std::to_string(kMaxShadowMapTexels) + " (give a smaller map:RES)");
      for (const Light& l : scene.lights)
        maps.push_back(std::make_unique<ShadowMap>(geometry, l, options.shadows.map_resolution,
                                                   options.shadows.map_bias));
    } else if (method == ShadowSettings::Method::Rays) {
      bvh.emplace(geometry);
    }
    st.shadows_ms = ms_since(t_shadows);
    meter.finish_stage();
    const double diagonal = box.isEmpty() ? 1.0 : box.diagonal().norm();
    const double ray_offset = kShadowRayOffset * diagonal;
    const std::vector<Eigen::Vector2d> probes = hammersley(options.shadows.ray_samples);
    // Rays with several probes: which points of a face's plane lie on the face (barycentric
    // maps of its triangles, with a rounding margin).
    std::vector<Barycentric> face_triangles;
    if (bvh && probes.size() > 1) {
      face_triangles.resize(geometry.triangles.size());
      parallel_for(geometry.triangles.size(), 0, [&](size_t t) {
        const SceneGeometry::Tri& tri = geometry.triangles[t];
        if (drawn[tri.face])
          face_triangles[t] = Barycentric::of(geometry.positions[tri.v[0]], geometry.positions[tri.v[1]],
                                              geometry.positions[tri.v[2]]);
      });
    }
    auto on_face = [&](int f, const Vec3& q) {
      for (int t = geometry.triangle_begin[f]; t < geometry.triangle_begin[f + 1]; ++t) {
        const Barycentric& bc = face_triangles[static_cast<size_t>(t)];
        const Vec3 rel = q - bc.a;
        const double lb = bc.gb.dot(rel), lc = bc.gc.dot(rel);
        if (lb >= -1e-12 && lc >= -1e-12 && lb + lc <= 1 + 1e-12) return true;
      }
      return false;
    };

    // ---- Tiles ----
    const auto t_raster = Clock::now();
    image.width = width;
    image.height = height;
    image.rgb.assign(static_cast<size_t>(width) * height * 3, 0);
    const detail::SampleGrid& grid = raster.grid;
    if (record) {
      record->columns = grid.columns;
      record->rows = grid.rows;
      record->lights = lights;
      record->view = view;
      const size_t n = static_cast<size_t>(grid.columns) * grid.rows;
      record->body.assign(n, -1);
      record->face.assign(n, -1);
      record->shadow.assign(n * lights, 0.0f);
      record->key.assign(n, INFINITY);
    }
    const Vec3 background = scene.image.background;
    meter.stage(0.5, 1.0, static_cast<double>(raster.bins.count()));
    parallel_for(static_cast<size_t>(raster.bins.count()), 0, [&](size_t index) {
      meter.add();
      const int tile = static_cast<int>(index);
      const detail::TileRect rect = detail::tile_rect(raster, tile);
      const int n = rect.size(), stride = rect.columns();
      std::vector<double> key(static_cast<size_t>(n)), scratch;
      std::vector<int> id(static_cast<size_t>(n));
      detail::depth_tile(raster, rect, key.data(), id.data(), scratch);

      // Exact shadows: each polygon marks the samples where its own face is the visible one.
      std::vector<uint32_t> bits;
      if (mask) {
        bits.assign(static_cast<size_t>(n), 0);
        for (const MaskSpan& span : mask->tile_spans[static_cast<size_t>(tile)]) {
          const MaskPolygon& m = mask->polygons[span.polygon];
          const size_t row = static_cast<size_t>(span.row - rect.r0) * stride - rect.c0;
          for (int c = span.c0; c < span.c1; ++c) {
            const int p = id[row + c];
            if (p >= 0 && raster.face[p] == m.face) bits[row + c] |= m.bit;
          }
        }
      }

      // Shading of every sample, then the resolve into pixels.
      std::vector<Vec3> colour(static_cast<size_t>(n));
      std::vector<float> shadow(static_cast<size_t>(lights));
      std::vector<Vec3> probe_points;
      for (int r = rect.r0; r < rect.r1; ++r) {
        const double sy = grid.y(r);
        for (int c = rect.c0; c < rect.c1; ++c) {
          const size_t s = static_cast<size_t>(r - rect.r0) * stride + (c - rect.c0);
          const int p = id[s];
          if (p < 0) {
            colour[s] = background;
            continue;
          }
          const double sx = grid.x(c);
          const int f = raster.face[p];
          const SceneGeometry::FaceRef& face = geometry.faces[f];
          const Material& m = geometry.bodies[face.body].body->material;
          const Vec3 point = view.point_at(sx, sy, key[s]);
          // Shadow rays: the probe points, spread over the sample's footprint on its face. A
          // probe counts only where the face is really there and seen (inside the face, and
          // not hidden from the eye: the ground under a box is not part of the pixel).
          if (bvh) {
            probe_points.clear();
            if (probes.size() == 1) probe_points.push_back(point);
            for (size_t k = 0; probes.size() > 1 && k < probes.size(); ++k) {
              const double px = sx + (probes[k].x() - 0.5) * grid.step;
              const double py = sy + (probes[k].y() - 0.5) * grid.step;
              const Eigen::Vector3d& kp = raster.key_plane[f];
              const Vec3 q = view.point_at(px, py, kp[0] * px + kp[1] * py + kp[2]);
              if (!on_face(f, q)) continue;
              const bool hidden =
                  view.is_perspective()
                      ? bvh->occluded(q, view.eye() - q, ray_offset / std::max((view.eye() - q).norm(), 1e-300), 1, f)
                      : bvh->occluded(q, -view.forward(), ray_offset, INFINITY, f);
              if (!hidden) probe_points.push_back(q);
            }
            if (probe_points.empty()) probe_points.push_back(point);
          }
          // Shadow fraction per light.
          for (int j = 0; j < lights; ++j) {
            float blocked = 0;
            if (shadows_on && self_shadow[static_cast<size_t>(f) * lights + j]) {
              blocked = 1;
            } else if (mask) {
              blocked = (bits[s] >> j) & 1u ? 1.0f : 0.0f;
            } else if (!maps.empty()) {
              blocked = maps[j]->shadowed(point) ? 1.0f : 0.0f;
            } else if (bvh) {
              const LightInfo& l = lighting.light(j);
              int hits = 0;
              for (const Vec3& q : probe_points) {
                if (l.at_infinity) {
                  hits += bvh->occluded(q, l.towards, ray_offset, INFINITY, f);
                } else {
                  const Vec3 d = l.position - q;
                  const double len = d.norm();
                  if (len > 0) hits += bvh->occluded(q, d, ray_offset / len, 1, f);
                }
              }
              blocked = static_cast<float>(hits) / static_cast<float>(probe_points.size());
            }
            shadow[j] = blocked;
          }
          Vec3 rgb;
          if (shading == Shading::Flat) {
            rgb = face_ambient[f];
            for (int j = 0; j < lights; ++j) rgb += (1 - shadow[j]) * face_terms[static_cast<size_t>(f) * lights + j];
          } else {
            const Barycentric& bc = bary[p];
            const Vec3 rel = point - bc.a;
            const double lb = bc.gb.dot(rel), lc = bc.gc.dot(rel), la = 1 - lb - lc;
            if (shading == Shading::Gouraud) {
              const Vec3* amb = &corner_ambient[3 * static_cast<size_t>(p)];
              rgb = la * amb[0] + lb * amb[1] + lc * amb[2];
              for (int j = 0; j < lights; ++j) {
                const Vec3* t = &corner_terms[(static_cast<size_t>(p) * lights + j) * 3];
                rgb += (1 - shadow[j]) * (la * t[0] + lb * t[1] + lc * t[2]);
              }
            } else {
              Vec3 normal = face.outward;
              if (face.smooth) {
                const SceneGeometry::Tri& tri = geometry.triangles[raster.triangle[p]];
                normal = (la * tri.normal[0] + lb * tri.normal[1] + lc * tri.normal[2]).normalized();
              }
              const Vec3 v = lighting.to_eye(point);
              const double factor = lighting.viewer_factor(point);
              rgb = lighting.ambient(m);
              for (int j = 0; j < lights; ++j)
                if (shadow[j] < 1) rgb += (factor * (1 - shadow[j])) * lighting.direct(j, m, point, normal, v);
            }
          }
          colour[s] = rgb;
          if (record) {
            const size_t at = static_cast<size_t>(r) * grid.columns + c;
            record->body[at] = geometry.bodies[face.body].scene_index;
            record->face[at] = face.face;
            record->key[at] = key[s];
            for (int j = 0; j < lights; ++j) record->shadow[at * lights + j] = shadow[j];
          }
        }
      }
      // Resolve: the average of each pixel's g × g samples.
      const double weight = 1.0 / (g * g);
      for (int y = rect.r0 / g; y < rect.r1 / g; ++y)
        for (int x = rect.c0 / g; x < rect.c1 / g; ++x) {
          Vec3 sum = Vec3::Zero();
          for (int dy = 0; dy < g; ++dy)
            for (int dx = 0; dx < g; ++dx)
              sum += colour[static_cast<size_t>(y * g + dy - rect.r0) * stride + (x * g + dx - rect.c0)];
          uint8_t* out = &image.rgb[3 * (static_cast<size_t>(y) * width + x)];
          for (int k = 0; k < 3; ++k) out[k] = to_byte(weight * sum[k]);
        }
    });
    st.raster_ms = ms_since(t_raster);
    meter.finish_stage();
  });
  return image;
}

RasterView scene_view(const Scene& scene, int width, int height) {
  return RasterView::of_camera(scene.camera, width, height, scene.bbox());
}

void draw_hidden_lines(Image& image, const Scene& scene, const Vec3& colour, double width) {
  const HlrResult lines = hidden_lines(scene);
  const RasterView view = scene_view(scene, image.width, image.height);
  std::vector<std::array<Eigen::Vector2d, 2>> segments;
  for (const HlrSegment& s : lines.visible) segments.push_back({view.project(s.a), view.project(s.b)});
  draw_segments(image, segments, colour, width);
}

void draw_segments(Image& image, const std::vector<std::array<Eigen::Vector2d, 2>>& segments,
                   const Vec3& colour, double width) {
  const double half = 0.5 * width;
  for (const auto& seg : segments) {
    const Eigen::Vector2d a = seg[0], b = seg[1];
    if (!a.allFinite() || !b.allFinite()) continue;
    const int x0 = std::max(0, static_cast<int>(std::floor(std::min(a.x(), b.x()) - half - 1)));
    const int x1 = std::min(image.width - 1, static_cast<int>(std::ceil(std::max(a.x(), b.x()) + half + 1)));
    const int y0 = std::max(0, static_cast<int>(std::floor(std::min(a.y(), b.y()) - half - 1)));
    const int y1 = std::min(image.height - 1, static_cast<int>(std::ceil(std::max(a.y(), b.y()) + half + 1)));
    const Eigen::Vector2d d = b - a;
    const double len2 = d.squaredNorm();
    for (int y = y0; y <= y1; ++y)
      for (int x = x0; x <= x1; ++x) {
        // Coverage from the distance of the pixel centre to the segment (a one-pixel ramp).
        const Eigen::Vector2d p(x + 0.5, y + 0.5);
        const double t = len2 > 0 ? std::clamp((p - a).dot(d) / len2, 0.0, 1.0) : 0.0;
        const double dist = (p - (a + t * d)).norm();
        const double cover = std::clamp(half + 0.5 - dist, 0.0, 1.0);
        if (cover <= 0) continue;
        uint8_t* out = &image.rgb[3 * (static_cast<size_t>(y) * image.width + x)];
        for (int k = 0; k < 3; ++k) out[k] = to_byte((1 - cover) * out[k] / 255.0 + cover * colour[k]);
      }
  }
}

}  // namespace hedra
