// The hedra command: see README.md for the table of subcommands.
#include <CLI/CLI.hpp>

#include <filesystem>
#include <iostream>

#include "cli/demo.h"
#include "cli/info.h"
#include "io/mesh_io.h"
#include "io/scene_json.h"
#include "kernel/error.h"

namespace {

constexpr int kExitUsage = 2;
constexpr int kExitInvalidInput = 3;

}  // namespace

int main(int argc, char** argv) {
  CLI::App app{"hedra: exact solid modeling for polyhedral scenes"};
  app.require_subcommand(1);

  std::string info_file;
  bool info_json = false, info_matrix = false;
  double coplanar_tolerance = 0, planarity_tolerance = -1;
  CLI::App* info = app.add_subcommand("info", "Report the bodies of a scene (.json) or mesh file (OFF, OBJ, STL, PLY)");
  info->add_option("file", info_file, "mesh file")->required();
  info->add_flag("--json", info_json, "print JSON instead of a table");
  info->add_flag("--matrix", info_matrix, "print the body matrix of every body");
  for (CLI::App* sub : {info}) {
    sub->add_option("--coplanar-tol", coplanar_tolerance,
                    "merge neighbouring faces within this distance of one plane (default: exact)");
    sub->add_option("--planarity-tol", planarity_tolerance,
                    "accept faces this far from planar (default: exact up to rounding)");
  }

  std::string convert_in, convert_out;
  bool stl_ascii = false;
  CLI::App* convert = app.add_subcommand("convert", "Convert between OFF, OBJ, STL, PLY and scene JSON");
  convert->add_option("in", convert_in, "input mesh")->required();
  convert->add_option("out", convert_out, "output mesh (format from its extension)")->required();
  convert->add_flag("--stl-ascii", stl_ascii, "write ASCII STL instead of binary");
  convert->add_option("--coplanar-tol", coplanar_tolerance, "merge tolerance (default: exact)");
  convert->add_option("--planarity-tol", planarity_tolerance, "planarity tolerance");

  CLI::App* demo = app.add_subcommand("demo", "Build the embedded demo scene and report on it");

  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    int code = app.exit(e);
    return code == 0 ? 0 : kExitUsage;
  }

  try {
    if (*info) {
      auto bodies = hedra::cli::load_bodies(info_file, coplanar_tolerance, planarity_tolerance);
      if (info_json)
        std::cout << hedra::cli::info_json(bodies, info_matrix).dump(2) << "\n";
      else
        hedra::cli::print_info_table(std::cout, bodies, info_matrix);
    } else if (*convert) {
      const bool to_scene = hedra::io::is_scene_path(convert_out);
      if (!to_scene) hedra::io::format_of(convert_out);  // reject an unknown format before reading
      auto named = hedra::cli::load_bodies(convert_in, coplanar_tolerance, planarity_tolerance);
      std::vector<hedra::Body> bodies;
      for (const auto& nb : named) bodies.push_back(nb.body);
      if (to_scene) {
        hedra::Scene scene;
        for (const auto& nb : named) scene.add(nb.name, nb.body);
        hedra::io::write_scene(scene, convert_out);
      } else {
        hedra::io::WriteOptions options;
        options.stl_ascii = stl_ascii;
        hedra::io::write_bodies(bodies, convert_out, options);
      }
      std::cout << "wrote " << convert_out << " (" << bodies.size() << " bod"
                << (bodies.size() == 1 ? "y" : "ies") << ")\n";
    } else if (*demo) {
      std::cout << "hedra demo: a ground slab with an L-shaped block, a box and a pyramid\n\n";
      const hedra::Scene scene = hedra::cli::demo_scene();
      std::vector<hedra::cli::NamedBody> bodies;
      for (const hedra::SceneBody* b : scene.visible_bodies())
        bodies.push_back({b->name, b->body, b->lod_note});
      hedra::cli::print_info_table(std::cout, bodies, false);
    }
  } catch (const hedra::InvalidInput& e) {
    std::cerr << "hedra: error: " << e.what() << "\n";
    return kExitInvalidInput;
  } catch (const hedra::IoError& e) {
    std::cerr << "hedra: error: " << e.what() << "\n";
    return kExitInvalidInput;
  } catch (const std::exception& e) {
    std::cerr << "hedra: internal error: " << e.what() << "\n";
    return 1;
  }
  return 0;
}
