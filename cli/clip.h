// `hedra clip`: clips the segments of a text file against a body (README, "The hedra command").
#pragma once

#include <ostream>
#include <string>

namespace CLI {
class App;
}

namespace hedra::cli {

struct ClipCommand {
  std::string body_file;      // mesh or scene file: its bodies (convex or not) form one clipper
  std::string segments_file;  // one segment per line: x1 y1 z1 x2 y2 z2
  std::string output_file;    // the parts, one per line: x1 y1 z1 x2 y2 z2 input-line
  bool outside = false;       // keep the parts outside (erasing) instead of inside
  std::string method = "cyrus-beck";  // or "midpoint"
  double eps = 0;  // midpoint precision; 0: kMidpointEpsilon × the clipper's scale
};

/// Registers the `clip` subcommand and its options on `app`, to fill `command`.
CLI::App* add_clip_subcommand(CLI::App& app, ClipCommand& command);

/// Runs `hedra clip`: reads the clipper and the segments, clips every segment in input order
/// and writes the parts (several per segment for a non-convex clipper, in order along it)
/// atomically; prints a one-line summary to `out`. Every body of the file (mesh or scene) is
/// part of one clipper: with the exact method a convex body through Cyrus–Beck and a non-convex
/// one directly against its triangles (PolyhedronClipper, no decomposition); with the midpoint
/// method a non-convex body through its exact convex decomposition.
/// \throw InvalidInput naming the file and line ("segments.txt:7: …"), IoError.
void run_clip(const ClipCommand& command, std::ostream& out);

}  // namespace hedra::cli
