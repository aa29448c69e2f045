// Transfer of per-vertex functions (piecewise linear) between the input mesh and an intrinsic
// triangulation over it, either way, through their correspondence (signposts or integer
// coordinates): pointwise (interpolation at the other side's vertices) or L2 (Galerkin
// projection with the mixed mass matrix over the common subdivision, as in the attribute
// transfer of Gillespie, Sharp & Crane 2021, "Integer Coordinates for Intrinsic Geometry
// Processing"). docs/decisions.md D-270.
#pragma once

#include <Eigen/Core>
#include <string>

#include "fem/operators.h"
#include "intrinsic/integer/correspondence.h"

namespace ifem::fem {

/// How transfer() carries a function to the other triangulation.
enum class TransferMethod {
  /// Interpolation: the value at each target vertex is the source function's value at that
  /// vertex's place. Input → intrinsic: at the inserted vertices' locations on the input
  /// (CorrespondenceView::input_to_intrinsic); intrinsic → input: the input vertices are
  /// intrinsic vertices with the same ids, so their values are copied.
  kPointwise,
  /// Galerkin (L2) projection: the target function u minimises ∫ (u − f)² dA, i.e. solves
  /// M_target u = M_mixed f with the consistent (galerkin_mass) mass matrix of the target and
  /// the mixed mass matrix (mixed_mass()), by diagonally preconditioned conjugate gradients to
  /// a relative residual of 1e−15 (1e−12 at worst). Preserves ∫ f dA; reproduces any
  /// function linear on both triangulations (e.g. a linear function on a flat mesh).
  kL2,
};

/// "pointwise" or "l2".
const char* to_string(TransferMethod m);
/// The TransferMethod named by `word` ("pointwise" or "l2").
/// @throws InvalidInput naming the word and the allowed ones
TransferMethod parse_transfer_method(const std::string& word);

/// The mixed mass matrix M (#V × #V_in): M_ij = ∫ φ_i ψ_j dA, φ_i the hat functions of
/// view.intrinsic(), ψ_j those of view.input(), integrated exactly over the pieces of
/// `locator` (a PointLocator of view; both functions are linear on each piece) in the input's
/// metric. Its column sums are the input's lumped masses, its row sums the intrinsic ones (up
/// to rounding).
SparseMatrix mixed_mass(const intrinsic::PointLocator& locator,
                        const intrinsic::CorrespondenceView& view);

/// Carries per-vertex values from one triangulation of view to the other.
/// @param values #V_in values on the input's vertices (back = false) or #V values on the
///        intrinsic vertices (back = true), finite
/// @param back false: input → intrinsic (returns #V values, the first #V_in on the input
///        vertices); true: intrinsic → input (returns #V_in values in input order)
/// @param locator for kL2: a PointLocator of view, reused across calls (nullptr: built here)
/// @throws InvalidInput on a size mismatch or a non-finite value (naming the first);
///         SolverError if the mass matrix solve does not converge; as PointLocator for kL2
Eigen::VectorXd transfer(const intrinsic::CorrespondenceView& view, const Eigen::VectorXd& values,
                         TransferMethod method, bool back = false,
                         const intrinsic::PointLocator* locator = nullptr);

}  // namespace ifem::fem
