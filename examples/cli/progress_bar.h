// The terminal progress bar of the `ifem` command: the library's progress fractions
// (ifem::ProgressCallback) drawn as one line on stderr, only where a person is watching.
#pragma once

#include "intrinsic/core/progress.h"
#include "options.h"

namespace ifem::cli {

/// The callback a command hands to the library for its long stages. Empty (nothing drawn,
/// nothing costs) when --quiet was given or stderr is not a terminal (isatty), so pipes, files
/// and CI logs never see it; stdout is never written. Otherwise it draws
/// "ifem: <stage> [#####.....]  42%" on stderr, overwritten in place (carriage return):
///  - only once the command has run for 2 s (environment IFEM_PROGRESS_DELAY=seconds changes
///    the delay; 0 draws from the start), so short commands print no bar at all;
///  - at most 10 times per second;
///  - erased when a stage reports 1, before any other stderr line (progress(), errors), and at
///    the end of the command.
ProgressCallback progress_bar(const Args& args);

/// Erases the bar if it is shown (the cursor goes back to the start of an empty line).
void clear_progress_bar();

}  // namespace ifem::cli
