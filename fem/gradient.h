// Per-face gradient and the matching (weak) divergence of piecewise-linear functions on an
// intrinsic triangulation, from edge lengths alone: each face is laid out in its own 2D frame.
// Used by the heat method (Crane, Weischedel, Wardetzky 2013, §3.2).
#pragma once

#include <Eigen/Core>
#include <array>
#include <vector>

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

/// divergence() of the unit field X_f = −∇u/|∇u| (the heat method's normalized gradient) in one
/// pass over the faces, without storing X: faces where |∇u| is zero or not finite, degenerate
/// faces and faces with use_face[f] == 0 (when use_face is given, #F) contribute nothing.
/// |∇u| is scaled by its largest component first, so gradients of ~1e-200 (underflowing heat)
/// still normalize.
/// Equals divergence(tri, X) with X built that way, to rounding (UnitGradientDivergence below).
/// @throws InvalidInput if u.size() != #V or use_face has the wrong size
Eigen::VectorXd divergence_of_unit_gradient(const intrinsic::IntrinsicTriangulation& tri,
                                            const Eigen::VectorXd& u,
                                            const std::vector<char>* use_face = nullptr);

/// divergence_of_unit_gradient() for many fields on one triangulation (the heat method's
/// queries): each face's 2D layout (ℓ₀, x, y of its third corner: 3 doubles per face) is computed
/// once, at construction, instead of on every call, and a call reads those with the face's corner
/// values: c_i = (s/2)·(J e_i)·X on face f, e_i the side opposite corner i, J the rotation by 90°,
/// X = −v/|v| with v = Σ u_i J e_i = 2A∇u (so the area cancels). The triangulation is copied
/// from, not referenced; it must not change while the object is used for it.
class UnitGradientDivergence {
 public:
  explicit UnitGradientDivergence(const intrinsic::IntrinsicTriangulation& tri);

  /// divergence_of_unit_gradient(tri, u, use_face), #V. The faces are summed in two fixed halves
  /// (one thread each when the mesh is large and a core is idle), so the result does not depend
  /// on the thread count.
  /// @throws InvalidInput if u.size() != #V or use_face has the wrong size
  Eigen::VectorXd apply(const Eigen::VectorXd& u,
                        const std::vector<char>* use_face = nullptr) const;

  /// divergence_of_unit_gradients(tri, U, use_face), #V×k; threads split the columns (each
  /// column is summed in face order, so the result does not depend on the thread count).
  /// @param use_face empty (every face), or k masks of #F entries
  /// @throws InvalidInput if U.rows() != #V or use_face has the wrong sizes
  Eigen::MatrixXd apply_columns(const Eigen::MatrixXd& U,
                                const std::vector<std::vector<char>>& use_face = {}) const;
  /// apply_columns() written into div (#V×k, overwritten), e.g. a block of a reused matrix.
  /// @throws InvalidInput as apply_columns(), or if div is not #V×k
  void apply_columns(const Eigen::Ref<const Eigen::MatrixXd>& U,
                     const std::vector<std::vector<char>>& use_face,
                     Eigen::Ref<Eigen::MatrixXd> div) const;
  /// apply_columns() on every face for k fields stored row-major: U and div are #V × k with the
  /// k values of vertex v contiguous (at U + v·k), the layout of solve_rows(); div is
  /// overwritten. The k values of a corner are one vector operation (AVX-512 or AVX2 when the
  /// host has it), so a block of fields costs a fraction of k single ones. Threads split the
  /// columns, each summed in face order: the bits do not depend on the thread count. Equal to
  /// apply_columns() column by column to rounding (FMA contraction on hosts with FMA).
  /// @param U, div #V·k doubles each, not overlapping
  /// @throws InvalidInput if k < 1
  void apply_rows(const double* U, Eigen::Index k, double* div) const;
  /// apply_rows() on columns [j0, j1) of the k only, on the calling thread (the other columns
  /// of div are not touched): for a caller that runs its own threads (no OpenMP team left
  /// spinning beside them). Two calls split at column_split(k) give apply_rows()'s bits.
  /// @param u_row null, or #V row numbers: vertex v's k values are then read at U + u_row[v]·k
  ///        (a block kept in another row order, read where it is; not checked)
  /// @param d_row the same for div: vertex v's divergences go to div + d_row[v]·k
  /// @throws InvalidInput unless 0 ≤ j0 ≤ j1 ≤ k and k ≥ 1
  void apply_rows(const double* U, Eigen::Index k, double* div, Eigen::Index j0, Eigen::Index j1,
                  const Index* u_row = nullptr, const Index* d_row = nullptr) const;
  /// Where apply_rows() splits the columns between two threads: ⌊k/2⌋ rounded up to a multiple of
  /// 8 (whole vectors, and for k = 32 whole cache lines of a row); k when k < 16 (one thread).
  static Eigen::Index column_split(Eigen::Index k);
  /// For tests: whether apply_rows() may run its AVX-512 variant on a host that has AVX-512
  /// (default true; false runs the portable kernels that other hosts run). Process-wide.
  /// @return the previous setting
  static bool allow_avx512(bool allowed);

  /// The same operator on renumbered vertices: vertex v of the triangulation is vertex
  /// new_index[v] of the copy, so that apply_rows() reads and writes blocks in another row order
  /// (e.g. one with better locality than the input's) without copying them. The faces are
  /// reordered into the three parts of add_rows_part(), each by its smallest new vertex index
  /// (stable), so that a pass over a part sweeps the new order; the sums at each vertex then
  /// run in that order (the same values to rounding).
  /// @throws InvalidInput if new_index is not a permutation of [0, #V)
  UnitGradientDivergence relabeled(const std::vector<Index>& new_index) const;

  /// Adds (+=) the divergences of one part of the faces to div, columns [j0, j1) (rows and maps
  /// as apply_rows()), for two threads that take every column at once: in a relabeled() copy,
  /// part 0 is the faces whose new corners are all below ⌊#V/2⌋, part 1 those whose corners are
  /// all at or above it, part 2 the rest (a thin band where the new order is local, e.g.
  /// breadth-first). Parts 0 and 1 write disjoint rows of div (u_row, d_row permutations or
  /// null), so they may run side by side on all columns; part 2 after both (split by columns
  /// if on two threads). Zeroing div first, then parts 0, 1, 2 in that order gives the same bits
  /// on one thread or two. In an operator that was not relabeled every face is in part 2.
  /// @throws InvalidInput unless part is 0, 1 or 2, 0 ≤ j0 ≤ j1 ≤ k and k ≥ 1
  void add_rows_part(const double* U, Eigen::Index k, double* div, int part, Eigen::Index j0,
                     Eigen::Index j1, const Index* u_row = nullptr,
                     const Index* d_row = nullptr) const;

 private:
  Index n_vertices_ = 0, n_faces_ = 0;
  double scale_ = 1.0;                     // 1 / tri.multiplicity()
  std::vector<Index> tail_;                // 3 per face: its corners
  std::vector<double> frame_;              // 3 per face: ℓ₀, x, y (y = 0 on a degenerate face)
  std::array<Index, 2> part_faces_{0, 0};  // faces in parts 0 and 1 (add_rows_part())
};

/// divergence_of_unit_gradient() of every column of U (#V×k) at once, #V×k: each face's layout
/// is computed once for all columns, and threads split the columns. Column j equals
/// divergence_of_unit_gradient(tri, U.col(j), &use_face[j]) up to the order of the sums
/// at each vertex.
/// @param use_face empty (every face), or k masks of #F entries
/// @throws InvalidInput if U.rows() != #V or use_face has the wrong sizes
Eigen::MatrixXd divergence_of_unit_gradients(const intrinsic::IntrinsicTriangulation& tri,
                                             const Eigen::MatrixXd& U,
                                             const std::vector<std::vector<char>>& use_face = {});

/// Local 2D position of corner 2 of face f in the frame of gradient() (corner 0 at the origin,
/// corner 1 at (ℓ₀, 0)); y ≥ 0.
Eigen::Vector2d face_corner2(const intrinsic::IntrinsicTriangulation& tri, Index f);

}  // namespace ifem::fem
