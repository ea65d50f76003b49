#include "cli/distributed_study.h"

#include <fcntl.h>
#include <spawn.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <vector>

#include "hedra/core/error.h"

extern char** environ;

namespace hedra::cli {
namespace {

namespace fs = std::filesystem;

// Imports the module first, so that a missing module or a missing Dask is one line and exit 3
// rather than a traceback.
constexpr const char* kBootstrap =
    "import sys\n"
    "try:\n"
    "    import hedra.distributed as d\n"
    "except Exception as e:\n"
    "    sys.stderr.write('the distributed sun study needs the hedra Python module and Dask "
    "(python3-distributed): ' + (' '.join(str(e).split()) or type(e).__name__) + '\\n')\n"
    "    sys.exit(3)\n"
    "sys.exit(d.main(sys.argv[1:]))\n";

// The folder holding the hedra package that belongs to this executable: build/python next to
// build/cli/hedra, lib/python3*/{site,dist}-packages under the install prefix. Empty if none.
std::string module_dir() {
  std::error_code ec;
  const fs::path exe = fs::read_symlink("/proc/self/exe", ec);
  if (ec) return {};
  const fs::path bin = exe.parent_path();
  std::vector<fs::path> candidates{bin / "python", bin / "../python",
                                   bin / "../lib/python3/dist-packages"};
  for (const auto& entry : fs::directory_iterator(bin / "../lib", ec))
    if (entry.path().filename().string().rfind("python3", 0) == 0)
      for (const char* sub : {"site-packages", "dist-packages"})
        candidates.push_back(entry.path() / sub);
  for (const fs::path& c : candidates)
    if (fs::exists(c / "hedra" / "distributed.py", ec)) return fs::weakly_canonical(c, ec).string();
  return {};
}

// A new empty file in the temporary folder; removed by the destructor.
struct TempFile {
  std::string path;
  explicit TempFile(const char* tag) {
    std::string pattern = (fs::temp_directory_path() / (std::string("hedra-") + tag + "-XXXXXX")).string();
    const int fd = ::mkstemp(pattern.data());
    if (fd < 0)
      throw IoError("cannot create a temporary file in " + fs::temp_directory_path().string() +
                    " (" + std::strerror(errno) + ")");
    ::close(fd);
    path = pattern;
  }
  ~TempFile() { ::unlink(path.c_str()); }
  TempFile(const TempFile&) = delete;
  TempFile& operator=(const TempFile&) = delete;
  std::string read() const {
    std::ifstream in(path, std::ios::binary);
    std::ostringstream text;
    text << in.rdbuf();
    return text.str();
  }
};

std::string last_line(const std::string& text) {
  std::istringstream in(text);
  std::string line, last;
  while (std::getline(in, line))
    if (line.find_first_not_of(" \t\r") != std::string::npos) last = line;
  return last;
}

}  // namespace

nlohmann::json distributed_sun_study(const std::string& scene_file,
                                     const SunStudyOptions& options, const DaskTarget& target) {
  const char* python_env = std::getenv("HEDRA_PYTHON");
  const std::string python = python_env && *python_env ? python_env : "/usr/bin/python3";
  TempFile out("study"), log("log");

  char step[40];
  std::snprintf(step, sizeof step, "%.17g", options.step_minutes);
  std::vector<std::string> args{python,
                                "-c",
                                kBootstrap,
                                "shadows",
                                scene_file,
                                "--sun-hours",
                                options.start.to_string(),
                                options.end.to_string(),
                                step,
                                "--out",
                                out.path};
  if (target.workers > 0) {
    args.insert(args.end(), {"--workers", std::to_string(target.workers)});
  } else {
    args.insert(args.end(), {"--scheduler", target.scheduler});
  }
  if (!options.grid_body.empty()) {
    char spacing[40];
    std::snprintf(spacing, sizeof spacing, "%.17g", options.grid_spacing);
    args.insert(args.end(),
                {"--grid", options.grid_body, std::to_string(options.grid_face), spacing});
  }

  // The environment, with the module's folder ahead of PYTHONPATH.
  std::vector<std::string> env;
  std::string python_path = module_dir();
  for (char** e = environ; *e; ++e) {
    const std::string kv = *e;
    if (kv.rfind("PYTHONPATH=", 0) == 0) {
      const std::string old = kv.substr(11);
      if (!old.empty()) python_path += (python_path.empty() ? "" : ":") + old;
    } else {
      env.push_back(kv);
    }
  }
  if (!python_path.empty()) env.push_back("PYTHONPATH=" + python_path);

  std::vector<char*> argv, envp;
  for (std::string& a : args) argv.push_back(a.data());
  argv.push_back(nullptr);
  for (std::string& e : env) envp.push_back(e.data());
  envp.push_back(nullptr);

  // Dask's own messages go to the log; only its last line is shown, and only on failure.
  posix_spawn_file_actions_t actions;
  posix_spawn_file_actions_init(&actions);
  posix_spawn_file_actions_addopen(&actions, 1, log.path.c_str(), O_WRONLY | O_TRUNC, 0);
  posix_spawn_file_actions_adddup2(&actions, 1, 2);
  pid_t pid = 0;
  const int spawned = posix_spawnp(&pid, python.c_str(), &actions, nullptr, argv.data(), envp.data());
  posix_spawn_file_actions_destroy(&actions);
  if (spawned != 0)
    throw InvalidInput("the distributed sun study cannot run " + python + " (" +
                       std::strerror(spawned) + "); it needs Python 3 with python3-distributed");
  int status = 0;
  while (::waitpid(pid, &status, 0) < 0)
    if (errno != EINTR) throw IoError(std::string("waitpid: ") + std::strerror(errno));

  if (!WIFEXITED(status) || WEXITSTATUS(status) != 0) {
    std::string message = last_line(log.read());
    if (message.empty())
      message = WIFEXITED(status) ? python + " exited with status " +
                                        std::to_string(WEXITSTATUS(status))
                                  : python + " was killed by signal " +
                                        std::to_string(WTERMSIG(status));
    // The caller names the scene file.
    if (message.rfind(scene_file + ": ", 0) == 0) message.erase(0, scene_file.size() + 2);
    throw InvalidInput(message);
  }
  try {
    nlohmann::json study = nlohmann::json::parse(out.read());
    sun_study_summary(study);  // the fields the command reads are there
    return study;
  } catch (const nlohmann::json::exception& e) {
    throw InvalidInput(std::string("the distributed sun study returned malformed JSON (") +
                       e.what() + ")");
  }
}

std::string sun_study_summary(const nlohmann::json& study) {
  int up = 0;
  for (const auto& s : study.at("steps")) up += s.at("sun_up").get<bool>();
  double lo = 1e300, hi = 0;
  for (const auto& f : study.at("faces")) {
    const double h = f.at("sun_hours").get<double>();
    lo = std::min(lo, h);
    hi = std::max(hi, h);
  }
  char buf[256];
  std::snprintf(buf, sizeof buf,
                "  sun study: %zu steps from %s to %s, sun up at %d; hours of direct sun per "
                "face from %.3g to %.3g\n",
                study.at("steps").size(), study.at("start").get<std::string>().c_str(),
                study.at("end").get<std::string>().c_str(), up, lo, hi);
  return buf;
}

}  // namespace hedra::cli
