// `ifem distance --exact`: exact polyhedral geodesic distance (window propagation) instead of
// the heat method, on the same prepared surface (manifold, --tufted, --refine).
#pragma once

#include <vector>

#include "cli.h"
#include "results.h"

namespace ifem::cli {

/// The body of `ifem distance MESH --exact --source I[,J,...] -o OUT`: refuses the heat method's
/// options and the forms --exact does not take (--curves, --sources-batch), prepares the surface
/// (refined when --refine), writes one exact distance per input vertex, and prints the windows
/// and time. --memory-budget GB bounds the windows (default: half the physical memory);
/// --mollify defaults to 0 (the distances are those of the input's own lengths).
/// @throws UsageError on an option --exact does not take
int run_exact_distance(const Args& args, const ResultOutput& out);

/// --paths-from I,J,... and --paths-out FILE (.obj/.ply): the exact geodesics back to the nearest
/// source, for the distance command's option table.
std::vector<OptionSpec> exact_path_options();

/// --paths-from and --paths-out together, only with --exact and without --refine.
/// @throws UsageError otherwise
void check_path_options(const Args& args);

/// The --exact flag's help text (for the distance command's option table).
const char* exact_flag_help();

}  // namespace ifem::cli
