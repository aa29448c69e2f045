// Intrinsic Delaunay refinement options for the `ifem` commands: `ifem refine`, and `--refine`
// in the solver commands (distance, eigen, poisson). The refinement itself is the library's
// (solvers::prepare_surface with PrepareOptions::refine).
#pragma once

#include <set>
#include <string>

#include "cli.h"
#include "solvers/pipeline.h"

namespace ifem::cli {

/// The options refinement understands: --min-angle, --resolution, --max-area,
/// --max-insertions, --relax, --max-edge.
extern const std::set<std::string> kRefineOptions;
/// Help text for them (and for the --refine flag of the solver commands).
extern const char* const kRefineHelp;

/// The library's refinement settings from the command line: --min-angle (default 25),
/// --resolution (default `default_resolution`; × the input's mean edge length), --max-area,
/// --max-insertions, --relax ITER, --max-edge L; `need_signposts` refuses the tufted path.
/// @throws InvalidInput on values out of range (RefineSettings::validate)
solvers::RefineSettings refine_settings(const Args& args, double default_resolution,
                                        bool need_signposts);

}  // namespace ifem::cli
