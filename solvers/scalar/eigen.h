// Smallest eigenpairs of the Laplace–Beltrami operator: L φ = λ M φ (L cotan stiffness, PSD;
// M lumped mass), by Lanczos in shift-invert mode (Spectra) with a CHOLMOD factor of L − σM.
// The results are bitwise the same for any OpenMP thread count and OpenBLAS setting (the
// factorization runs at one BLAS thread, unless called inside a BlasThreadScope, whose count it
// then takes; Spectra's dense products go to OpenBLAS, also at one thread).
#pragma once

#include <Eigen/Core>

#include "fem/operators.h"
#include "intrinsic/core/progress.h"
#include "intrinsic/core/triangulation.h"

namespace ifem::solvers {

/// Options of eigenpairs().
struct EigenOptions {
  /// Extra pairs computed internally and dropped, so that a degenerate eigenvalue cut by the
  /// k-th pair is not returned with a missing copy (Lanczos can miss copies; docs/DEPENDENCIES.md,
  /// "Spectra"). ≥ 0.
  Index extra_pairs = 6;
  /// Lanczos basis size: max(2·(k + extra) + 1, 20), capped by the number of unknowns; 0 = auto.
  /// ≥ 0.
  Index ncv = 0;
  Index max_iterations = 1000;  ///< Lanczos restarts before giving up (SolverError); ≥ 1
  double tolerance = 1e-10;     ///< Spectra's relative convergence tolerance; > 0
  /// σ = −shift_scale / (total area): slightly negative so that L − σM is positive definite.
  /// Relative (dimensionless: σ is in 1 / area units); > 0.
  double shift_scale = 1e-2;
  /// Spectral coarsening (triangulation overload only): 0 = off (the exact eigenpairs above);
  /// N > 0: the triangulation is simplified to N vertices (intrinsic::simplify), the coarse
  /// problem's q = min(2·(k + extra_pairs), N' − 1) smallest pairs (N' coarse vertices with
  /// mass) are solved as above, prolonged (fem::prolongation) to the fine vertices as a
  /// subspace, and Rayleigh–Ritz with the fine L and M gives the k pairs: an approximation
  /// (EigenPairs::residuals says how good), with no factor of the fine matrices. N must lie in
  /// (k + extra_pairs, #V). ≥ 0.
  Index coarse = 0;
  /// With coarse > 0: block (subspace) iterations refining that subspace before the last
  /// Rayleigh–Ritz, each X ← (L − σM)⁻¹ M X with a Cholesky factor of the fine L − σM (σ as
  /// shift_scale says): the error of λ_j shrinks per iteration by about ((λ_j − σ) /
  /// (λ_q+1 − σ))². 0 = none. ≥ 0.
  Index coarse_iterations = 0;
  /// Progress, stage "eigenpairs": back-substitutions made over an estimate of those Lanczos
  /// needs (ncv for the first basis, then ncv − nev per restart for a few restarts;
  /// saturating_fraction()), 1 when done (ProgressCallback). Empty: none.
  ProgressCallback on_progress;
  /// @throws InvalidInput naming the fields and their ranges when one is out of range
  void validate() const;
};

/// k eigenpairs with the smallest eigenvalues.
struct EigenPairs {
  Eigen::VectorXd values;   ///< k, ascending (≥ 0 up to round-off; 0 once per component)
  Eigen::MatrixXd vectors;  ///< #V×k, M-orthonormal: Φᵀ M Φ = I
  /// Spectra's num_iterations(): Lanczos expansions of the basis, the first included (restarts =
  /// iterations − 1)
  Index iterations = 0;
  Index solves = 0;  ///< Spectra's num_operations(): back-substitutions with the factor of L − σM
  /// k: relative residual of each pair, ‖Lφ − λMφ‖₂ / ‖λMφ‖₂ (for λ below 1e-9 × the largest
  /// of the k, that largest λ stands in the denominator: the constant mode's residual is then
  /// relative to the spectrum's scale, not to its own round-off eigenvalue)
  Eigen::VectorXd residuals;
  /// Spectral coarsening (EigenOptions::coarse): the coarse triangulation's vertex count, 0 when
  /// the pairs are the exact ones. The pairs are then an approximation: Ritz pairs in a
  /// subspace, each λ ≥ the exact one (min–max), φ M-orthonormal.
  Index coarse_vertices = 0;
};

/// Solves L φ = λ M φ for the k smallest eigenvalues.
/// Unreferenced vertices (no face: zero row in L and zero mass) are left out of the problem and
/// get 0 in every eigenvector. Faces of zero area on an otherwise referenced vertex are fine.
/// @param L #V×#V stiffness (PSD), @param mass #V lumped mass (> 0 on referenced vertices)
/// @throws InvalidInput if k < 1 or k ≥ the number of referenced vertices, sizes disagree, on
///         bad options (EigenOptions::validate()), or options.coarse > 0 (it needs the
///         triangulation: use the overload below)
/// @throws SolverError if Lanczos does not converge ("3 of 10 eigenpairs converged ...") or the
///         factorization of L − σM fails
EigenPairs eigenpairs(const fem::SparseMatrix& L, const Eigen::VectorXd& mass, Index k,
                      const EigenOptions& options = {});

/// Same, assembling L and M from the triangulation (use the intrinsic Delaunay one); with
/// options.coarse > 0, the spectral-coarsening approximation described at EigenOptions::coarse.
/// @throws InvalidInput as above, or if options.coarse is not in (k + extra_pairs, #V)
EigenPairs eigenpairs(const intrinsic::IntrinsicTriangulation& tri, Index k,
                      const EigenOptions& options = {});

}  // namespace ifem::solvers
