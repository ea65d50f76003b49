// The hedra command: see README.md for the table of subcommands.
#include <CLI/CLI.hpp>

#include <filesystem>
#include <iostream>

#if defined(__GLIBC__)
#include <malloc.h>
#include <unistd.h>

#include <cstdlib>
#include <fstream>
#include <string>
#endif

#include "cli/clip.h"
#include "cli/decompose.h"
#include "hedra/scene/demo.h"
#include "cli/hlr.h"
#include "cli/info.h"
#include "cli/progress.h"
#include "cli/render.h"
#include "cli/shadows.h"
#include "cli/usage.h"
#include "hedra/io/mesh_io.h"
#include "hedra/io/scene_json.h"
#include "hedra/decompose/decompose.h"
#include "hedra/core/error.h"
#include "hedra/version.h"

namespace {

constexpr int kExitUsage = 2;
constexpr int kExitInvalidInput = 3;

// A large mesh's arrays (the file, its polygons, faces, half-edges, boxes) are allocated and
// freed one after another. glibc maps each block over its mmap threshold afresh and unmaps it
// on free, so every pass paid its page faults again (about a sixth of reading a 1M-triangle
// file). Up to 32 MB blocks come from the heap instead, which keeps freed memory for reuse
// (trimmed only beyond 1 GB free). A short-lived process: the memory is returned at exit.
void tune_allocator() {
#if defined(__GLIBC__)
  mallopt(M_MMAP_THRESHOLD, 32 << 20);
  mallopt(M_TRIM_THRESHOLD, 1 << 30);
  mallopt(M_TOP_PAD, 64 << 20);
#endif
}

// Transparent huge pages. A million-face mesh touches about 1.3 GB once, in blocks of every size;
// with 4 KB pages that is ~370 000 page faults: `hedra shadows` of such a mesh took 7.2 s on this
// project's 2-core virtual machine, 2.2 s of it in the kernel, and 3.2-4.7 s with 2 MB pages
// (docs/benchmarks.md, "Faces scaling"). glibc backs its heaps, thread arenas and mapped blocks
// with 2 MB pages when its tunable glibc.malloc.hugetlb=1 is set, but it reads tunables only when
// a program starts. So when the kernel gives huge pages on request ("madvise" mode) and the user
// has not chosen (GLIBC_TUNABLES names no glibc.malloc.hugetlb), the command sets the tunable and
// executes itself again once, with the same arguments (about 6 ms); if that fails it goes on as
// it is. GLIBC_TUNABLES=glibc.malloc.hugetlb=0 turns this off.
// Not under AddressSanitizer, whose allocator ignores the tunable.
void use_huge_pages(char** argv) {
#if defined(__GLIBC__) && defined(__linux__) && !defined(__SANITIZE_ADDRESS__)
  const char* found = std::getenv("GLIBC_TUNABLES");
  const std::string tunables = found != nullptr ? found : "";
  if (tunables.find("glibc.malloc.hugetlb") != std::string::npos) return;
  std::ifstream mode_file("/sys/kernel/mm/transparent_hugepage/enabled");
  std::string mode;
  std::getline(mode_file, mode);
  if (mode.find("[madvise]") == std::string::npos) return;  // "always" has them, "never" refuses
  const std::string value =
      tunables.empty() ? "glibc.malloc.hugetlb=1" : tunables + ":glibc.malloc.hugetlb=1";
  if (setenv("GLIBC_TUNABLES", value.c_str(), 1) != 0) return;
  execv("/proc/self/exe", argv);
  // exec failed: go on as we are, with the environment as it was
  if (found != nullptr) setenv("GLIBC_TUNABLES", tunables.c_str(), 1);
  else unsetenv("GLIBC_TUNABLES");
#else
  (void)argv;
#endif
}

int fail(const std::string& message, int code) {
  std::cerr << "hedra: error: " << hedra::cli::sanitize_message(message) << "\n";
  return code;
}

}  // namespace

int main(int argc, char** argv) {
  use_huge_pages(argv);
  tune_allocator();
  CLI::App app{"hedra: exact solid modeling for polyhedral scenes"};
  app.set_version_flag("--version", std::string("hedra ") + hedra::kVersion);
  app.require_subcommand(1);

  std::string info_file;
  bool info_json = false, info_matrix = false;
  double tolerance = 0;
  CLI::App* info = app.add_subcommand("info", "Report the bodies of a scene (.json) or mesh file (OFF, OBJ, STL, PLY)");
  info->add_option("file", info_file, "scene or mesh file")->required();
  info->add_flag("--json", info_json, "print JSON instead of a table");
  info->add_flag("--matrix", info_matrix, "print the body matrix of every body");

  std::string convert_in, convert_out;
  bool stl_ascii = false;
  CLI::App* convert = app.add_subcommand("convert", "Convert between OFF, OBJ, STL, PLY and scene JSON");
  convert->add_option("in", convert_in, "input scene or mesh file")->required();
  convert->add_option("out", convert_out, "output scene or mesh file (format from its extension)")
      ->required();
  convert->add_flag("--stl-ascii", stl_ascii, "write ASCII STL instead of binary");

  hedra::cli::DecomposeCommand dec;
  CLI::App* decompose = app.add_subcommand(
      "decompose", "Split non-convex bodies into convex pieces (mesh file, or every non-convex body of a scene)");
  decompose->add_option("file", dec.file, "scene or mesh file")->required();
  decompose->add_option("--method", dec.method, "planes (exact, default) | float | tetgen | cgal")
      ->check(CLI::IsMember({"planes", "float", "tetgen", "cgal"}));
  decompose->add_option("--eps", dec.epsilon, "float method: tolerance relative to the body's size")
      ->check(hedra::cli::finite_number(true));
  decompose->add_flag("--merge", dec.merge, "join adjacent pieces whose union is convex");
  decompose->add_option("-o", dec.out_dir,
                        "write one OFF file per piece into this directory (made whole or not at all)");
  decompose->add_flag("--json", dec.json, "print JSON");
  hedra::cli::add_threads_option(*decompose, dec.threads);

  hedra::cli::ClipCommand clip_args;
  CLI::App* clip = hedra::cli::add_clip_subcommand(app, clip_args);

  hedra::cli::HlrCommand hlr_args;
  CLI::App* hlr = hedra::cli::add_hlr_subcommand(app, hlr_args);

  hedra::cli::RenderCommand render_args;
  CLI::App* render = hedra::cli::add_render_subcommand(app, render_args);

  hedra::cli::ShadowsCommand shadows_args;
  CLI::App* shadows = hedra::cli::add_shadows_subcommand(app, shadows_args);

  CLI::App* demo = app.add_subcommand("demo", "Build the embedded demo scene and report on it");

  // An unknown first word is named (CLI11 would only say that a subcommand is required).
  if (argc >= 2 && argv[1][0] != '-' && argv[1][0] != '\0') {
    std::string names;
    bool known = false;
    for (const CLI::App* sub : app.get_subcommands([](CLI::App*) { return true; })) {
      names += (names.empty() ? "" : ", ") + sub->get_name();
      known = known || sub->get_name() == argv[1];
    }
    if (!known)
      return fail(std::string("unknown command '") + argv[1] + "' (expected one of: " + names + ")",
                  kExitUsage);
  }

  // One modeling tolerance for every command that reads bodies (--coplanar-tol and
  // --planarity-tol are its old names).
  for (CLI::App* sub : {info, convert, decompose, clip, hlr, render, shadows}) {
    sub->add_option("--tolerance", tolerance,
                    "merge nearly coplanar neighbouring faces of meshes read into planar faces, "
                    "moving no vertex by more than D (default 0: exact)")
        ->check(hedra::cli::finite_number(false))
        ->option_text("D");
    // Separate options, so that a usage error names the one given.
    for (const char* alias : {"--coplanar-tol", "--planarity-tol"})
      sub->add_option(alias, tolerance, "the same as --tolerance")
          ->check(hedra::cli::finite_number(false))
          ->option_text("D");
  }

  // Long commands: a progress bar on a terminal unless --quiet, and Ctrl-C stops them cleanly.
  bool quiet = false;
  for (CLI::App* sub : {hlr, render, shadows})
    sub->add_flag("--quiet", quiet, "no progress bar on stderr (it is drawn only on a terminal)");

  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    if (e.get_exit_code() == 0) return app.exit(e);  // --help, --version
    return fail(std::string(e.what()) + " (run with --help for more information)", kExitUsage);
  }

  hedra::cli::set_import_tolerance(tolerance);
  hedra::cli::set_quiet(quiet);
  if (*hlr || *render || *shadows) hedra::cli::catch_interrupts();
  // What the run builds, for the one resource error that no input check can rule out: the
  // machine running out of memory (the guards bound what an input may ask for, not what the
  // machine has).
  std::string building = "the demo scene";
  if (*info) building = "the bodies of " + info_file;
  if (*convert) building = convert_out + " from " + convert_in;
  if (*decompose) building = "the convex pieces of " + dec.file;
  if (*clip) building = "the parts of " + clip_args.segments_file + " clipped by " + clip_args.body_file;
  if (*hlr) building = "the hidden lines of " + hlr_args.scene_file;
  if (*render) building = "the image of " + render_args.scene_file;
  if (*shadows) building = "the shadows of " + shadows_args.scene_file;
  try {
    if (*info) {
      std::vector<hedra::cli::NamedBody> bodies;
      std::vector<hedra::SceneSurface> surfaces;  // a scene's open surfaces
      try {
        bodies = hedra::cli::load_bodies(info_file, &surfaces);
      } catch (const hedra::InvalidInput& e) {
        // An open surface (consistently oriented and manifold, with boundary edges) is not a
        // body, but hlr, shadows and render take it (two-sided faces): its report, exit 0.
        if (std::string(e.what()).find("not closed") != std::string::npos)
          if (const auto open = hedra::cli::open_surface(info_file)) {
            hedra::cli::print_open_surface(std::cout, *open, info_json);
            return 0;
          }
        throw;
      }
      if (info_json) {
        nlohmann::json report = hedra::cli::info_json(bodies, info_matrix);
        for (const auto& s : surfaces) report["bodies"].push_back(hedra::cli::open_surface_json(s));
        std::cout << report.dump(2, ' ', false, nlohmann::json::error_handler_t::replace) << "\n";
      } else {
        if (!bodies.empty() || surfaces.empty())
          hedra::cli::print_info_table(std::cout, bodies, info_matrix);
        for (size_t i = 0; i < surfaces.size(); ++i) {
          if (i > 0 || !bodies.empty()) std::cout << "\n";
          hedra::cli::print_open_surface(std::cout, surfaces[i], false);
        }
      }
    } else if (*convert) {
      const bool to_scene = hedra::io::is_scene_path(convert_out);
      if (!to_scene) hedra::io::format_of(convert_out);  // reject an unknown format before reading
      auto named = hedra::cli::load_bodies(convert_in);
      // hedra never writes a file it would reject: a file without bodies is one.
      if (named.empty())
        throw hedra::InvalidInput(convert_in + ": no visible body to write (every body is hidden)");
      std::vector<hedra::Body> bodies;
      for (const auto& nb : named) bodies.push_back(nb.body);
      if (to_scene) {
        // The scene as hlr, shadows and render see it (a scene file's camera, lights and
        // materials; a mesh file's default view and light), so the converted file gives the
        // same results (docs/io.md, "Round trips").
        hedra::io::write_scene(hedra::cli::load_scene(convert_in), convert_out);
      } else {
        hedra::io::WriteOptions options;
        options.stl_ascii = stl_ascii;
        for (const auto& nb : named) options.names.push_back(nb.name);
        hedra::io::write_bodies(bodies, convert_out, options);
      }
      std::cout << "wrote " << convert_out << " (" << bodies.size() << " bod"
                << (bodies.size() == 1 ? "y" : "ies") << ")\n";
    } else if (*clip) {
      hedra::cli::run_clip(clip_args, std::cout);
    } else if (*hlr) {
      hedra::cli::run_hlr(hlr_args, std::cout);
    } else if (*render) {
      hedra::cli::run_render(render_args, std::cout);
    } else if (*shadows) {
      hedra::cli::run_shadows(shadows_args, std::cout);
    } else if (*decompose) {
      hedra::cli::run_decompose(dec, std::cout);
    } else if (*demo) {
      std::cout << "hedra demo: a ground slab with an L-shaped block, a box and a pyramid\n\n";
      const hedra::Scene scene = hedra::demo_scene();
      std::vector<hedra::cli::NamedBody> bodies;
      for (const hedra::SceneBody* b : scene.visible_bodies())
        bodies.push_back({b->name, b->body, b->lod_note});
      hedra::cli::print_info_table(std::cout, bodies, false);
      const hedra::Decomposition pieces = hedra::decompose(scene.get("L").body);
      std::cout << "\nconvex decomposition of L (exact plane splitting): " << pieces.pieces.size()
                << " pieces, " << pieces.cuts << " cut(s)\n";
      for (size_t i = 0; i < pieces.pieces.size(); ++i) {
        const hedra::Body& p = pieces.pieces[i];
        std::cout << "  piece " << i << ": " << p.face_count() << " faces, volume " << p.volume()
                  << ", box " << p.bbox().min().transpose() << " .. " << p.bbox().max().transpose()
                  << "\n";
      }
      std::cout << "\n";
      hedra::cli::write_demo_render(scene, "demo-render.png", std::cout);
      hedra::cli::write_demo_hidden_lines(scene, "demo-hidden-lines.svg", std::cout);
      hedra::cli::write_demo_shadows(scene, "demo-shadows.svg", std::cout);
    }
  } catch (const hedra::Cancelled& e) {
    // Ctrl-C (or a cancelled pass): outputs are all-or-nothing, so nothing was written.
    hedra::cli::end_progress_bar();
    std::cerr << "hedra: "
              << (hedra::cli::interrupted() ? std::string("interrupted")
                                            : hedra::cli::sanitize_message(e.what()))
              << "; no output written\n";
    return hedra::cli::kExitInterrupted;
  } catch (const hedra::cli::UsageError& e) {
    return fail(e.what(), kExitUsage);
  } catch (const hedra::InvalidInput& e) {
    return fail(e.what(), kExitInvalidInput);
  } catch (const hedra::IoError& e) {
    return fail(e.what(), kExitInvalidInput);
  } catch (const hedra::InternalError& e) {
    std::cerr << "hedra: internal error: " << hedra::cli::sanitize_message(e.what()) << "\n";
    return 1;
  } catch (const std::bad_alloc&) {
    // A resource error, not a bug: the input is within hedra's limits (docs/io.md) but this
    // machine has not the memory to build its result.
    return fail("out of memory while building " + building +
                    " (the input is valid but needs more memory than is available)",
                kExitInvalidInput);
  } catch (const std::exception& e) {
    std::cerr << "hedra: internal error: " << hedra::cli::sanitize_message(e.what()) << "\n";
    return 1;
  }
  return 0;
}
