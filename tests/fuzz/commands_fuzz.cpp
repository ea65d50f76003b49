// libFuzzer target: a small scene through what every command computes: info (convexity,
// volume, area), decompose, clip (pieces, inside and outside, the batch path against the
// scalar one, the parts' end points), hlr, shadows, render, and convert's round trips through
// the scene file and every full-precision mesh format (hedra must read back every file it
// writes; binary STL is float32 by design, docs/io.md).
#include <cstdio>
#include <cstdlib>

#include "fuzz_common.h"
#include "hedra/clip/batch_clip.h"
#include "hedra/clip/convex_clipper.h"
#include "hedra/clip/cyrus_beck.h"
#include "hedra/clip/polyhedron_clipper.h"
#include "hedra/decompose/decompose.h"
#include "hedra/io/mesh_io.h"
#include "hedra/io/scene_json.h"
#include "hedra/mesh/convexity.h"
#include "hedra/render/raster.h"
#include "hedra/visibility/roberts.h"
#include "hedra/visibility/shadows.h"
#include "obj.h"
#include "off.h"
#include "ply.h"
#include "stl.h"

namespace {

using namespace hedra;

// Small scenes only: the point is every code path, not large inputs (the readers' targets and
// the resource guards cover size).
constexpr int kMaxBodies = 6, kMaxFaces = 200;

// A file hedra wrote that hedra rejects is a finding.
[[noreturn]] void rejected_own_output(const char* what, const std::exception& e) {
  std::fprintf(stderr, "hedra rejects its own %s: %s\n", what, e.what());
  std::abort();
}

void commands(const Scene& scene) {
  int faces = 0;
  for (const SceneBody& b : scene.bodies()) faces += b.body.face_count();
  if (scene.bodies().size() > kMaxBodies || faces > kMaxFaces) return;

  // convert: scene JSON and, per body, OFF read back.
  try {
    io::parse_scene("fuzz/again.json", io::format_scene(scene));
  } catch (const InvalidInput& e) {
    rejected_own_output("scene file", e);
  }
  for (const SceneBody& b : scene.bodies()) {
    io::WriteOptions options;
    options.stl_ascii = true;
    options.names = {b.name};
    const std::vector<Body> one{b.body};
    try {
      bodies_from_soup(io::parse_off("again.off", io::format_bodies(one, io::MeshFormat::Off)));
    } catch (const InvalidInput& e) {
      rejected_own_output("OFF file", e);
    }
    try {
      bodies_from_soup(io::parse_obj("again.obj", io::format_bodies(one, io::MeshFormat::Obj, options)));
    } catch (const InvalidInput& e) {
      rejected_own_output("OBJ file", e);
    }
    try {
      bodies_from_soup(io::parse_ply("again.ply", io::format_bodies(one, io::MeshFormat::Ply)));
    } catch (const InvalidInput& e) {
      rejected_own_output("PLY file", e);
    }
    try {
      bodies_from_soup(io::parse_stl("again.stl", io::format_bodies(one, io::MeshFormat::Stl, options)));
    } catch (const InvalidInput& e) {
      rejected_own_output("ASCII STL file", e);
    }
  }
  // info, decompose, clip.
  for (const SceneBody* b : scene.visible_bodies()) {
    const ConvexityReport c = convexity(b->body);
    (void)b->body.volume();
    (void)b->body.area();
    std::vector<ConvexClipper> pieces;
    if (c.convex) {
      pieces.emplace_back(b->body);
    } else {
      fuzz::rejecting_cleanly([&] {
        DecomposeOptions options;
        options.threads = 1;
        for (const Body& p : decompose(b->body, options).pieces) pieces.emplace_back(p);
        // As `clip --method midpoint` asks: exact pieces, cut from a moved body's exact image
        // or a file's rotated part's plane solid (core/exact_solid.h) where it has one.
        options.exact_pieces = true;
        options.prefer_exact_solid = true;
        (void)decompose(b->body, options);
      });
    }
    const Eigen::AlignedBox3d box = b->body.bbox();
    const Vec3 lo = box.min() - Vec3::Constant(1), hi = box.max() + Vec3::Constant(1);
    const Vec3 centre = box.center();
    const std::pair<Vec3, Vec3> segments[] = {
        {lo, hi}, {Vec3(lo.x(), hi.y(), lo.z()), Vec3(hi.x(), lo.y(), hi.z())}, {centre, centre}};
    if (!c.convex) {
      // hedra clip's exact path for a non-convex body: directly against its triangles.
      fuzz::rejecting_cleanly([&] {
        const PolyhedronClipper direct(b->body);
        for (const auto& [p, q] : segments) {
          for (const ClipPart& part : clip_segment(direct, p, q)) {
            (void)end_point(direct, part.start, p, q);
            (void)end_point(direct, part.end, p, q);
          }
          (void)clip_segment_outside(direct, p, q);
        }
      });
    }
    if (pieces.empty()) continue;
    const std::span<const ConvexClipper> all(pieces);
    SegmentArrays batch;
    for (const auto& [p, q] : segments) {
      for (const ClipPart& part : clip_segment(all, p, q)) {
        (void)end_point(all, part.start, p, q);
        (void)end_point(all, part.end, p, q);
      }
      for (const ClipPart& part : clip_segment_outside(all, p, q)) {
        (void)end_point(all, part.start, p, q);
        (void)end_point(all, part.end, p, q);
      }
      batch.push_back(p, q);
    }
    // The batch path (hedra clip against one convex piece) equals the scalar one bit for bit.
    BatchClipResult result;
    BatchClipOptions batch_options;
    batch_options.threads = 1;
    clip_batch(pieces[0], batch, result, batch_options);
    for (size_t i = 0; i < batch.size(); ++i) {
      const std::optional<ClipPart> scalar = clip_segment(pieces[0], batch.start(i), batch.end(i));
      if (scalar.has_value() != result.visible(i) ||
          (scalar && (scalar->start.t != result.t_start[i] || scalar->end.t != result.t_end[i]))) {
        std::fprintf(stderr, "batch and scalar clipping differ on segment %zu\n", i);
        std::abort();
      }
    }
  }
  // hlr, shadows, render: a scene-level problem (the eye inside a body) is an input error.
  fuzz::rejecting_cleanly([&] {
    HlrOptions options;
    options.hidden = true;
    hidden_lines(scene, options);
  });
  if (!scene.lights.empty())
    fuzz::rejecting_cleanly([&] {
      ShadowOptions options;
      options.threads = 1;
      options.visible_parts = true;
      compute_shadows(scene, options);
    });
  fuzz::rejecting_cleanly([&] {
    RenderOptions options;
    options.width = 24;
    options.height = 18;
    options.threads = 1;
    options.shadows.method = ShadowSettings::Method::Exact;
    render(scene, options);
  });
}

}  // namespace

extern "C" int LLVMFuzzerInitialize(int*, char***) {
  hedra::fuzz::init();
  return 0;
}

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  std::optional<hedra::Scene> scene;
  hedra::fuzz::rejecting_cleanly(
      [&] { scene = hedra::io::parse_scene("fuzz/scene.json", hedra::fuzz::bytes_of(data, size)); });
  if (scene) commands(*scene);
  return 0;
}
