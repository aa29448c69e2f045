// Vector kernels over row-major blocks of k columns (k sources of the heat method, k right-hand
// sides): the k values of row v contiguous at block + v·k. Internal to solvers/ (the heat
// engine, solvers/scalar/heat_engine.h). Each is compiled for AVX-512, AVX2 + FMA and the
// baseline ISA and picked at load time (why hand-written: row_kernels.cpp).
#pragma once

#include <cstdint>

#include "intrinsic/core/types.h"

namespace ifem::solvers {

/// Adds (+=) to columns [j0, j1) of div the weak divergence of X = −∇u/|∇u| over faces
/// [0, nf): face f has corners tail[3f..3f+2] and the 2D layout frame[3f..3f+2] = ℓ₀, x, y
/// (corner 0 at the origin, corner 1 at (ℓ₀, 0), corner 2 at (x, y); y = 0 marks a degenerate
/// face, which adds nothing); corner i gets half_s·(J e_i)·X, e_i the side opposite corner i and
/// J the rotation by 90° (UnitGradientDivergence, solvers/scalar/heat_engine.h). Columns where
/// ∇u is 0 or not finite on a face add 0 there. The faces are summed in order, so the bits depend
/// on the faces and columns only.
/// @param U, div #V·k doubles each (row-major), not overlapping
/// @param u_row, d_row null, or #V row numbers: vertex v's values are read at U + u_row[v]·k
///        and written at div + d_row[v]·k (not checked)
void unit_divergence_rows(const double* frame, const Index* tail, Index nf, const double* U,
                          const Index* u_row, const Index* d_row, Index k, Index j0, Index j1,
                          double half_s, double* div);

/// Columns [0, k) of rows [v0, v1) of a row-major block H: per column the largest finite value
/// (into hx, max with its value) and the smallest, NaN once any value is NaN (into hn), over the
/// rows whose label is `comp` (every row when label is null).
/// @param hx, hn k values each, read and updated
void extremes_of_rows(const double* H, Index v0, Index v1, std::int64_t k, const Index* label,
                      Index comp, double* hx, double* hn);

/// out[j][v] = max(P[row[v]·k + j] − shift[j], 0)·scale for the vertices [t0, t1) and the k
/// columns (NaN stays NaN, −0 stays −0: the bits of that scalar expression).
/// @param out k column pointers
void rows_to_output(const double* P, const Index* row, Index t0, Index t1, std::int64_t k,
                    const double* shift, double scale, double* const* out);

}  // namespace ifem::solvers
