// Per-face gradient and the matching (weak) divergence of piecewise-linear functions on an
// intrinsic triangulation, from edge lengths alone: each face is laid out in its own 2D frame.
// Used by the heat method (Crane, Weischedel, Wardetzky 2013, §3.2; its batched form of
// divergence(−∇u/|∇u|) is solvers/scalar/heat_engine.h).
#pragma once

#include <Eigen/Core>

#include "intrinsic/core/triangulation.h"

namespace ifem::fem {

/// Per-face gradients, #F×2. Row f is ∇u on face f in that face's local 2D frame: corner 0 of
/// f at the origin, corner 1 at (ℓ₀, 0) on the +x axis (ℓ₀ = length of side 0, corner 0 → 1),
/// corner 2 at positive y. The frame is intrinsic: only lengths are used, so the same layout
/// is used by divergence(). A degenerate face (zero area) gets a zero gradient.
/// @param u #V values at the vertices
/// @throws InvalidInput if u.size() != #V
Eigen::MatrixX2d gradient(const intrinsic::IntrinsicTriangulation& tri, const Eigen::VectorXd& u);

/// Weak (integrated) divergence of a per-face vector field X given in the frames of
/// gradient(): div(X)_i = Σ_f A_f ∇φ_i|_f · X_f, divided by tri.multiplicity(), #V.
/// Sign convention: this is the adjoint of gradient() under the area-weighted inner product,
/// so divergence(gradient(u)) = L·u with L = cotan_laplacian(tri) (PSD); it is the NEGATIVE of
/// the classical integrated divergence ∫ φ_i ∇·X. To fit ∇φ ≈ X in least squares, solve
/// L φ = divergence(X).
/// @param X #F×2 per-face vectors
/// @throws InvalidInput if X.rows() != #F
Eigen::VectorXd divergence(const intrinsic::IntrinsicTriangulation& tri, const Eigen::MatrixX2d& X);

/// Local 2D position of corner 2 of face f in the frame of gradient() (corner 0 at the origin,
/// corner 1 at (ℓ₀, 0)); y ≥ 0.
Eigen::Vector2d face_corner2(const intrinsic::IntrinsicTriangulation& tri, Index f);

}  // namespace ifem::fem
