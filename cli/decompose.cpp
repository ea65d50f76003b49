#include "cli/decompose.h"

#include <chrono>
#include <cstdio>
#include <filesystem>

#include <nlohmann/json.hpp>

#include "cli/info.h"
#include "hedra/baselines/decompose_baselines.h"
#include "hedra/io/mesh_io.h"
#include "hedra/mesh/convexity.h"
#include "hedra/decompose/decompose.h"
#include "hedra/core/error.h"
#ifdef HEDRA_HAVE_TETGEN
#include "hedra/tetgen/tetgen_decompose.h"
#endif

namespace hedra::cli {

void run_decompose(const DecomposeCommand& c, std::ostream& out) {
  if (c.method != "planes" && c.method != "float" && c.method != "tetgen" && c.method != "cgal")
    throw InvalidInput("unknown method '" + c.method + "' (expected planes, float, tetgen, cgal)");
#ifndef HEDRA_HAVE_TETGEN
  if (c.method == "tetgen") throw InvalidInput("this hedra was built without TetGen");
#endif
  std::vector<NamedBody> bodies = load_bodies(c.file);
  // A scene: every non-convex body. A mesh file: every body.
  const bool scene = c.file.size() > 5 && c.file.substr(c.file.size() - 5) == ".json";
  nlohmann::ordered_json results = nlohmann::ordered_json::array();
  for (const NamedBody& nb : bodies) {
    if (scene && is_convex(nb.body)) continue;
    DecomposeOptions options;
    options.threads = c.threads;
    options.merge = c.merge;
    const auto start = std::chrono::steady_clock::now();
    Decomposition d;
    if (c.method == "planes") d = decompose(nb.body, options);
    if (c.method == "float") d = decompose_float(nb.body, c.epsilon, options);
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
      std::filesystem::create_directories(c.out_dir);
      const std::string prefix = bodies.size() == 1 ? "" : nb.name + "_";
      for (size_t i = 0; i < d.pieces.size(); ++i) {
        char name[32];
        std::snprintf(name, sizeof name, "piece_%03zu.off", i);
        io::write_bodies({d.pieces[i]}, (std::filesystem::path(c.out_dir) / (prefix + name)).string());
      }
    }
    nlohmann::ordered_json j;
    j["name"] = nb.name;
    j["method"] = c.method;
    j["pieces"] = d.pieces.size();
    if (c.merge) j["merged"] = d.merges;
    j["input_volume"] = nb.body.volume();
    j["pieces_volume"] = volume;
    j["all_convex"] = all_convex;
    j["ms"] = ms;
    results.push_back(j);
  }
  if (c.json) {
    out << (results.size() == 1 ? results[0] : results).dump(2) << "\n";
    return;
  }
  char line[256];
  std::snprintf(line, sizeof line, "%-12s %-7s %7s %14s %14s %7s %10s\n", "body", "method", "pieces",
                "input volume", "pieces volume", "convex", "ms");
  out << line;
  for (const auto& j : results) {
    std::snprintf(line, sizeof line, "%-12s %-7s %7d %14.10g %14.10g %7s %10.3f\n",
                  j["name"].get<std::string>().c_str(), c.method.c_str(), j["pieces"].get<int>(),
                  j["input_volume"].get<double>(), j["pieces_volume"].get<double>(),
                  j["all_convex"].get<bool>() ? "yes" : "no", j["ms"].get<double>());
    out << line;
  }
  if (results.empty()) out << "(no non-convex body)\n";
}

}  // namespace hedra::cli
