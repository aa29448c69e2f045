// `ifem distance --signed`: signed distance to curves (--curves) or oriented points (--points)
// by the signed heat method (solvers/recipes/signed_distance.h).
#pragma once

#include <string>
#include <vector>

#include "cli.h"
#include "results.h"

namespace ifem::cli {

/// --signed, --points FILE, --level-set MODE, for distance's option group.
std::vector<OptionSpec> signed_options();

/// The --signed paragraph of distance's help (what it computes, the sign convention, the
/// points file).
std::string signed_help();

/// Refuses, with a UsageError, --points / --level-set without --signed and, with --signed, the
/// options it cannot use (--source, --sources-batch, --correction-steps, --mixed-precision;
/// --refine with --points) and a missing or doubled source (--curves or --points, one of them).
/// Call before any work.
void check_signed_options(const Args& args);

/// Runs `distance --signed` (after check_signed_options()) and writes OUT.
int run_signed(const Args& args, const ResultOutput& out);

}  // namespace ifem::cli
