// Progress bars and Ctrl-C for the long commands (hlr, render, shadows): a bar on stderr only
// when stderr is a terminal (and not --quiet), and SIGINT turned into a clean cancellation
// (hedra::Cancelled from the running pass, no output written, exit code 130).
#pragma once

#include <string>

#include "hedra/core/progress.h"

namespace hedra::cli {

/// Exit code of a command stopped by Ctrl-C (128 + SIGINT, as shells report it).
constexpr int kExitInterrupted = 130;

/// Installs the SIGINT handler: the first Ctrl-C sets a flag that progress callbacks and
/// check_interrupted() turn into hedra::Cancelled; a second one ends the process at once
/// (the default action is restored by the first).
void catch_interrupts();

/// Whether Ctrl-C was pressed since catch_interrupts().
bool interrupted();

/// Throws hedra::Cancelled when interrupted(): called before the outputs are committed, so a
/// Ctrl-C during the last steps still leaves no file.
void check_interrupted();

/// --quiet: no progress bar even on a terminal.
void set_quiet(bool quiet);

/// A ProgressCallback that draws "label [#####.....]  42 %" on stderr when stderr is a terminal
/// and not quiet, and returns false once interrupted. Cost O(1) per call.
ProgressCallback progress_bar(const std::string& label);

/// Clears the progress bar's line, if one was drawn.
void end_progress_bar();

}  // namespace hedra::cli
