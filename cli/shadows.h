// `hedra shadows`: self shadows, cast-shadow polygons and sun studies of a scene (README, "The
// hedra command"; hedra/visibility/shadows.h).
#pragma once

#include <ostream>
#include <string>
#include <vector>

#include "hedra/scene/scene.h"

namespace CLI {
class App;
}

namespace hedra::cli {

struct ShadowsCommand {
  std::string scene_file;
  std::string json_file;  // the full report (faces, polygons, counts, sun study)
  std::string svg_file;   // the shadow polygons over the hidden-line drawing
  bool fit = false;       // --fit: the drawing fitted to the image, not framed as `render` does
  /// START END STEP: ISO 8601 UTC times (or hh:mm on the date of the scene's sun) and minutes.
  std::vector<std::string> sun_hours;
  /// Optional sample grid of the sun study: BODY FACE SPACING.
  std::vector<std::string> grid;
  bool visible_parts =
      false;  // compute the parts of the shadows the camera sees (implied by --svg)
  int threads = 0;
  /// With --sun-hours: run the study on a Dask cluster, a local one of `workers` processes or
  /// the one whose scheduler is at `scheduler` (cli/distributed_study.h).
  int workers = 0;
  std::string scheduler;
};

/// Registers the `shadows` subcommand on `app`, to fill `command`. Malformed option values
/// (a time or a step that does not parse) are usage errors (exit code 2).
CLI::App* add_shadows_subcommand(CLI::App& app, ShadowsCommand& command);

/// Runs `hedra shadows`: reads the scene, computes the shadows of every light (and the sun
/// study with --sun-hours), writes the JSON and SVG atomically and prints a summary.
/// \throw InvalidInput (a scene without lights, --sun-hours without a sun light, a grid body or
///   face that does not exist, anything wrong in the scene), IoError.
void run_shadows(const ShadowsCommand& command, std::ostream& out);

/// `hedra demo`'s shadows: the scene's shadows over its hidden-line drawing, written to `path`,
/// and the shadowed area of the body named "ground" (its top face) printed to `out`.
void write_demo_shadows(const Scene& scene, const std::string& path, std::ostream& out);

}  // namespace hedra::cli
