// Poisson / Laplace / screened Poisson problems on an intrinsic triangulation with Dirichlet
// values on any vertex set and natural (zero) Neumann conditions elsewhere.
#pragma once

#include <Eigen/Core>
#include <memory>
#include <vector>

#include "fem/operators.h"
#include "intrinsic/core/triangulation.h"
#include "solvers/linalg/cholesky.h"
#include "solvers/scalar/components.h"
#include "solvers/scalar/solver_choice.h"

namespace ifem::solvers {

/// Options of PoissonSolver / solve_poisson().
struct PoissonOptions {
  /// c ≥ 0: solves (L + c·M) u = M f (screened Poisson); 0 = plain Poisson L u = M f.
  double screening = 0.0;
  /// Options of the factorization (e.g. factor_blas_threads = 1 when several are built at once).
  CholeskyOptions cholesky;
  /// The linear solver: the Cholesky factor (kDirect, the default) or multigrid-preconditioned
  /// CG (kMultigrid; kAuto by size). With multigrid every solve is iterative, to
  /// solver.multigrid.tolerance (relative residual), and a shared CholeskyAnalysis is not used.
  SolverChoice solver;
  /// The prolongation chain over all #V vertices (P₀ #V × n₁, …) for multigrid from assembled
  /// operators; the triangulation constructor fills it from solver.provider() when empty. Rows of
  /// Dirichlet and pinned vertices are left out of the hierarchy here. An empty chain (a mesh no
  /// larger than the coarsest level) factors directly, as one level.
  std::shared_ptr<const std::vector<SparseMatrix>> prolongations;
  /// Multigrid only: another PoissonSolver's multigrid_pattern() (e.g. the heat method's M + tL
  /// beside its L, built on the same vertices and prolongations). Where this solver's fine
  /// operator has exactly that pattern it keeps its values only (MultigridSolver's
  /// fine_pattern; docs/decisions.md D-365); otherwise it is ignored. Null: nothing shared.
  std::shared_ptr<const SparseMatrix> multigrid_pattern;
  /// @throws InvalidInput if screening is negative or not finite, or on bad solver options
  void validate() const;
};

/// Solves (L + c·M) u = b on the free vertices with u = g on the Dirichlet vertices, where
/// L = cotan_laplacian (PSD) and M = lumped mass (diagonal), factoring once for a fixed
/// Dirichlet vertex set so that new right-hand sides and Dirichlet values cost back-substitutions.
///
/// Conventions (per connected component):
/// - a component with at least one Dirichlet vertex, or any component when c > 0, has a unique
///   solution;
/// - a component with no Dirichlet vertex and c = 0 (e.g. a closed surface) is pure Neumann:
///   the right-hand side is first made compatible by removing its mass-weighted mean
///   (b ← b − (Σb / Σm)·m on the component), and the zero-mean solution (Σ m_i u_i = 0) is
///   returned;
/// - unreferenced vertices (no face, zero row in L and zero mass) get 0, or their Dirichlet value
///   when one is given.
class PoissonSolver {
 public:
  /// @param tri the triangulation (use the intrinsic Delaunay one for non-negative weights)
  /// @param dirichlet_vertices distinct vertex ids in [0, #V) where u is prescribed
  /// @throws InvalidInput on an out-of-range or repeated Dirichlet vertex or bad options, or
  ///         multigrid asked for without a hierarchy provider
  /// @throws SolverError if the reduced matrix cannot be factored (or multigrid does not converge)
  PoissonSolver(const intrinsic::IntrinsicTriangulation& tri, std::vector<Index> dirichlet_vertices,
                const PoissonOptions& options = {});

  /// Same, from assembled operators: A = L + c·diag(mass), with components[v] the component of
  /// v (kInvalidIndex for a vertex that takes part in no face: it is left out of the system).
  /// Multigrid here needs options.prolongations (InvalidInput for kMultigrid without them; kAuto
  /// without them is direct).
  PoissonSolver(const fem::SparseMatrix& L, const Eigen::VectorXd& mass,
                const Components& components, std::vector<Index> dirichlet_vertices,
                const PoissonOptions& options = {});

  /// Same, factoring with a shared symbolic analysis (made by analyze() from an L of the same
  /// pattern and the same components) instead of one of its own: the Dirichlet and pinned
  /// vertices stay in the factored system as decoupled rows (their diagonal entry, their
  /// off-diagonal entries stored as zeros), so every such solver has the analyzed pattern — the
  /// heat method's M + tL and L share one (docs/decisions.md, "Small meshes: one analysis, no
  /// threads below their size"). Results equal the constructor above's to rounding.
  /// @throws InvalidInput also if L's pattern or the components are not the analyzed ones
  PoissonSolver(const fem::SparseMatrix& L, const Eigen::VectorXd& mass,
                const Components& components, std::vector<Index> dirichlet_vertices,
                const CholeskyAnalysis& analysis, const PoissonOptions& options = {});

  /// The analysis for the constructor above: of L's pattern on the vertices of a component.
  /// @throws InvalidInput if the sizes disagree; SolverError if CHOLMOD fails
  static CholeskyAnalysis analyze(const fem::SparseMatrix& L, const Components& components,
                                  const CholeskyOptions& options = {});

  /// The same analysis from tri alone, before L is assembled: the pattern of
  /// cotan_laplacian(tri) on the vertices that faces reference (every edge between two of them,
  /// parallel edges merged), for the constructor above with L = cotan_laplacian(tri) (or any
  /// matrix of its pattern) and components = connected_components(tri). With force_amd (and no
  /// given ordering) AMD orders it here, straight from the edge lists, which is the ordering
  /// analyze(L, ...) would compute. The heat method runs this beside the assembly of L and M
  /// (docs/decisions.md, "Small meshes: the analysis beside the assembly").
  /// @throws InvalidInput if tri is too large for 32-bit indices; SolverError if CHOLMOD fails
  static CholeskyAnalysis analyze(const intrinsic::IntrinsicTriangulation& tri,
                                  const CholeskyOptions& options = {});

  ~PoissonSolver();
  PoissonSolver(PoissonSolver&&) noexcept;
  PoissonSolver& operator=(PoissonSolver&&) noexcept;

  /// Solves (L + c·M) u = M f. @param f #V per-vertex source values
  /// @param dirichlet_values one value per Dirichlet vertex, in the constructor's order
  /// @returns u, #V
  Eigen::VectorXd solve(const Eigen::VectorXd& f, const Eigen::VectorXd& dirichlet_values) const;

  /// Solves (L + c·M) u = b for an integrated (weak) right-hand side b (#V), e.g. b = M f or a
  /// divergence. Same conventions as solve().
  Eigen::VectorXd solve_weak(const Eigen::VectorXd& b,
                             const Eigen::VectorXd& dirichlet_values) const;

  /// solve_weak() for every column of B (#V×k) with zero Dirichlet values.
  Eigen::MatrixXd solve_weak_homogeneous(const Eigen::MatrixXd& B) const;

  /// The Dirichlet vertices, in the constructor's order.
  const std::vector<Index>& dirichlet_vertices() const;
  /// Number of unknowns in the factored system (with a shared analysis: including the Dirichlet
  /// and pinned vertices, kept as decoupled rows).
  Index n_unknowns() const;
  /// Entries of the Cholesky factor (0 when nothing is factored: every vertex constrained, or
  /// multigrid).
  double factor_nonzeros() const;
  /// True when the solves run multigrid-preconditioned CG (PoissonOptions::solver).
  bool multigrid() const;
  /// The multigrid solver's fine operator, for its pattern (MultigridSolver::fine_pattern()):
  /// pass it as another solver's PoissonOptions::multigrid_pattern. Null when not multigrid.
  std::shared_ptr<const SparseMatrix> multigrid_pattern() const;

  struct Impl;

 private:
  fem::SparseMatrix setup(const fem::SparseMatrix& L, const Eigen::VectorXd& mass,
                          const Components& components, std::vector<Index> dirichlet_vertices,
                          const PoissonOptions& options, bool keep_fixed, bool on_shared_pattern);
  // options with prolongations from the provider when multigrid is chosen for tri
  static PoissonOptions with_hierarchy(const intrinsic::IntrinsicTriangulation& tri,
                                       const PoissonOptions& options);
  // the Cholesky factor (with the analysis when given) or the multigrid solver of A (setup()'s;
  // an rvalue: the multigrid solver takes its storage, Eigen 3.4 has no sparse move)
  void factor(fem::SparseMatrix&& A, const PoissonOptions& options,
              const CholeskyAnalysis* analysis);
  std::unique_ptr<Impl> impl_;
  friend struct PoissonBlocks;  // the heat method's block solves (heat_engine.h)
};

/// One-off: solves (L + c·M) u = M f with u = dirichlet_values on dirichlet_vertices.
/// See PoissonSolver for the conventions (zero mean without Dirichlet data, 0 on unreferenced).
/// @param f #V per-vertex right-hand side (a function, multiplied by the lumped mass here)
Eigen::VectorXd solve_poisson(const intrinsic::IntrinsicTriangulation& tri,
                              const Eigen::VectorXd& f,
                              const std::vector<Index>& dirichlet_vertices,
                              const Eigen::VectorXd& dirichlet_values,
                              const PoissonOptions& options = {});

}  // namespace ifem::solvers
