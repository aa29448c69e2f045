// Benchmark section `eigen`: k = 10 and 50 eigenpairs L φ = λ M φ on icosphere(71) (100,820
// faces, intrinsic Delaunay, not mollified), with 1 and the default OpenBLAS thread count,
// Spectra's iterations and solves, and the factorization of L − σM on its own. `--write DIR` writes
// L and M as Matrix Market (DIR/L.mtx, DIR/M.mtx) for scripts/eigsh_scipy.py. Also run at the
// end of the `solvers` section.
//
//   ifem_bench eigen [--repeat N] [--write DIR]
#include <cstdio>
#include <string>

#include "bench_util.h"
#include "fem/operators.h"
#include "intrinsic/core/triangulation.h"
#include "intrinsic/generators/mesh_generators.h"
#include "intrinsic/io/mesh_io.h"
#include "solvers/linalg/cholesky.h"
#include "solvers/scalar/eigen.h"

namespace ifem::bench {
namespace {

// The factorization eigenpairs() runs: lower triangle of L − σM, σ = −shift_scale / area, one
// BLAS thread.
double factor_seconds(const fem::SparseMatrix& L, const Eigen::VectorXd& m, int repeat) {
  const double sigma = -solvers::EigenOptions{}.shift_scale / m.sum();
  fem::SparseMatrix A = L.triangularView<Eigen::Lower>();
  for (Eigen::Index j = 0; j < A.outerSize(); ++j) {
    for (fem::SparseMatrix::InnerIterator it(A, j); it; ++it) {
      if (it.row() == j) it.valueRef() -= sigma * m[j];
    }
  }
  solvers::CholeskyOptions o;
  o.factor_blas_threads = 1;
  return time_median(repeat, [&] { const solvers::CholeskySolver chol(A, o); });
}

void write_problem(const std::string& dir, const fem::SparseMatrix& L, const Eigen::VectorXd& m) {
  fem::SparseMatrix M;
  M = m.asDiagonal();
  io::write_matrix_market(dir + "/L.mtx", L);
  io::write_matrix_market(dir + "/M.mtx", M);
  std::printf("wrote %s/L.mtx and %s/M.mtx (%ld vertices)\n\n", dir.c_str(), dir.c_str(),
              long(m.size()));
}

}  // namespace

int eigen(int argc, char** argv) {
  const int repeat = int(int_option(argc, argv, "--repeat", 3));
  const std::string dir = string_option(argc, argv, "--write", "");
  print_load_average();
  const auto mesh = intrinsic::icosphere(71);
  auto tri = intrinsic::IntrinsicTriangulation::from_positions(mesh.faces, mesh.positions);
  tri.flip_to_delaunay();
  const fem::SparseMatrix L = fem::cotan_laplacian(tri);
  const Eigen::VectorXd m = fem::lumped_mass(tri);
  if (!dir.empty()) write_problem(dir, L, m);
  std::printf(
      "## eigenpairs L φ = λ M φ on icosphere(71) (%d faces, %ld vertices), median of %d\n\n",
      int(tri.n_faces()), long(m.size()), repeat);
  std::printf("factorization of L − σM alone (one BLAS thread): %.3f s\n\n",
              factor_seconds(L, m, repeat));
  std::printf("| k | BLAS threads | seconds | iterations | solves | λ_k | peak MiB |\n");
  std::printf("|---|---|---|---|---|---|---|\n");
  // the process's OpenBLAS setting (0 without OpenBLAS): eigenpairs() runs at one BLAS
  // thread whatever it is (both rows should agree but for noise)
  const int threads_default = solvers::BlasThreadScope::current();
  for (const Index k : {10, 50}) {
    for (const int threads : {1, threads_default}) {
      solvers::EigenPairs ep;
      const solvers::BlasThreadScope blas(threads);
      const double t = time_median(repeat, [&] { ep = solvers::eigenpairs(L, m, k); });
      std::printf("| %d | %d | %.3f | %d | %d | %.6f | %.0f |\n", k, threads, t, int(ep.iterations),
                  int(ep.solves), ep.values[k - 1], peak_rss_mib());
      std::fflush(stdout);
      if (threads_default <= 1) break;
    }
  }
  return 0;
}

}  // namespace ifem::bench
