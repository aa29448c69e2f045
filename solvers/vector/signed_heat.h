// The signed heat method (Feng, Crane, "A Heat Method for Generalized Signed Distance", ACM TOG
// 2024) on an intrinsic triangulation: a signed distance to curves and oriented points that
// need not be closed, connected or clean (open curves, curves with gaps, noisy normals).
//
//   integrated normals Y₀ (#V, tangent vectors)
//     ──► vector heat:   Y = (M + t L∇)⁻¹ Y₀                 (one backward Euler step)
//     ──► unit field:    X = Y / |Y|                        (per vertex; where Y underflowed,
//                        further stages diffuse X from the resolved region's frontier)
//     ──► Poisson:       L φ = d₀ᵀ W α,  α_ij = ∫_ij X·dl    (the least-squares φ with ∇φ ≈ X)
//     ──► level set:     φ = 0 on the sources' zero set (Dirichlet: the paper's "preserve the
//                        zero set"), or φ shifted so its weighted mean there is 0
//
// W holds the cotan weights clamped to ≥ 0, L = d₀ᵀ W d₀ the Laplacian on them, M the lumped
// mass, L∇ the connection Laplacian (n = 1) on the same weights in the tangent coordinates in
// use, t = m·h². Curves inserted as constrained edges can leave large negative cotan weights
// (a curve edge across a nearly flat triangle pair): they would make M + tL∇ indefinite and the
// Poisson step ill-conditioned, while the clamped operators are positive (semi)definite on every
// triangulation. The integrated 1-form α on edge ij is the trapezoidal rule,
// ½ (X_i · e_ij|_i + X_j · e_ij|_j), with e_ij the edge vector (length ℓ_ij) read in i's and j's
// coordinates. For X = ∇φ of a linear φ on a flat domain α is exact, so φ is reproduced exactly
// whatever the (positive) weights: the clamping costs no consistency.
//
// Tangent coordinates, two paths as the vector heat method (solvers/vector/vector_heat.h):
//  - intrinsic: the angular coordinates of fem::tangent_frames(tri) (manifold meshes, refined or
//    with curves inserted as edges); e_ij|_i = ℓ·exp(iθ_h), e_ij|_j = ℓ·exp(i(θ_h + arg r_h));
//  - frames: per-vertex 3D frames (tufted covers, point clouds): L∇ from
//    fem::connection_laplacian_from_frames, e_ij|_i = ℓ × the chord x_j − x_i projected to i's
//    tangent plane and normalized.
//
// Sign: the result is positive on the side the normals point to, negative on the other. The
// magnitude approximates the distance to the sources near them and where the normals are
// consistent; far away it is the paper's generalized signed distance (a smooth function whose
// gradient follows the diffused normals).
#pragma once

#include <Eigen/Core>
#include <string>
#include <vector>

#include "intrinsic/core/triangulation.h"
#include "intrinsic/core/types.h"
#include "solvers/vector/tangent_basis.h"

namespace ifem::solvers {

/// How the additive constant of φ is fixed (the paper's two options).
enum class SignedLevelSet {
  /// φ = 0 exactly on every zero-set vertex (Dirichlet conditions of the Poisson step): the
  /// curve stays the zero level set even where the diffused normals disagree with it.
  kZeroSet,
  /// φ from the pure Neumann problem, shifted per component so that the weighted mean of φ over
  /// the zero-set vertices is 0: the zero level set may move off a broken or noisy curve.
  kMean,
};

/// "zero-set", "mean".
const char* to_string(SignedLevelSet level_set);
/// The SignedLevelSet named `name` (to_string()'s names): the one parser of the CLI and Python.
/// @throws InvalidInput "'NAME': expected 'zero-set' or 'mean'"
SignedLevelSet signed_level_set_from(const std::string& name);

/// Options of signed_heat_distance().
struct SignedHeatOptions {
  /// m in t = m·h² (> 0, finite). The paper's default is 1; larger smooths over gaps and noise.
  double time_factor = 1.0;
  /// h, absolute (the triangulation's length unit), when > 0; 0: mean_edge_length(tri). ≥ 0.
  double mean_edge_length = 0.0;
  SignedLevelSet level_set = SignedLevelSet::kZeroSet;
  /// @throws InvalidInput naming the field: time_factor not > 0 and finite, mean_edge_length
  ///         negative or not finite
  void validate() const;
};

/// The sources: integrated normals and the zero set.
struct SignedHeatSources {
  /// #V: per vertex the integrated normal (∫ n ds over the vertex's share of the curve, or a
  /// point's normal × its weight), in the path's tangent coordinates; 0 where there is none.
  Eigen::VectorXcd normals;
  /// Vertices the zero level set passes through (curve vertices, oriented points): distinct,
  /// in [0, #V), referenced.
  std::vector<Index> zero_set;
  /// kMean: one weight ≥ 0 per zero_set vertex (e.g. its share of curve length); empty: equal.
  std::vector<double> zero_weights;
};

/// What one signed distance did.
struct SignedHeatReport {
  /// Vertices in a connected component without a source (NaN), and unreferenced vertices.
  Index unreached_vertices = 0;
  /// Vertices of a reached component where |Y| underflowed in every stage (below 1e-270 of the
  /// component's largest, or below 1e-290): X = 0 there, φ is only the Poisson step's fill.
  Index unresolved_vertices = 0;
  /// Diffusion stages: 1, or more where the heat underflowed (about 700·√t from the sources):
  /// each further stage diffuses X from the frontier of the resolved region (same factor).
  int stages = 1;
  double time_step = 0.0;  ///< t, squared length units
};

/// Signed heat distance on tri as given (no flips: intrinsic Delaunay, or constrained Delaunay
/// with curves as edges), intrinsic path: sources.normals in the angular coordinates of
/// fem::tangent_frames(tri). #V values, NaN on unreached vertices.
/// @throws InvalidInput on bad options, sizes, a zero set out of range, repeated, unreferenced
///         or empty, no nonzero normal, non-finite normals or weights
/// @throws SolverError if a factorization fails
Eigen::VectorXd signed_heat_distance(const intrinsic::IntrinsicTriangulation& tri,
                                     const SignedHeatSources& sources,
                                     const SignedHeatOptions& options = {},
                                     SignedHeatReport* report = nullptr);

/// The frame path: sources.normals as x + iy for x·e1 + y·e2 of `basis` (frame_basis_3d());
/// every vertex of tri needs a position (positions: #V×3, tri's length unit) and a frame.
/// @throws as the intrinsic path, and InvalidInput if positions or basis do not have #V rows
Eigen::VectorXd signed_heat_distance(const intrinsic::IntrinsicTriangulation& tri,
                                     const Positions& positions, const TangentBasis3d& basis,
                                     const SignedHeatSources& sources,
                                     const SignedHeatOptions& options = {},
                                     SignedHeatReport* report = nullptr);

}  // namespace ifem::solvers
