#include "cli/decompose.h"

#include <cctype>
#include <chrono>
#include <cstdio>
#include <filesystem>

#include <nlohmann/json.hpp>

#include "cli/info.h"
#include "cli/usage.h"
#include "hedra/baselines/decompose_baselines.h"
#include "hedra/io/atomic_file.h"
#include "hedra/io/mesh_io.h"
#include "hedra/io/scene_json.h"
#include "hedra/mesh/convexity.h"
#include "hedra/decompose/decompose.h"
#include "hedra/core/error.h"
#ifdef HEDRA_HAVE_TETGEN
#include "hedra/tetgen/tetgen_decompose.h"
#endif

namespace hedra::cli {
namespace {

// A body name as part of a file name: letters, digits, '.', '-', '_' and '#' kept, anything
// else (a '/', a space, a control character) becomes '_', so a name cannot leave the directory.
std::string file_name_part(const std::string& name) {
  std::string out;
  for (unsigned char c : name)
    out += std::isalnum(c) || c == '-' || c == '_' || c == '#' || (c == '.' && !out.empty())
               ? static_cast<char>(c)
               : '_';
  return out.substr(0, 100);
}

}  // namespace

void run_decompose(const DecomposeCommand& c, std::ostream& out) {
#ifndef HEDRA_HAVE_TETGEN
  if (c.method == "tetgen") throw InvalidInput("this hedra was built without TetGen");
#endif
  if (!c.out_dir.empty()) {
    std::error_code ec;
    if (std::filesystem::exists(c.out_dir, ec) && !std::filesystem::is_directory(c.out_dir, ec))
      throw IoError(c.out_dir + ": -o needs a directory, and this is an existing file");
  }
  std::vector<NamedBody> bodies = load_bodies(c.file);
  // A scene: every non-convex body. A mesh file: every body.
  const bool scene = io::is_scene_path(c.file);
  // The piece files, written together at the end (all or none).
  std::vector<std::pair<std::string, std::string>> piece_files;
  nlohmann::ordered_json results = nlohmann::ordered_json::array();
  for (const NamedBody& nb : bodies) {
    if (scene && is_convex(nb.body)) continue;
    DecomposeOptions options;
    options.threads = c.threads;
    options.merge = c.merge;
    const auto start = std::chrono::steady_clock::now();
    Decomposition d;
    if (c.method == "planes") d = decompose(nb.body, options);
    if (c.method == "float") {
      try {
        d = decompose_float(nb.body, c.epsilon, options);
      } catch (const DecompositionFailed& e) {
        // The floating-point baseline gives up on inputs it cannot handle: a property of the
        // input for this method, reported like other bad input.
        throw InvalidInput(c.file + ": body '" + nb.name + "': " + e.what());
      }
    }
    if (c.method == "cgal") d = decompose_cgal(nb.body);
#ifdef HEDRA_HAVE_TETGEN
    if (c.method == "tetgen") d = tetgen::decompose(nb.body);
#endif
    if (c.merge && (c.method == "tetgen" || c.method == "cgal")) d.pieces = merge_convex(d.pieces, &d.merges);
    const double ms =
        std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count();
    double volume = 0;
    bool all_convex = true;
    for (const Body& p : d.pieces) {
      volume += p.volume();
      all_convex = all_convex && is_convex(p);
    }
    if (!c.out_dir.empty()) {
      const std::string prefix = bodies.size() == 1 ? "" : file_name_part(nb.name) + "_";
      for (size_t i = 0; i < d.pieces.size(); ++i) {
        char name[32];
        std::snprintf(name, sizeof name, "piece_%03zu.off", i);
        piece_files.emplace_back(prefix + name, io::format_bodies({d.pieces[i]}, io::MeshFormat::Off));
      }
    }
    nlohmann::ordered_json j;
    j["name"] = nb.name;
    j["method"] = c.method;
    j["pieces"] = d.pieces.size();
    if (c.merge) j["merged"] = d.merges;
    // The pieces of a Boolean's exact result, not of its rounding (DecomposeOptions).
    if (c.method == "planes") j["from_exact_solid"] = d.from_exact_solid;
    j["input_volume"] = nb.body.volume();
    j["pieces_volume"] = volume;
    j["all_convex"] = all_convex;
    j["ms"] = ms;
    results.push_back(j);
  }
  if (!c.out_dir.empty()) {
    io::OutputTransaction outputs;
    outputs.add_directory(c.out_dir, piece_files);
    outputs.commit();
  }
  if (c.json) {
    out << (results.size() == 1 ? results[0] : results)
               .dump(2, ' ', false, nlohmann::ordered_json::error_handler_t::replace)
        << "\n";
    return;
  }
  // The name is written as a string (no length limit, never cut into the next row).
  auto pad = [](std::string name) {
    name = sanitize_message(name);
    return name.size() >= 12 ? name : name + std::string(12 - name.size(), ' ');
  };
  char line[256];
  std::snprintf(line, sizeof line, "%-7s %7s %14s %14s %7s %10s\n", "method", "pieces",
                "input volume", "pieces volume", "convex", "ms");
  out << pad("body") << " " << line;
  for (const auto& j : results) {
    std::snprintf(line, sizeof line, "%-7s %7d %14.10g %14.10g %7s %10.3f\n", c.method.c_str(),
                  j["pieces"].get<int>(), j["input_volume"].get<double>(),
                  j["pieces_volume"].get<double>(), j["all_convex"].get<bool>() ? "yes" : "no",
                  j["ms"].get<double>());
    out << pad(j["name"].get<std::string>()) << " " << line;
  }
  if (results.empty()) out << "(no non-convex body)\n";
}

}  // namespace hedra::cli
