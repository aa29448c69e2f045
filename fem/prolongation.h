// Prolongation from a coarse intrinsic triangulation to the fine one it simplifies
// (intrinsic/simplify/simplify.h): piecewise-linear interpolation in the coarse faces, for
// scalars and for tangent vectors (in the angular coordinates of fem/connection.h).
#pragma once

#include "fem/connection.h"
#include "fem/operators.h"
#include "intrinsic/simplify/simplify.h"

namespace ifem::fem {

/// P, #V fine × #Vc coarse: row i holds the barycentric coordinates of fine vertex i in its
/// coarse face (s.fine_in_coarse[i]) at that face's corners (a kept vertex: 1 at itself; an
/// unreferenced vertex: 1 at its coarse copy). Rows sum to 1, entries are ≥ 0; P·u interpolates
/// a coarse piecewise-linear function u at the fine vertices, Pᵀ restricts. Zero coordinates are
/// not stored. Galerkin coarse operators: Pᵀ·L·P, Pᵀ·M·P (fem/operators.h on s.coarse gives the
/// rediscretised ones).
/// @throws InvalidInput if s.fine_in_coarse names a face or vertex `s.coarse` does not have
SparseMatrix prolongation(const intrinsic::Simplification& s);

/// Tangent-vector prolongation, #V fine × #Vc coarse, complex: a coarse tangent field u (one
/// complex number per coarse vertex, in tangent_frames(s.coarse)'s coordinates) to the fine
/// vertices (in tangent_frames(fine)'s), P·u. Row i, for fine vertex i at barycentric b in coarse
/// face F (s.fine_in_coarse[i]), holds b_k · r_k at F's corner c_k: r_k the unit complex number
/// that transports c_k's coordinate into F's planar layout (the direction of F's side leaving
/// c_k is that side's halfedge angle at c_k) and from there into i's coordinate. The latter is
/// the circular mean, over i's fine edges i→j, of the angle between the layout direction from i
/// to j and the fine halfedge angle of i→j; j is placed in F's layout when it lies in F, at a
/// corner of F, or in a face glued to one of F's sides (unfolded across it); if none is, the
/// rotation is 1 (no information). So |P_ik| = b_k and each row's magnitudes sum to 1 (an
/// unreferenced vertex: 1 at its coarse copy). On a flat domain (angle scales 1) a parallel coarse
/// field goes to a parallel fine field exactly; on a curved surface the error is of the order of
/// the coarse faces' curvature (angle scaling within a face). The restriction is P's adjoint
/// Pᴴ; Galerkin coarse connection Laplacian Pᴴ·L∇·P (L∇ = connection_laplacian(fine)).
/// Meaningful where the angular coordinates are (a manifold triangulation, fem/connection.h);
/// on the tufted cover and point clouds it is defined but, like their intrinsic connection, not
/// the surface's.
/// @param fine the triangulation s was simplified from (the same vertex ids)
/// @throws InvalidInput as prolongation(), or if s.fine_in_coarse does not have #V(fine) entries
ComplexSparseMatrix tangent_prolongation(const intrinsic::IntrinsicTriangulation& fine,
                                         const intrinsic::Simplification& s);

}  // namespace ifem::fem
