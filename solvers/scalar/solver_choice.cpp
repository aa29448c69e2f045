#include "solvers/scalar/solver_choice.h"

#include <algorithm>

#include "fem/prolongation.h"
#include "intrinsic/core/errors.h"
#include "intrinsic/simplify/simplify.h"

namespace ifem::solvers {

void HierarchyOptions::validate() const {
  if (!(level_ratio > 0.0 && level_ratio < 1.0)) {
    throw InvalidInput("HierarchyOptions: level_ratio must be in (0, 1)");
  }
  if (coarsest_vertices < 1) throw InvalidInput("HierarchyOptions: coarsest_vertices must be ≥ 1");
}

std::vector<SparseMatrix> simplification_hierarchy(const intrinsic::IntrinsicTriangulation& tri,
                                                   const HierarchyOptions& options) {
  options.validate();
  std::vector<SparseMatrix> chain;
  // Eigen 3.4's SparseMatrix is copied, not moved, when a vector grows (its move is not
  // noexcept): room for every level up front (each level keeps at most 0.6 of the vertices).
  chain.reserve(64);
  intrinsic::IntrinsicTriangulation coarsest;  // the last level made (tri itself is not copied)
  const intrinsic::IntrinsicTriangulation* level = &tri;
  while (level->n_vertices() > options.coarsest_vertices) {
    intrinsic::SimplifyOptions s;
    s.target_vertices = std::max(options.coarsest_vertices,
                                 Index(options.level_ratio * double(level->n_vertices())));
    intrinsic::Simplification coarse = intrinsic::simplify(*level, s);
    // short of the target: vertices simplify() could not remove; a level that keeps most of
    // them is not worth its cycle, and the next one would not do better
    const bool stuck = coarse.coarse.n_vertices() > s.target_vertices;
    if (stuck && double(coarse.coarse.n_vertices()) > 0.6 * double(level->n_vertices())) break;
    chain.push_back(fem::prolongation(coarse));
    coarsest = std::move(coarse.coarse);
    level = &coarsest;
    if (stuck) break;
  }
  return chain;
}

HierarchyProvider default_hierarchy_provider() {
  return [](const intrinsic::IntrinsicTriangulation& tri) { return simplification_hierarchy(tri); };
}

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
