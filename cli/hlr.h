// `hedra hlr`: Roberts hidden-line removal of a scene, drawn as SVG and listed as JSON
// (README, "The hedra command"; docs/hidden-lines.md).
#pragma once

#include <ostream>
#include <string>

#include "hedra/scene/scene.h"

namespace CLI {
class App;
}

namespace hedra::cli {

struct HlrCommand {
  std::string scene_file;
  std::string svg_file;   // -o: the drawing
  std::string json_file;  // --json: the segments
  bool hidden = false;    // also hidden lines (dashed in the drawing, "hidden" in the JSON)
  double crease_angle = 30;  // --crease-angle: edges turning less are smooth (0..180 degrees)
  bool smooth = false;       // --smooth: also draw the smooth edges
  bool fit = false;       // --fit: the drawing fitted to the image, not framed as `render` does
};

/// Registers the `hlr` subcommand and its options on `app`, to fill `command`.
CLI::App* add_hlr_subcommand(CLI::App& app, HlrCommand& command);

/// Runs `hedra hlr`: reads the scene, removes the hidden lines with the scene's camera, writes
/// the SVG (framed as `hedra render` frames the scene, or fitted with --fit) and the JSON {"visible": [[x1,y1,z1,x2,y2,z2], …], "hidden": […], "junction": […],
/// "ms": T} (world coordinates; junction segments only under "junction", visible parts only;
/// "outline" when the scene has smooth parts, "smooth" with --smooth;
/// "hidden" filled with --hidden; ms = computation time without file I/O), each file whole or
/// not at all, and prints a one-line summary to `out`.
/// \throw InvalidInput naming the file and the place ("scene.json:14:9: …", "scene.json: body
///   'tower': …"), IoError.
void run_hlr(const HlrCommand& command, std::ostream& out);

/// `hedra demo`'s drawing of the demo scene: writes `path` (SVG, hidden lines dashed) and a
/// line about it to `out`.
void write_demo_hidden_lines(const Scene& scene, const std::string& path, std::ostream& out);

}  // namespace hedra::cli
