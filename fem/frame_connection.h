// The connection Laplacian from per-vertex 3D tangent frames (the point-cloud vector heat of
// Sharp, Soliman, Crane, "The Vector Heat Method", ACM TOG 2019, §5.4 / geometry-central's
// point-cloud tangent spaces): the scalar weights of any real Laplacian, the transport between
// neighbours from their frames in space.
//
// Used where the intrinsic angular coordinate is not the surface's: on the tufted cover of a
// nonmanifold mesh and on point-cloud triangulations every vertex has several fans (front and
// back, fem/connection.h), so a vertex's angle does not name one direction in space. There a
// tangent vector at vertex i is the complex number x + iy for x·e1_i + y·e2_i, (n_i, e1_i, e2_i)
// a right-handed orthonormal frame (e2 = n × e1), and the transport along a neighbour pair
// (i, j) is the minimal rotation that takes n_i to n_j, applied to i's frame and read in j's.
// The normals must be oriented consistently (one side of the surface) for the complex
// structure, i.e. counter-clockwise, to agree between neighbours.
#pragma once

#include <Eigen/Core>
#include <Eigen/SparseCore>
#include <complex>

#include "fem/connection.h"
#include "fem/operators.h"

namespace ifem::fem {

/// The transport between two frames: the unit complex r that takes a tangent vector at i,
/// x + iy in (e1_i, e2_i), to j's frame, r·(x + iy), by the minimal rotation R with R n_i = n_j
/// (about n_i × n_j): r = ⟨R e1_i, e1_j⟩ + i⟨R e1_i, e2_j⟩, normalized. r_{j→i} = conj(r_{i→j}).
/// Where n_i = −n_j (no minimal rotation: disagreeing orientations) R is the half turn about
/// the axis e1_i; the result is then a defined but meaningless unit number.
/// @pre every vector unit, (n, e1, e2) orthonormal and right-handed at both ends
std::complex<double> frame_transport(const Eigen::Vector3d& n_i, const Eigen::Vector3d& e1_i,
                                     const Eigen::Vector3d& n_j, const Eigen::Vector3d& e1_j,
                                     const Eigen::Vector3d& e2_j);

/// Connection Laplacian for n-direction fields (n = 1 vectors, 2 lines, 4 crosses) on the
/// pattern of a real Laplacian L: with w_ij = −L_ij (i ≠ j), #V×#V complex Hermitian,
/// L∇_ij = −w_ij · r_{j→i}^n, L∇_ii = Σ_{j≠i} w_ij (the sign and conjugation convention of
/// connection_laplacian(): x*L∇x = Σ_{i<j} w_ij |x_j − r_{i→j}^n x_i|²), r from
/// frame_transport(). PSD when every w_ij ≥ 0 (the cotan Laplacian of an intrinsic Delaunay
/// triangulation, tufted or not). Use it with the mass that goes with L. Vertices without
/// off-diagonal entries have zero rows.
/// @param L #V×#V real, symmetric pattern and values (e.g. cotan_laplacian(tri))
/// @param normal,e1,e2 #V×3 each: per vertex a right-handed orthonormal frame, e2 = normal × e1
/// @param symmetry n ≥ 1
/// @throws InvalidInput on sizes that do not match, symmetry < 1, a non-finite frame or weight
ComplexSparseMatrix connection_laplacian_from_frames(const SparseMatrix& L,
                                                     const Eigen::MatrixX3d& normal,
                                                     const Eigen::MatrixX3d& e1,
                                                     const Eigen::MatrixX3d& e2, int symmetry = 1);

}  // namespace ifem::fem
