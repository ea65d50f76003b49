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
  hlr->add_option("--crease-angle", command.crease_angle,
                  "edges whose faces turn by at most DEG are smooth: not drawn, the outline of "
                  "smooth parts is (0..180, default 30; 0: every edge)")
      ->check(CLI::Validator(
          [](std::string& text) -> std::string {
            double v = 0;
            if (!CLI::detail::lexical_cast(text, v) || !(v >= 0 && v <= 180))
              return "expected an angle from 0 to 180 degrees, got '" + text + "'";
            return "";
          },
          "DEG"));
  hlr->add_flag("--smooth", command.smooth, "also draw the smooth edges (class \"smooth\")");
  hlr->add_flag("--fit", command.fit,
                "fit the drawing to the image (default: frame it as `hedra render` does)");
  return hlr;
}

void run_hlr(const HlrCommand& command, std::ostream& out) {
  const Scene scene = load_scene(command.scene_file);
  HlrOptions options;
  options.hidden = command.hidden;
  options.crease_angle = command.crease_angle;
  options.smooth = command.smooth;
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

  size_t edges = 0, junctions = 0, outlines = 0, smooth = 0;
  for (const HlrSegment& s : result.visible) {
    if (s.kind == LineKind::Edge) ++edges;
    else if (s.kind == LineKind::Junction) ++junctions;
    else if (s.kind == LineKind::Outline) ++outlines;
    else ++smooth;
  }
  char buf[256];
  std::snprintf(buf, sizeof buf,
                "hidden lines: %zu visible edge segments (length %.6g), %zu junction segments, "
                "%zu hidden segments; ",
                edges, result.length(LineKind::Edge), junctions, result.hidden.size());
  out << buf;
  if (result.has_smooth()) {
    std::snprintf(buf, sizeof buf, "%zu outline segments (length %.6g), %d smooth edges%s; ",
                  outlines, result.length(LineKind::Outline), result.stats.smooth_edges,
                  command.smooth ? (" (" + std::to_string(smooth) + " segments drawn)").c_str() : "");
    out << buf;
  }
  std::snprintf(buf, sizeof buf, "%d bodies, %d convex pieces; %.3g ms", result.stats.bodies,
                result.stats.pieces, ms);
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
  size_t edges = 0, junctions = 0, outlines = 0;
  for (const HlrSegment& s : result.visible) {
    junctions += s.kind == LineKind::Junction;
    edges += s.kind == LineKind::Edge;
    outlines += s.kind == LineKind::Outline;
  }
  out << "hidden lines (Roberts, exact): " << edges << " visible edge segments, " << junctions
      << " junction segments, ";
  if (result.has_smooth()) out << outlines << " outline segments, ";
  out << result.hidden.size() << " hidden (dashed); wrote " << path << "\n";
}

}  // namespace hedra::cli
