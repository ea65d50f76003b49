#include "cli/progress.h"

#include <unistd.h>

#include <csignal>
#include <cstdio>

namespace hedra::cli {
namespace {

volatile std::sig_atomic_t g_interrupted = 0;
bool g_quiet = false;
bool g_drawn = false;

void on_sigint(int) {
  g_interrupted = 1;
  std::signal(SIGINT, SIG_DFL);  // a second Ctrl-C ends the process
}

}  // namespace

void catch_interrupts() { std::signal(SIGINT, on_sigint); }

bool interrupted() { return g_interrupted != 0; }

void check_interrupted() {
  if (interrupted()) throw Cancelled("interrupted");
}

void set_quiet(bool quiet) { g_quiet = quiet; }

ProgressCallback progress_bar(const std::string& label) {
  const bool draw = !g_quiet && isatty(STDERR_FILENO) == 1;
  return [draw, label, shown = -1](double done) mutable {
    if (interrupted()) return false;
    if (!draw) return true;
    const int percent = static_cast<int>(100 * (done < 0 ? 0 : done > 1 ? 1 : done));
    if (percent == shown) return true;
    shown = percent;
    constexpr int kWidth = 30;
    char bar[kWidth + 1];
    const int full = percent * kWidth / 100;
    for (int i = 0; i < kWidth; ++i) bar[i] = i < full ? '#' : '.';
    bar[kWidth] = '\0';
    std::fprintf(stderr, "\r%s [%s] %3d %%", label.c_str(), bar, percent);
    std::fflush(stderr);
    g_drawn = true;
    return true;
  };
}

void end_progress_bar() {
  if (!g_drawn) return;
  std::fprintf(stderr, "\r\033[K");
  std::fflush(stderr);
  g_drawn = false;
}

}  // namespace hedra::cli
