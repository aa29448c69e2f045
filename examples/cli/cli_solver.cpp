#include "cli_solver.h"

#include <string>

#include "intrinsic/core/errors.h"

namespace ifem::cli {

OptionSpec solver_option() {
  return text("solver", "KIND")
      .defaults_to("direct")
      .explain(
          "the linear solver: direct (sparse Cholesky factors: fast to solve, memory\n"
          "growing faster than the mesh), multigrid (conjugate gradients with\n"
          "V-cycles on a hierarchy of intrinsic simplifications of the triangulation,\n"
          "see `ifem simplify`: memory linear in the mesh, answers to a relative\n"
          "residual of 1e-10; the heat method then continues in stages from the frontier\n"
          "of the heat it resolves, each a direct solve on a band around it), or auto\n"
          "(poisson: multigrid from 2.5M vertices on, where the\n"
          "direct factors take a third of a 24 GiB machine; distance: direct)");
}

solvers::SolverChoice solver_choice(const Args& args) {
  solvers::SolverChoice c;
  if (!args.has("solver")) return c;
  try {
    c.kind = solvers::parse_linear_solver(args.get("solver"));
  } catch (const InvalidInput& e) {
    throw UsageError(std::string("--") + e.what());
  }
  return c;
}

}  // namespace ifem::cli
