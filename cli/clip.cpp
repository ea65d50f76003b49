#include "cli/clip.h"

#include <CLI/CLI.hpp>
#include <algorithm>
#include <cstdio>
#include <optional>
#include <vector>

#include "cli/info.h"
#include "cli/segments.h"
#include "cli/usage.h"
#include "hedra/io/atomic_file.h"
#include "hedra/io/mesh_io.h"
#include "hedra/io/text_reader.h"
#include "hedra/clip/batch_clip.h"
#include "hedra/mesh/convexity.h"
#include "hedra/decompose/decompose.h"
#include "hedra/clip/cyrus_beck.h"
#include "hedra/clip/polyhedron_clipper.h"
#include "hedra/core/error.h"
#include "hedra/baselines/midpoint_clip.h"
#include "hedra/core/tolerance.h"

namespace hedra::cli {
namespace {

// A part of a segment as parameters on it.
struct Interval {
  double t0, t1;
};

std::vector<Segment> read_segments(const std::string& path) {
  return parse_segments(path, io::read_file(path));
}

// The midpoint method's clipper: every convex body one piece, every non-convex one its exact
// convex decomposition (midpoint subdivision needs convex pieces).
std::vector<ConvexClipper> decomposed_pieces(const std::string& path,
                                             const std::vector<NamedBody>& bodies) {
  std::vector<ConvexClipper> pieces;
  for (const NamedBody& named : bodies) {
    const Body& body = named.body;
    if (is_convex(body)) {
      pieces.emplace_back(body);
      continue;
    }
    try {
      // Each piece as its exact planes where the decomposition gives them (nothing rounded),
      // else the rounded piece. A moved body's exact image, or a file's rotated part's plane
      // solid, gives every piece exactly convex (DecomposeOptions::prefer_exact_solid).
      DecomposeOptions options;
      options.exact_pieces = true;
      options.prefer_exact_solid = true;
      const Decomposition d = decompose(body, options);
      for (size_t k = 0; k < d.pieces.size(); ++k) {
        if (k < d.exact_pieces.size() && !d.exact_pieces[k].faces.empty())
          pieces.push_back(ConvexClipper::from_planes(d.exact_pieces[k].faces));
        else
          pieces.emplace_back(d.pieces[k]);
      }
    } catch (const InvalidInput& e) {
      throw InvalidInput(path + ": body '" + named.name + "': " + e.what());
    }
  }
  return pieces;
}

// The exact method's clipper: convex bodies through Cyrus–Beck, non-convex ones directly
// against their triangles (PolyhedronClipper), without decomposition.
SolidClipper solid_clipper(const std::string& path, const std::vector<NamedBody>& bodies) {
  std::vector<Body> list;
  list.reserve(bodies.size());
  for (const NamedBody& named : bodies) {
    if (named.body.two_sided())
      throw InvalidInput(path + ": body '" + named.name + "': an open surface (two-sided) has no interior "
                         "to clip against");
    list.push_back(named.body);
  }
  return SolidClipper(list);
}

// Parts from midpoint subdivision of each piece, joined where they are within 2ε (each end is
// within ε of the exact end on its visible side, so parts meeting at a shared face leave a gap
// of up to 2ε).
std::vector<Interval> midpoint_parts(const std::vector<ConvexClipper>& pieces, const Segment& s,
                                     double eps) {
  std::vector<Interval> parts;
  for (const ConvexClipper& piece : pieces)
    if (auto m = midpoint_clip(piece, s.p1, s.p2, eps)) parts.push_back({m->t_start, m->t_end});
  std::sort(parts.begin(), parts.end(),
            [](const Interval& a, const Interval& b) { return a.t0 < b.t0; });
  const double length = (s.p2 - s.p1).norm();
  const double join = length > 0 ? 2 * eps / length : 0;
  std::vector<Interval> merged;
  for (const Interval& p : parts) {
    if (!merged.empty() && p.t0 <= merged.back().t1 + join)
      merged.back().t1 = std::max(merged.back().t1, p.t1);
    else
      merged.push_back(p);
  }
  return merged;
}

std::vector<Interval> complement(const std::vector<Interval>& inside, const Segment& s) {
  if (s.p1 == s.p2) return inside.empty() ? std::vector<Interval>{{0, 1}} : std::vector<Interval>{};
  std::vector<Interval> out;
  double from = 0;
  for (const Interval& p : inside) {
    if (p.t0 > from) out.push_back({from, p.t0});
    from = std::max(from, p.t1);
  }
  if (from < 1) out.push_back({from, 1});
  return out;
}

void append_part(std::string& text, const Segment& s, const Vec3& a, const Vec3& b) {
  char buf[512];
  std::snprintf(buf, sizeof buf, "%.17g %.17g %.17g %.17g %.17g %.17g %d\n", a.x(), a.y(), a.z(),
                b.x(), b.y(), b.z(), s.line);
  text += buf;
}

}  // namespace

CLI::App* add_clip_subcommand(CLI::App& app, ClipCommand& command) {
  CLI::App* clip = app.add_subcommand(
      "clip", "Clip segments (x1 y1 z1 x2 y2 z2 per line) against the bodies of a file");
  clip->add_option("--body", command.body_file,
                   "scene or mesh file: every body of it is part of one clipper (convex or not)")
      ->required();
  clip->add_option("--segments", command.segments_file, "input segments, one per line")->required();
  clip->add_option("-o,--output", command.output_file,
                   "output parts, one per line, followed by the input line number")
      ->required();
  clip->add_flag("--outside", command.outside, "keep the parts outside the body (erasing)");
  clip->add_option("--method", command.method, "cyrus-beck (exact decisions) or midpoint")
      ->check(CLI::IsMember({"cyrus-beck", "midpoint"}));
  clip->add_option("--eps", command.eps, "midpoint precision (default: 1e-9 times the body's size)")
      ->check(finite_number(true));
  return clip;
}

void run_clip(const ClipCommand& command, std::ostream& out) {
  const std::vector<NamedBody> bodies = load_bodies(command.body_file);
  double scale = 0;
  for (const NamedBody& named : bodies) scale = std::max(scale, named.body.scale());
  const bool midpoint = command.method == "midpoint";
  const std::vector<ConvexClipper> pieces =
      midpoint ? decomposed_pieces(command.body_file, bodies) : std::vector<ConvexClipper>{};
  const std::optional<SolidClipper> solid =
      midpoint ? std::nullopt : std::optional(solid_clipper(command.body_file, bodies));
  const std::vector<Segment> segments = read_segments(command.segments_file);
  const double eps = command.eps > 0 ? command.eps : kMidpointEpsilon * std::max(scale, 1e-300);

  std::string text;
  size_t count = 0;
  if (midpoint) {
    for (const Segment& s : segments) {
      std::vector<Interval> parts = midpoint_parts(pieces, s, eps);
      if (command.outside) parts = complement(parts, s);
      for (const Interval& p : parts)
        append_part(text, s, point_at(s.p1, s.p2, p.t0), point_at(s.p1, s.p2, p.t1));
      count += parts.size();
    }
  } else if (!command.outside && solid->convex_count() == 1 && solid->polyhedra().empty()) {
    // One convex clipper: the batch path (identical results to clip_segment, vectorized).
    const ConvexClipper& clipper = solid->convex()[0];
    SegmentArrays batch;
    batch.reserve(segments.size());
    for (const Segment& s : segments) batch.push_back(s.p1, s.p2);
    BatchClipResult result;
    clip_batch(clipper, batch, result);
    for (size_t i = 0; i < segments.size(); ++i) {
      if (!result.visible(i)) continue;
      // End points from the exact crossings, rounded once (not from the rounded t).
      const ClipPart part = result.part(i);
      append_part(text, segments[i], end_point(clipper, part.start, segments[i].p1, segments[i].p2),
                  end_point(clipper, part.end, segments[i].p1, segments[i].p2));
      ++count;
    }
  } else {
    for (const Segment& s : segments) {
      const std::vector<ClipPart> parts =
          command.outside ? solid->clip_outside(s.p1, s.p2) : solid->clip(s.p1, s.p2);
      for (const ClipPart& p : parts)
        append_part(text, s, solid->end_point(p.start, s.p1, s.p2),
                    solid->end_point(p.end, s.p1, s.p2));
      count += parts.size();
    }
  }
  io::write_file_atomically(command.output_file, text);
  out << "wrote " << command.output_file << " (" << count << (count == 1 ? " part" : " parts")
      << " of " << segments.size() << (segments.size() == 1 ? " segment" : " segments") << ", "
      << (command.outside ? "outside" : "inside") << " ";
  // What the segments were clipped against: convex pieces (Cyrus–Beck or midpoint) and, for
  // the exact method, non-convex bodies clipped directly against their triangles.
  const size_t convex = midpoint ? pieces.size() : solid->convex().size();
  const size_t direct = midpoint ? 0 : solid->polyhedra().size();
  if (convex > 0 || direct == 0)
    out << convex << (convex == 1 ? " convex piece" : " convex pieces");
  if (direct > 0) {
    size_t triangles = 0;
    for (const PolyhedronClipper& p : solid->polyhedra())
      triangles += static_cast<size_t>(p.triangle_count());
    out << (convex > 0 ? " and " : "") << direct
        << (direct == 1 ? " non-convex body" : " non-convex bodies") << " (" << triangles
        << " triangles, not decomposed)";
  }
  out << ", " << command.method;
  if (midpoint) out << ", eps " << eps;
  out << ")\n";
}

}  // namespace hedra::cli
