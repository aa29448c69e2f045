// Finite-element operators assembled from edge lengths alone: cotan Laplacian (stiffness),
// lumped and Galerkin mass. Sign convention: L is symmetric positive semi-definite
// (positive diagonal, L·1 = 0), the FEM stiffness matrix; libigl's cotmatrix is −L.
#pragma once

#include <Eigen/Core>
#include <Eigen/SparseCore>
#include <vector>

#include "intrinsic/core/triangulation.h"

namespace ifem::fem {

using SparseMatrix = Eigen::SparseMatrix<double, Eigen::ColMajor, int>;

/// Cotan Laplacian L (#V×#V, symmetric PSD, L·1 = 0): L_ij = −(cot α_ij + cot β_ij)/2 summed
/// over every edge joining i ≠ j, L_ii = −Σ_j L_ij. Self-edges cancel and contribute nothing.
/// Divided by tri.multiplicity() so a tufted cover approximates the surface it covers.
/// Every vertex has a stored diagonal entry (0 for an unreferenced vertex).
/// On an intrinsic Delaunay triangulation every off-diagonal entry is ≤ 0.
SparseMatrix cotan_laplacian(const intrinsic::IntrinsicTriangulation& tri);

/// Same, from per-edge weights w (#E) already computed (see intrinsic::cotan_weights).
SparseMatrix laplacian_from_weights(const intrinsic::IntrinsicTriangulation& tri,
                                    const Eigen::VectorXd& edge_weights);

/// Lumped (barycentric) mass, #V: a third of the area of every incident face, divided by the
/// multiplicity. 0 on unreferenced vertices.
Eigen::VectorXd lumped_mass(const intrinsic::IntrinsicTriangulation& tri);

/// Galerkin (consistent) mass for piecewise-linear elements, #V×#V: per face, A/6 on the
/// diagonal and A/12 off it, divided by the multiplicity.
SparseMatrix galerkin_mass(const intrinsic::IntrinsicTriangulation& tri);

/// Per-face areas, #F (not divided by the multiplicity).
Eigen::VectorXd face_areas(const intrinsic::IntrinsicTriangulation& tri);

/// CSC assembly helpers (for matrices written straight into Eigen's arrays, no triplets).
/// Sorts one column's n entries (rows r, values x) by row, stably, and sums equal rows in the
/// order they were given (parallel edges, repeated entries); returns the merged count (≤ n),
/// the merged entries first in r, x.
int sort_and_merge_column(int* r, double* x, int n);

/// Moves each column v's first count[v] entries (starting at outer[v]) down so the columns are
/// contiguous, and sets outer[v] (#nv + 1) to match; returns the final number of nonzeros.
int squeeze_columns(Index nv, const std::vector<int>& count, int* outer, int* inner, double* value);

}  // namespace ifem::fem
