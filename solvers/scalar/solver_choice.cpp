#include "solvers/scalar/solver_choice.h"

#include "intrinsic/core/errors.h"

namespace ifem::solvers {

HierarchyProvider default_hierarchy_provider() { return {}; }

HierarchyProvider SolverChoice::provider() const {
  return hierarchy ? hierarchy : default_hierarchy_provider();
}

bool SolverChoice::use_multigrid(Index n_vertices) const {
  switch (kind) {
    case LinearSolverKind::kDirect:
      return false;
    case LinearSolverKind::kMultigrid:
      if (!provider()) {
        throw InvalidInput(
            "solver multigrid: no multigrid hierarchy is available in this build (no default "
            "hierarchy provider; pass one in SolverChoice::hierarchy), use the direct solver");
      }
      return true;
    case LinearSolverKind::kAuto:
      return n_vertices >= auto_multigrid_vertices && bool(provider());
  }
  return false;
}

void SolverChoice::validate() const {
  multigrid.validate();
  if (auto_multigrid_vertices < 1) {
    throw InvalidInput("SolverChoice: auto_multigrid_vertices must be ≥ 1");
  }
}

LinearSolverKind parse_linear_solver(const std::string& name) {
  if (name == "direct") return LinearSolverKind::kDirect;
  if (name == "multigrid") return LinearSolverKind::kMultigrid;
  if (name == "auto") return LinearSolverKind::kAuto;
  throw InvalidInput("solver: '" + name + "' is not one of direct, multigrid, auto");
}

const char* linear_solver_name(LinearSolverKind kind) {
  switch (kind) {
    case LinearSolverKind::kDirect:
      return "direct";
    case LinearSolverKind::kMultigrid:
      return "multigrid";
    case LinearSolverKind::kAuto:
      return "auto";
  }
  return "direct";
}

}  // namespace ifem::solvers
