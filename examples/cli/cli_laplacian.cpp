// `ifem laplacian`: the intrinsic Delaunay cotan Laplacian and mass matrix of a mesh.
#include <algorithm>
#include <cstdio>
#include <string>

#include "cli.h"
#include "fem/operators.h"
#include "intrinsic/core/errors.h"
#include "intrinsic/core/timer.h"

namespace ifem::cli {
namespace {

int run_laplacian(const Args& args) {
  const std::string prefix = args.get("output");
  PreparedSurface s = prepare_surface(args.positional()[0], args);
  const Stopwatch watch;
  const fem::SparseMatrix L = fem::cotan_laplacian(s.tri);
  const Eigen::VectorXd m = fem::lumped_mass(s.tri);
  progress(args, "assembled L and M in " + std::to_string(watch.seconds()) + " s");
  fem::SparseMatrix M(m.size(), m.size());
  M.reserve(Eigen::VectorXi::Ones(m.size()));
  for (Eigen::Index i = 0; i < m.size(); ++i) M.insert(i, i) = m[i];
  M.makeCompressed();
  io::write_matrix_market(prefix + "_L.mtx", L);
  io::write_matrix_market(prefix + "_M.mtx", M);
  // positive off-diagonals (negative weights), judged relative to the diagonal: weights that
  // are exactly 0 (cocircular or right angles) come out as ±1e-16-sized rounding
  double max_offdiag = 0.0, max_diag = 0.0;
  long positive = 0;
  for (int k = 0; k < L.outerSize(); ++k) {
    for (fem::SparseMatrix::InnerIterator it(L, k); it; ++it) {
      if (it.row() == it.col())
        max_diag = std::max(max_diag, it.value());
      else
        max_offdiag = std::max(max_offdiag, it.value());
    }
  }
  const double tol = 1e-10 * max_diag;
  for (int k = 0; k < L.outerSize(); ++k) {
    for (fem::SparseMatrix::InnerIterator it(L, k); it; ++it) {
      positive += it.row() != it.col() && it.value() > tol;
    }
  }
  std::printf("wrote %s_L.mtx and %s_M.mtx: %d×%d, %ld nonzeros in L, path %s, %zu flips, %s\n",
              prefix.c_str(), prefix.c_str(), int(L.rows()), int(L.cols()), long(L.nonZeros()),
              intrinsic::to_string(s.path), s.flips.flips,
              positive == 0
                  ? "all weights non-negative (off-diagonals ≤ 1e-10 × max diagonal)"
                  : (std::to_string(positive) + " negative weights (positive off-diagonals" +
                     ", largest " + std::to_string(max_offdiag) + ")")
                        .c_str());
  return 0;
}

}  // namespace

Command laplacian_command() {
  Command c;
  c.summary = "write the intrinsic Delaunay cotan Laplacian L and lumped mass M (Matrix Market)";
  c.spec.name = "laplacian";
  c.spec.positionals = {"MESH"};
  c.spec.prose =
      "Writes PREFIX_L.mtx (cotan Laplacian) and PREFIX_M.mtx (lumped mass, diagonal),\n"
      "Matrix Market coordinate format, 1-based, rows and columns = the input's vertices\n"
      "in the input's order (size = input vertex count, unreferenced vertices included\n"
      "with a zero row and zero mass).\n\n"
      "Sign convention: L is symmetric positive semi-definite (positive diagonal,\n"
      "L·1 = 0), the FEM stiffness matrix; libigl's cotmatrix is −L. On the intrinsic\n"
      "Delaunay triangulation every off-diagonal entry is ≤ 0. Solve L u = M f for\n"
      "Poisson problems.\n";
  c.spec.groups = {
      {"Options", {text("output", "PREFIX").short_alias('o').mandatory().explain("output prefix")}},
      surface_options()};
  c.run = run_laplacian;
  return c;
}

}  // namespace ifem::cli
