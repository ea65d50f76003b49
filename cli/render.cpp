#include "cli/render.h"

#include <CLI/CLI.hpp>

#include <chrono>
#include <cstdio>

#include "cli/info.h"
#include "cli/progress.h"
#include "cli/usage.h"
#include "hedra/io/png.h"
#include "hedra/core/error.h"
#include "hedra/render/raster.h"

namespace hedra::cli {
namespace {

// CLI11 validators: a malformed value is a usage error (exit 2), named by CLI11.
template <class Parse>
CLI::Validator parsed_by(const char* what, Parse parse) {
  return CLI::Validator(
      [parse](std::string& value) -> std::string {
        try {
          parse(value);
          return "";
        } catch (const InvalidInput& e) {
          return e.what();
        }
      },
      what);
}

Shading shading_of(const std::string& name) {
  if (name == "flat") return Shading::Flat;
  if (name == "gouraud") return Shading::Gouraud;
  return Shading::Phong;
}

const char* shading_name(Shading s) {
  return s == Shading::Flat ? "flat" : s == Shading::Gouraud ? "Gouraud" : "Phong";
}

}  // namespace

CLI::App* add_render_subcommand(CLI::App& app, RenderCommand& c) {
  CLI::App* sub = app.add_subcommand("render", "Render a shaded PNG image of a scene with shadows");
  sub->add_option("scene", c.scene_file, "scene (.json) or mesh file")->required()->check(CLI::ExistingFile);
  sub->add_option("-o", c.output_file, "output image (.png)")
      ->required()
      ->check(CLI::Validator(
          [](std::string& v) {
            return v.size() > 4 && v.substr(v.size() - 4) == ".png" ? std::string()
                                                                    : std::string("the output must be a .png file");
          },
          "FILE.png"));
  sub->add_option("--shadows", c.shadows, "exact (default) | map[:RES[:BIAS]] | rays[:SPP] | none")
      ->check(parsed_by("METHOD", [](const std::string& v) { ShadowSettings::parse(v); }));
  sub->add_option("--shading", c.shading, "flat | gouraud | phong (default)")
      ->check(CLI::IsMember({"flat", "gouraud", "phong"}));
  sub->add_option("--width", c.width, "image width, 1 to 16384 (default: the scene's)")
      ->check(CLI::Range(1, kMaxImageSide));
  sub->add_option("--height", c.height, "image height, 1 to 16384 (default: the scene's)")
      ->check(CLI::Range(1, kMaxImageSide));
  sub->add_option("--aa", c.aa, "samples per pixel: 1 (default), 4 or 16")->check(CLI::IsMember({1, 4, 16}));
  sub->add_flag("--lines", c.lines, "draw the visible edges and junction lines (Roberts) on top");
  sub->add_option("--attenuation", c.attenuation, "none (default) | linear:K | quadratic:A,B,C")
      ->check(parsed_by("MODEL", [](const std::string& v) { Attenuation::parse(v); }));
  sub->add_option("--ambient", c.ambient, "ambient intensity I_a (default 1)")->check(finite_number(false));
  add_threads_option(*sub, c.threads);
  return sub;
}

void run_render(const RenderCommand& c, std::ostream& out) {
  const auto start = std::chrono::steady_clock::now();
  if (static_cast<long long>(c.width) * c.height > kMaxImagePixels)
    throw UsageError("--width, --height: " + std::to_string(c.width) + " x " +
                     std::to_string(c.height) + " is more than " +
                     std::to_string(kMaxImagePixels) + " pixels");
  const Scene scene = load_scene(c.scene_file);
  RenderOptions options;
  options.width = c.width;
  options.height = c.height;
  options.shading = shading_of(c.shading);
  options.shadows = ShadowSettings::parse(c.shadows);
  options.aa = c.aa;
  options.attenuation = Attenuation::parse(c.attenuation);
  options.ambient = c.ambient;
  options.threads = c.threads;
  options.progress = progress_bar("render");
  Image image;
  RenderStats stats;
  try {
    image = render(scene, options, nullptr, &stats);
    if (c.lines) draw_hidden_lines(image, scene);
  } catch (const InvalidInput& e) {
    // Scene-level problems (a light, a body that cannot be decomposed) name the file.
    end_progress_bar();
    throw InvalidInput(c.scene_file + ": " + e.what());
  }
  end_progress_bar();
  check_interrupted();  // Ctrl-C up to here (the line overlay has no reports): no file
  io::write_png(c.output_file, image.width, image.height, image.rgb);
  const double ms =
      std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count();
  char line[256];
  std::snprintf(line, sizeof line,
                "wrote %s (%d x %d, %s, shadows %s, %d sample%s per pixel%s): %d triangles, "
                "render %.1f ms, total %.1f ms\n",
                c.output_file.c_str(), image.width, image.height, shading_name(options.shading),
                options.shadows.to_string().c_str(), c.aa, c.aa == 1 ? "" : "s",
                c.lines ? ", lines" : "", stats.triangles,
                stats.setup_ms + stats.shadows_ms + stats.raster_ms, ms);
  out << line;
}

void write_demo_render(const Scene& scene, const std::string& path, std::ostream& out) {
  RenderOptions options;
  options.shadows.method = ShadowSettings::Method::Exact;
  options.aa = 4;
  RenderStats stats;
  const Image image = render(scene, options, nullptr, &stats);
  io::write_png(path, image.width, image.height, image.rgb);
  char line[200];
  std::snprintf(line, sizeof line,
                "wrote %s (%d x %d, Phong shading, exact shadows, 4 samples per pixel, %.0f ms)\n",
                path.c_str(), image.width, image.height,
                stats.setup_ms + stats.shadows_ms + stats.raster_ms);
  out << line;
}

}  // namespace hedra::cli
