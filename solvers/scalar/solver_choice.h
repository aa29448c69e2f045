// Which linear solver a scalar PDE (Poisson, the heat method) runs on: a direct Cholesky factor
// or multigrid-preconditioned conjugate gradients (solvers/linalg/multigrid.h) on a hierarchy of
// prolongations that a provider builds from the triangulation.
#pragma once

#include <functional>
#include <memory>
#include <string>
#include <vector>

#include "intrinsic/core/triangulation.h"
#include "solvers/linalg/multigrid.h"

namespace ifem::solvers {

/// The linear solver of a scalar PDE.
enum class LinearSolverKind {
  kDirect,     ///< sparse Cholesky (CholeskySolver)
  kMultigrid,  ///< PCG with V-cycles (MultigridSolver) on a hierarchy from the provider
  kAuto,       ///< kDirect below SolverChoice::auto_multigrid_vertices or without a provider
};

/// Builds the prolongation chain P₀ (#V × n₁), P₁ (n₁ × n₂), … of a triangulation (vertex ids of
/// the triangulation as given: rows of P₀ are its vertices; each P piecewise linear, rows
/// summing to 1).
using HierarchyProvider =
    std::function<std::vector<SparseMatrix>(const intrinsic::IntrinsicTriangulation&)>;

/// Options of simplification_hierarchy().
struct HierarchyOptions {
  /// Each level keeps this fraction of the previous level's vertices (intrinsic::simplify's
  /// ratio), in (0, 1).
  double level_ratio = 0.25;
  /// Stop coarsening at this many vertices or fewer (the coarsest level is factored). ≥ 1.
  Index coarsest_vertices = 2000;
  /// @throws InvalidInput naming the field
  void validate() const;
};

/// The prolongation chain of repeated intrinsic simplification (intrinsic/simplify/simplify.h,
/// fem/prolongation.h): level l+1 is simplify(level l) to max(coarsest_vertices, level_ratio ×
/// its vertices); P_l is its prolongation. Stops at coarsest_vertices, or at a level that misses
/// its target (simplify() left vertices it could not remove: tufted covers of point clouds),
/// which is dropped when it keeps more than 60 % of the vertices. The chain is empty for a
/// triangulation of at most coarsest_vertices vertices (the solvers then factor A directly).
/// @throws InvalidInput on bad options
std::vector<SparseMatrix> simplification_hierarchy(const intrinsic::IntrinsicTriangulation& tri,
                                                   const HierarchyOptions& options = {});

/// The library's default provider, used when SolverChoice::hierarchy is empty:
/// simplification_hierarchy() with default options.
HierarchyProvider default_hierarchy_provider();

/// The solver choice of PoissonOptions and HeatDistanceOptions.
struct SolverChoice {
  LinearSolverKind kind = LinearSolverKind::kDirect;
  /// The hierarchy for kMultigrid / kAuto; empty: default_hierarchy_provider().
  HierarchyProvider hierarchy;
  /// PCG tolerance, iteration cap, smoother.
  MultigridOptions multigrid;
  /// kAuto takes multigrid from this many vertices on (when a provider exists). Why this size:
  /// docs/decisions.md D-230 (the direct factors' memory against the machine's). ≥ 1.
  Index auto_multigrid_vertices = 2'500'000;
  /// The provider in effect: hierarchy, or default_hierarchy_provider() when that is empty.
  HierarchyProvider provider() const;
  /// Whether a system of n_vertices unknowns runs multigrid.
  /// @throws InvalidInput for kMultigrid without any provider
  bool use_multigrid(Index n_vertices) const;
  /// @throws InvalidInput naming the field
  void validate() const;
};

/// "direct", "multigrid", "auto" → the kind. @throws InvalidInput on another name
LinearSolverKind parse_linear_solver(const std::string& name);
/// The kind's name, as parse_linear_solver() reads it.
const char* linear_solver_name(LinearSolverKind kind);

}  // namespace ifem::solvers
