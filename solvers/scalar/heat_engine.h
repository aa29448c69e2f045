// The heat method's fast path (internal to solvers/: HeatDistanceSolver's queries and their
// tests; not part of the library's public API): the divergence of normalized gradients with
// each face's layout computed once, for one field or blocks of k fields in the row-major layout
// the solve kernel works in, and a PoissonSolver's block solves in that layout and in the
// factor's own row order. Textbook gradient and divergence: fem/gradient.h; textbook solves:
// PoissonSolver (poisson.h).
#pragma once

#include <Eigen/Core>
#include <array>
#include <vector>

#include "intrinsic/core/triangulation.h"

namespace ifem::solvers {

class PoissonSolver;

/// The weak divergence of the unit field X_f = −∇u/|∇u| (the heat method's normalized gradient)
/// in one pass over the faces, without storing X, for one or many fields u on one
/// triangulation: each face's 2D layout (ℓ₀, x, y of its third corner, fem::face_corner2(): 3
/// doubles per face) is computed once, at construction. Face f adds c_i = (s/2)·(J e_i)·X to its
/// corner i, e_i the side opposite corner i, J the rotation by 90°, s = 1/tri.multiplicity(),
/// X = −v/|v| with v = Σ u_i J e_i = 2A∇u (so the area cancels); equal to
/// fem::divergence(tri, X) to rounding. Faces where |∇u| is zero or not finite, degenerate faces
/// and faces with use_face[f] == 0 (when a mask is given) contribute nothing. |∇u| is scaled by
/// a power of two or its largest component first, so gradients of ~1e-200 (underflowing heat)
/// still normalize. The triangulation is copied from, not referenced.
class UnitGradientDivergence {
 public:
  explicit UnitGradientDivergence(const intrinsic::IntrinsicTriangulation& tri);

  /// One field, #V. The faces are summed in two fixed halves (one OpenMP thread each on large
  /// meshes), so the result does not depend on the thread count.
  /// @param u #V values at the vertices
  /// @param use_face null, or #F flags
  /// @throws InvalidInput if u.size() != #V or use_face has the wrong size
  Eigen::VectorXd apply(const Eigen::VectorXd& u,
                        const std::vector<char>* use_face = nullptr) const;

  /// Every column of U (#V×k), #V×k; threads split the columns (each column is summed in face
  /// order, so the result does not depend on the thread count).
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
  /// k values of vertex v contiguous (at U + v·k), the layout of CholeskySolver::solve_rows();
  /// div is overwritten. The k values of a corner are one vector operation
  /// (solvers/linalg/row_kernels.h). Two OpenMP threads split the columns at column_split(k),
  /// each summed in face order: the bits do not depend on the thread count. Equal to
  /// apply_columns() column by column to rounding (~2e-14 relative).
  /// @param U, div #V·k doubles each, not overlapping
  /// @throws InvalidInput if k < 1
  void apply_rows(const double* U, Eigen::Index k, double* div) const;
  /// apply_rows() on columns [j0, j1) of the k only, on the calling thread (the other columns
  /// of div are not touched). Two calls split at column_split(k) give apply_rows()'s bits.
  /// @param u_row null, or #V row numbers: vertex v's k values are then read at U + u_row[v]·k
  ///        (a block kept in another row order, read where it is; not checked)
  /// @param d_row the same for div: vertex v's divergences go to div + d_row[v]·k
  /// @throws InvalidInput unless 0 ≤ j0 ≤ j1 ≤ k and k ≥ 1
  void apply_rows(const double* U, Eigen::Index k, double* div, Eigen::Index j0, Eigen::Index j1,
                  const Index* u_row = nullptr, const Index* d_row = nullptr) const;
  /// apply() on a list of faces, for fields kept on a subset of the vertices (e.g. a band):
  /// face f adds its corners' divergences to div[local[v]], reading u[local[v]] (v a corner).
  /// The faces are summed in the order given. apply()'s bits: the faces by increasing index,
  /// those below face_split() into one accumulator, the others into another, then added.
  /// @param faces n face indices in [0, #F) (not checked)
  /// @param local #V entries; every corner of a listed face maps into u and div (not checked)
  void add_faces(const Index* faces, Index n, const double* u, const Index* local,
                 double* div) const;
  /// Where apply() splits the faces into its two sums: #F/2, or #F when it sums them as one.
  Index face_split() const;

  /// Where apply_rows() splits the columns between two threads: ⌊k/2⌋ rounded up to a multiple of
  /// 8 (whole vectors, and for k = 32 whole cache lines of a row); k when k < 16 (one thread).
  static Eigen::Index column_split(Eigen::Index k);

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

/// UnitGradientDivergence(tri).apply(u, use_face), #V.
/// @throws InvalidInput if u.size() != #V or use_face has the wrong size
Eigen::VectorXd divergence_of_unit_gradient(const intrinsic::IntrinsicTriangulation& tri,
                                            const Eigen::VectorXd& u,
                                            const std::vector<char>* use_face = nullptr);

/// UnitGradientDivergence(tri).apply_columns(U, use_face), #V×k.
/// @throws InvalidInput if U.rows() != #V or use_face has the wrong sizes
Eigen::MatrixXd divergence_of_unit_gradients(const intrinsic::IntrinsicTriangulation& tri,
                                             const Eigen::MatrixXd& U,
                                             const std::vector<std::vector<char>>& use_face = {});

/// A PoissonSolver's block solves for the heat method's queries: with zero Dirichlet values, in
/// place, column-major or row-major, and in the factor's own row order (defined in poisson.cpp).
struct PoissonBlocks {
  /// PoissonSolver::solve_weak_homogeneous() written over B (#V×k, columns contiguous: a
  /// MatrixXd or a block of its leading columns). When every vertex is an unknown (a solver
  /// built with a shared analysis on a mesh without unreferenced vertices) no #V×k temporary is
  /// allocated, so a caller that reuses B's storage takes no page faults per call.
  /// @throws InvalidInput if B.rows() != #V or its columns are not contiguous
  static void solve_in_place(const PoissonSolver& p, Eigen::Ref<Eigen::MatrixXd> B);
  /// solve_in_place() for k columns stored row-major at X (#V × k: the k values of vertex v
  /// contiguous at X + v·k), the layout of CholeskySolver::solve_rows() and
  /// UnitGradientDivergence::apply_rows(): no transposes when every vertex is an unknown and
  /// the pure-Neumann part is one component or none (else through a column-major copy). Equal
  /// to the column-major solve to rounding.
  /// @param zero_mean false: leave out the final zero-mean shift on a pure-Neumann component
  ///        (each column then is right up to a constant there), for a caller that subtracts a
  ///        value of its own anyway (the heat method's φ − φ(source))
  /// @throws InvalidInput if k < 1
  static void solve_rows_in_place(const PoissonSolver& p, double* X, Eigen::Index k,
                                  bool zero_mean = true);
  /// The vertex order of blocks for solve_rows_in_order(): row i of such a block is vertex
  /// (*order)[i], the factor's fill-reducing order. Null where that path does not apply: where
  /// solve_rows_in_place() copies (Dirichlet vertices, several pure-Neumann components) or
  /// blocks do not run our kernel (CholeskyBlocks::block_order()).
  static const std::vector<int>* block_order(const PoissonSolver& p);
  /// solve_rows_in_place() on a block of k ≥ 2 columns already in block_order() (non-null), so
  /// that a caller keeping its block in that order across several solves copies no rows.
  /// source_rows: point sources, as CholeskyBlocks::solve_in_block_order() (ignored on a
  /// pure-Neumann component, whose compatibility shift fills every row). On a pure-Neumann
  /// component the shift's subtraction is folded into the solve (no sweep of the block), and
  /// compat_sums (k values, or null), the sums Σ_v a_v W(v, :) with a = compatibility_weights(),
  /// spare its other sweep to a caller that has them from a sweep of its own.
  /// @throws InvalidInput if block_order() is null or k < 2
  static void solve_rows_in_order(const PoissonSolver& p, double* W, Eigen::Index k,
                                  bool zero_mean = true, const int* source_rows = nullptr,
                                  const double* compat_sums = nullptr);
  /// The weights a of the compatibility shift on a single pure-Neumann component (1 on its
  /// vertices, 0 elsewhere; #V, vertex order): a right-hand side x is made compatible as
  /// x − b·(aᵀx). Null when there is no such component (or several).
  static const Eigen::VectorXd* compatibility_weights(const PoissonSolver& p);
};

}  // namespace ifem::solvers
