// Benchmark section `vector_heat`: the Vector Heat Method's precompute and queries against the
// scalar heat method's on the same meshes (issue 14's targets: precompute within 1.5×, queries
// within 2×), and the choices for the complex factorization of M + tL∇ (AMD, METIS, the real
// 2n×2n form).
//
//   ifem_bench vector_heat [--repeat N] [--max-n 224] [--orderings N (icosphere(N); 0 = skip)]
//                          [--log-map-mesh FILE[,FILE...] (the two log-map methods on these)]
#include <algorithm>
#include <complex>
#include <cstdio>
#include <fstream>
#include <string>
#include <vector>

#include "bench_util.h"
#include "fem/connection.h"
#include "fem/operators.h"
#include "intrinsic/core/geometry.h"
#include "intrinsic/core/triangulation.h"
#include "intrinsic/generators/mesh_generators.h"
#include "intrinsic/io/mesh_io.h"
#include "solvers/linalg/cholesky.h"
#include "solvers/recipes/pipeline.h"
#include "solvers/recipes/tangent_fields.h"
#include "solvers/scalar/heat_distance.h"
#include "solvers/vector/vector_heat.h"

namespace ifem::bench {
namespace {

using Complex = std::complex<double>;

struct VectorHeatTimes {
  std::vector<double> heat_pre, heat_query, pre, transport, transport2, extend, log_first, log;
};

// One run on a fresh solver of each kind (the scalar one destroyed before the vector one is
// built, so the peak is the larger of the two, as for a user holding one).
void vector_heat_run(const intrinsic::IntrinsicTriangulation& tri, VectorHeatTimes& t) {
  const Index nv = tri.n_vertices();
  const Index a = nv / 3, b = (2 * nv) / 3;
  {
    double t0 = seconds_now();
    const solvers::HeatDistanceSolver heat(tri);
    t.heat_pre.push_back(seconds_now() - t0);
    t0 = seconds_now();
    heat.compute_distance({a});
    t.heat_query.push_back(seconds_now() - t0);
  }
  double t0 = seconds_now();
  const solvers::VectorHeatSolver vh(tri);
  t.pre.push_back(seconds_now() - t0);
  t0 = seconds_now();
  vh.transport({{a, Complex(1.0, 0.5)}});
  t.transport.push_back(seconds_now() - t0);
  t0 = seconds_now();
  vh.transport({{a, Complex(1.0, 0.5)}, {b, Complex(-2.0, 0.0)}});
  t.transport2.push_back(seconds_now() - t0);
  t0 = seconds_now();
  vh.extend_scalar({{a, 1.0}, {b, 2.0}});
  t.extend.push_back(seconds_now() - t0);
  t0 = seconds_now();
  vh.log_map(a);
  t.log_first.push_back(seconds_now() - t0);
  t0 = seconds_now();
  vh.log_map(b);
  t.log.push_back(seconds_now() - t0);
}

void vector_heat_row(int n, int repeat) {
  const auto m = intrinsic::icosphere(n);
  auto tri = intrinsic::IntrinsicTriangulation::from_positions(m.faces, m.positions);
  tri.mollify();
  VectorHeatTimes t;
  for (int r = 0; r < repeat; ++r) vector_heat_run(tri, t);
  const double hp = median(t.heat_pre), hq = median(t.heat_query), vp = median(t.pre);
  const double tq = median(t.transport);
  std::printf(
      "| icosphere(%d) | %zu | %.3f | %.4f | %.3f | %.2f | %.4f | %.2f | %.4f | %.4f | %.3f | "
      "%.4f | %.0f |\n",
      n, m.faces.size(), hp, hq, vp, vp / hp, tq, tq / hq, median(t.transport2), median(t.extend),
      median(t.log_first), median(t.log), peak_rss_mib());
  std::fflush(stdout);
}

// M + tL∇ (t = h²) on the intrinsic Delaunay triangulation of icosphere(n).
solvers::ComplexSparseMatrix vector_heat_matrix(int n, fem::SparseMatrix* scalar) {
  const auto m = intrinsic::icosphere(n);
  auto tri = intrinsic::IntrinsicTriangulation::from_positions(m.faces, m.positions);
  tri.flip_to_delaunay();
  const double h = intrinsic::mean_edge_length(tri);
  const Eigen::VectorXd mass = fem::lumped_mass(tri);
  const fem::TangentFrames frames = fem::tangent_frames(tri);
  solvers::ComplexSparseMatrix A = h * h * fem::connection_laplacian(tri, frames, 1);
  fem::SparseMatrix S = h * h * fem::cotan_laplacian(tri);
  for (Index v = 0; v < tri.n_vertices(); ++v) {
    A.coeffRef(v, v) += mass[v];
    S.coeffRef(v, v) += mass[v];
  }
  A.makeCompressed();
  S.makeCompressed();
  *scalar = S;
  return A;
}

// The real symmetric 2n×2n form [Re −Im; Im Re] of a Hermitian matrix, entries interleaved
// (unknowns 2i, 2i + 1 = Re, Im of x_i) so that AMD sees 2×2 blocks.
fem::SparseMatrix real_form(const solvers::ComplexSparseMatrix& A) {
  std::vector<Eigen::Triplet<double>> trip;
  trip.reserve(static_cast<std::size_t>(4 * A.nonZeros()));
  for (Eigen::Index j = 0; j < A.outerSize(); ++j) {
    for (solvers::ComplexSparseMatrix::InnerIterator it(A, j); it; ++it) {
      const Eigen::Index i = it.row();
      const Complex z = it.value();
      trip.emplace_back(2 * i, 2 * j, z.real());
      trip.emplace_back(2 * i + 1, 2 * j + 1, z.real());
      trip.emplace_back(2 * i + 1, 2 * j, z.imag());
      trip.emplace_back(2 * i, 2 * j + 1, -z.imag());
    }
  }
  fem::SparseMatrix R(2 * A.rows(), 2 * A.cols());
  R.setFromTriplets(trip.begin(), trip.end());
  return R;
}

template <class Solver, class Matrix>
void ordering_row(const char* what, const Matrix& A, bool metis, int threads, int repeat) {
  solvers::CholeskyOptions o;
  o.force_metis = metis;
  o.factor_blas_threads = threads;
  double nnz = 0.0, solve = 0.0;
  const double t = time_median(repeat, [&] {
    const Solver chol(A, o);
    nnz = chol.factor_nonzeros();
    using Vector = Eigen::Matrix<typename Matrix::Scalar, Eigen::Dynamic, 1>;
    const Vector rhs = Vector::Ones(A.rows());
    chol.solve(rhs);
    const double t0 = seconds_now();
    chol.solve(rhs);
    solve = seconds_now() - t0;
  });
  std::printf("| %s | %s | %d | %.3f | %.4f | %.3g | %.0f |\n", what, metis ? "METIS" : "AMD",
              threads, t, solve, nnz, peak_rss_mib());
  std::fflush(stdout);
}

// The three log-map methods on a prepared mesh file (what `ifem logmap` runs) against one scalar
// heat query of geodesic_distance() in the same process: solver precompute, then the first and
// a later query of each method (the vector heat method's first builds its distance solver; the
// blend runs after it and reuses it).
void log_map_methods_row(const std::string& path, int repeat) {
  const solvers::PreparedSurface s = solvers::prepare_surface(io::read_mesh(path));
  const Index nv = s.n_input_vertices();
  const Index a = nv / 3, b = (2 * nv) / 3;
  std::vector<double> heat, pre, aff_first, aff, vh_first, vh, blend;
  for (int r = 0; r < repeat; ++r) {
    {
      const solvers::HeatDistanceSolver d(s.tri, solvers::distance_options(s));
      d.compute_distance({a});  // warm-up
      const double t0 = seconds_now();
      d.compute_distance({b});
      heat.push_back(seconds_now() - t0);
    }
    double t0 = seconds_now();
    const solvers::VectorHeatSolver solver = solvers::vector_heat_solver(s);
    pre.push_back(seconds_now() - t0);
    const auto time = [&](Index v, solvers::LogMapMethod m, std::vector<double>& out) {
      const double t1 = seconds_now();
      solver.log_map(v, m);
      out.push_back(seconds_now() - t1);
    };
    time(a, solvers::LogMapMethod::kAffine, aff_first);
    time(b, solvers::LogMapMethod::kAffine, aff);
    time(a, solvers::LogMapMethod::kVectorHeat, vh_first);
    time(b, solvers::LogMapMethod::kVectorHeat, vh);
    time(a, solvers::LogMapMethod::kBlend, blend);
  }
  const double hq = median(heat);
  std::printf(
      "| %s | %zu | %.4f | %.3f | %.4f | %.4f | %.2f | %.4f | %.4f | %.2f | %.4f | %.2f | %.0f |\n",
      path.substr(path.find_last_of('/') + 1).c_str(), s.input.triangles.size(), hq, median(pre),
      median(aff_first), median(aff), median(aff) / hq, median(vh_first), median(vh),
      median(vh) / hq, median(blend), median(blend) / hq, peak_rss_mib());
  std::fflush(stdout);
}

}  // namespace

int vector_heat(int argc, char** argv) {
  const int repeat = int(int_option(argc, argv, "--repeat", 3));
  const int max_n = int(int_option(argc, argv, "--max-n", 224));
  const int orderings_n = int(int_option(argc, argv, "--orderings", 224));
  const std::string log_map_meshes = string_option(argc, argv, "--log-map-mesh", "");
  print_load_average();
  if (!log_map_meshes.empty()) {
    std::printf(
        "## Log map: the three methods (median of %d; heat query = one "
        "HeatDistanceSolver query on the same surface)\n\n"
        "| mesh | faces | heat query s | vector heat precomp s | affine first s | affine s | "
        "ratio | vector-heat first s | vector-heat s | ratio | blend s | ratio | peak MiB |\n"
        "|---|---|---|---|---|---|---|---|---|---|---|---|---|\n",
        repeat);
    std::size_t start = 0;
    while (start <= log_map_meshes.size()) {
      const std::size_t comma = std::min(log_map_meshes.find(',', start), log_map_meshes.size());
      log_map_methods_row(log_map_meshes.substr(start, comma - start), repeat);
      start = comma + 1;
    }
    return 0;
  }
  std::printf(
      "## Vector heat against scalar heat (median of %d; each run: fresh HeatDistanceSolver, "
      "then a fresh VectorHeatSolver)\n\n",
      repeat);
  std::printf(
      "| mesh | faces | heat precomp s | heat query s | vector precomp s | ratio | transport s | "
      "ratio | transport 2 src s | extend s | first log map s | log map s | peak MiB |\n");
  std::printf("|---|---|---|---|---|---|---|---|---|---|---|---|---|\n");
  for (const int n : {23, 71, 158, 224}) {
    if (n <= max_n) vector_heat_row(n, repeat);
  }
  if (orderings_n <= 0) return 0;
  std::printf(
      "\n## Factoring M + tL∇ of icosphere(%d) (constructor = analysis + factorization + "
      "conversion; one solve after a warm-up one; median of %d)\n\n",
      orderings_n, repeat);
  std::printf(
      "| matrix | ordering | BLAS threads | factor s | solve s | nnz(L) | peak MiB |\n"
      "|---|---|---|---|---|---|---|\n");
  fem::SparseMatrix scalar;
  const solvers::ComplexSparseMatrix A = vector_heat_matrix(orderings_n, &scalar);
  for (const int threads : {1, 2}) {
    const char* ref = "real M + tL (reference)";
    ordering_row<solvers::CholeskySolver>(ref, scalar, false, threads, repeat);
    ordering_row<solvers::CholeskySolver>(ref, scalar, true, threads, repeat);
    ordering_row<solvers::ComplexCholeskySolver>("complex M + tL∇", A, false, threads, repeat);
    ordering_row<solvers::ComplexCholeskySolver>("complex M + tL∇", A, true, threads, repeat);
  }
  const fem::SparseMatrix R = real_form(A);
  ordering_row<solvers::CholeskySolver>("real 2n form of M + tL∇", R, false, 1, repeat);
  return 0;
}

}  // namespace ifem::bench
