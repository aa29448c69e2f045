// Intrinsic Delaunay refinement options for the `ifem` commands: `ifem refine`, and `--refine`
// in the solver commands (distance, eigen, poisson). The refinement itself is the library's
// (solvers::prepare_surface with PrepareOptions::refine).
#pragma once

#include <string>

#include "cli.h"
#include "solvers/recipes/pipeline.h"

namespace ifem::cli {

/// The options refinement understands, appended to refine and to the solver commands:
/// --min-angle, --resolution (shown with default `resolution_default`: refine_settings()'
/// default_resolution at that command), --max-area, --max-insertions, --relax, --max-edge.
OptionGroup refine_options_group(double resolution_default);

/// The library's refinement settings from the command line: --min-angle, --resolution
/// (default `default_resolution`; × the input's mean edge length), --max-area, --max-insertions,
/// --relax ITER, --max-edge L; `need_signposts` refuses the tufted path (library message).
/// @throws UsageError on --max-edge without --relax
solvers::SurfaceRefineOptions refine_settings(const Args& args, double default_resolution,
                                              bool need_signposts);

}  // namespace ifem::cli
