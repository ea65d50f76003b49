#include "cli/hlr.h"

#include <CLI/CLI.hpp>
#include <chrono>
#include <cstdio>

#include "cli/info.h"
#include "cli/progress.h"
#include "hedra/io/atomic_file.h"
#include "hedra/io/report_json.h"
#include "hedra/core/error.h"
#include "hedra/visibility/roberts.h"
#include "hedra/render/raster.h"
#include "hedra/render/svg.h"

namespace hedra::cli {
namespace {

// The drawing framed as `hedra render` frames the scene, or (fit) fitted to the image.
SvgStyle style_of(const Scene& scene, bool hidden, bool fit) {
  SvgStyle style;
  style.width = scene.camera.width;
  style.height = scene.camera.height;
  style.background = scene.image.background;
  style.hidden = hidden;
  if (!fit) style.view = scene_view(scene, style.width, style.height);
  return style;
}

}  // namespace

CLI::App* add_hlr_subcommand(CLI::App& app, HlrCommand& command) {
  CLI::App* hlr = app.add_subcommand(
      "hlr", "Hidden-line drawing of a scene (Roberts, exact): SVG and JSON segment lists");
  hlr->add_option("scene", command.scene_file, "scene or mesh file")->required();
  hlr->add_option("-o,--output", command.svg_file, "write the drawing (SVG)");
  hlr->add_flag("--hidden", command.hidden, "also hidden lines: dashed in the SVG, listed in the JSON");
  hlr->add_option("--json", command.json_file, "write the segments as JSON");
  hlr->add_flag("--fit", command.fit,
                "fit the drawing to the image (default: frame it as `hedra render` does)");
  return hlr;
}

void run_hlr(const HlrCommand& command, std::ostream& out) {
  const Scene scene = load_scene(command.scene_file);
  HlrOptions options;
  options.hidden = command.hidden;
  options.progress = progress_bar("hlr");
  HlrResult result;
  const auto start = std::chrono::steady_clock::now();
  try {
    result = hidden_lines(scene, options);
  } catch (const InvalidInput& e) {
    end_progress_bar();
    throw InvalidInput(command.scene_file + ": " + e.what());
  }
  end_progress_bar();
  const double ms = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count();

  // Everything is formatted before anything is written.
  std::string svg, json;
  if (!command.svg_file.empty()) {
    SvgStyle style = style_of(scene, command.hidden, command.fit);
    style.title = "hedra hlr " + command.scene_file;
    svg = hidden_lines_svg(result, style);
  }
  if (!command.json_file.empty()) {
    json = io::hidden_lines_json(result, ms) + "\n";
  }
  io::OutputTransaction outputs;  // both files or neither
  if (!command.svg_file.empty()) outputs.add(command.svg_file, svg);
  if (!command.json_file.empty()) outputs.add(command.json_file, json);
  check_interrupted();  // Ctrl-C up to here: no file
  outputs.commit();

  size_t edges = 0, junctions = 0;
  for (const HlrSegment& s : result.visible) (s.kind == LineKind::Edge ? edges : junctions) += 1;
  char buf[256];
  std::snprintf(buf, sizeof buf,
                "hidden lines: %zu visible edge segments (length %.6g), %zu junction segments, "
                "%zu hidden segments; %d bodies, %d convex pieces; %.3g ms",
                edges, result.length(LineKind::Edge), junctions, result.hidden.size(),
                result.stats.bodies, result.stats.pieces, ms);
  out << buf;
  if (!command.svg_file.empty()) out << "; wrote " << command.svg_file;
  if (!command.json_file.empty()) out << (command.svg_file.empty() ? "; wrote " : ", ") << command.json_file;
  out << "\n";
}

void write_demo_hidden_lines(const Scene& scene, const std::string& path, std::ostream& out) {
  HlrOptions options;
  options.hidden = true;
  const HlrResult result = hidden_lines(scene, options);
  SvgStyle style = style_of(scene, true, false);
  style.title = "hedra demo: hidden lines";
  io::write_file_atomically(path, hidden_lines_svg(result, style));
  size_t junctions = 0;
  for (const HlrSegment& s : result.visible) junctions += s.kind == LineKind::Junction;
  out << "hidden lines (Roberts, exact): " << result.visible.size() - junctions
      << " visible edge segments, " << junctions << " junction segments, "
      << result.hidden.size() << " hidden (dashed); wrote " << path << "\n";
}

}  // namespace hedra::cli
