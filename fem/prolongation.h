// Prolongation from a coarse intrinsic triangulation to the fine one it simplifies
// (intrinsic/simplify/simplify.h): piecewise-linear interpolation in the coarse faces.
#pragma once

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

}  // namespace ifem::fem
