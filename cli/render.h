// `hedra render`: a shaded PNG image of a scene (README, "The hedra command").
#pragma once

#include <ostream>
#include <string>

#include "hedra/scene/scene.h"

namespace CLI {
class App;
}

namespace hedra::cli {

struct RenderCommand {
  std::string scene_file;   // scene (.json), or a mesh file shown with a default view and light
  std::string output_file;  // .png
  std::string shadows = "exact";  // exact | map[:RES[:BIAS]] | rays[:SPP] | none
  std::string shading = "phong";  // flat | gouraud | phong
  int width = 0, height = 0;      // 0: the scene's image size
  int aa = 1;                     // 1 | 4 | 16
  bool lines = false;             // hidden-line overlay (hedra/visibility/roberts.h)
  std::string attenuation = "none";
  double ambient = 1;
  int threads = 0;
};

/// Registers the `render` subcommand on `app`, to fill `command`. Malformed option values
/// are usage errors (exit code 2).
CLI::App* add_render_subcommand(CLI::App& app, RenderCommand& command);

/// Runs `hedra render`: reads the scene, renders it (hedra/render/raster.h), draws the visible
/// lines on top with --lines, writes the PNG atomically and prints a one-line summary.
/// \throw InvalidInput naming the file and the place, IoError.
void run_render(const RenderCommand& command, std::ostream& out);

/// `hedra demo`'s picture: the scene with Phong shading and exact shadows, 4 samples per
/// pixel, written to `path`; prints one line to `out`.
void write_demo_render(const Scene& scene, const std::string& path, std::ostream& out);

}  // namespace hedra::cli
