// `--solver direct|multigrid|auto` of `ifem distance` and `ifem poisson` (solvers::SolverChoice).
#pragma once

#include "cli.h"
#include "solvers/scalar/solver_choice.h"

namespace ifem::cli {

/// The --solver option's spec, with its help text.
OptionSpec solver_option();

/// The choice --solver asks for (default direct). @throws UsageError on another name
solvers::SolverChoice solver_choice(const Args& args);

}  // namespace ifem::cli
