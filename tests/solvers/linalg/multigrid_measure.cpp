// Measurement tool (not a test): heat distance on icosphere(n) with the direct solver or with
// multigrid on the nested icosphere hierarchy (tests/solvers/linalg/nested_hierarchies.h).
//   ifem_multigrid_measure N direct|multigrid [LEVELS] [STEPS] [gs|jacobi] [TIME_FACTOR]
//   [CORRECTION_STEPS]
//   ifem_multigrid_measure N write FILE.ply   (the icosphere as a binary PLY, for `ifem distance`)
//   ifem_multigrid_measure N linear [LEVELS] [STEPS] [gs|jacobi]   (PCG on M + tL and pinned L;
//   LEVELS 0: the library's simplification hierarchy instead of the nested one, its CPU time)
//   ifem_multigrid_measure MESH_FILE linear   (the same on a manifold mesh file, flipped to
//   intrinsic Delaunay, with the simplification hierarchy)
//   ifem_multigrid_measure N pinned   (L pinned at vertex 0 on the default simplification
//   hierarchy: the vertex eliminated with its row of P₀, or kept as a decoupled row with it)
// Prints the set-up and query times, the peak resident memory after each phase, the PCG
// figures of one heat solve and the distance error against the great-circle distance.
#include <sys/resource.h>

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <ctime>
#include <string>

#include "fem/operators.h"
#include "intrinsic/core/geometry.h"
#include "intrinsic/core/triangulation.h"
#include "intrinsic/io/mesh_io.h"
#include "solvers/linalg/nested_hierarchies.h"
#include "solvers/scalar/heat_distance.h"
#include "solvers/scalar/solver_choice.h"

using namespace ifem;

namespace {
double peak_gib() {
  rusage u{};
  getrusage(RUSAGE_SELF, &u);
  return double(u.ru_maxrss) / (1024.0 * 1024.0);
}
double seconds_since(std::chrono::steady_clock::time_point t0) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
}
// M + tL (t = h²) and L with vertex 0 eliminated: PCG (iterations, reduction per cycle, seconds
// per solve of a point source) against the Cholesky factor (factor seconds, solve seconds, MB).
int linear(const intrinsic::TriangleMesh& mesh, const intrinsic::IntrinsicTriangulation& tri, int n,
           int levels, int steps, bool jacobi) {
  (void)mesh;
  const double h = intrinsic::mean_edge_length(tri);
  const solvers::SparseMatrix L = fem::cotan_laplacian(tri);
  const Eigen::VectorXd m = fem::lumped_mass(tri);
  solvers::SparseMatrix H = h * h * L;
  for (Eigen::Index i = 0; i < H.rows(); ++i) H.coeffRef(i, i) += m[i];
  std::vector<int> keep;
  for (int v = 1; v < int(L.rows()); ++v) keep.push_back(v);
  const solvers::SparseMatrix Lp =
      test::keep_rows(solvers::SparseMatrix(test::keep_rows(L, keep).transpose()), keep);
  const std::clock_t c0 = std::clock();
  auto chain =
      levels > 0 ? test::icosphere_hierarchy(n, levels) : solvers::simplification_hierarchy(tri);
  std::printf("hierarchy: %s, %.2f CPU s, levels (vertices):", levels > 0 ? "nested" : "simplified",
              double(std::clock() - c0) / CLOCKS_PER_SEC);
  for (const auto& P : chain) std::printf(" %d", int(P.cols()));
  std::printf("\n");
  solvers::MultigridOptions o;
  o.smoothing_steps = steps;
  if (jacobi) o.smoother = solvers::MultigridOptions::Smoother::kJacobi;
  for (int which = 0; which < 2; ++which) {
    const solvers::SparseMatrix& A = which == 0 ? H : Lp;
    std::vector<solvers::SparseMatrix> c = chain;
    if (which == 1) c[0] = test::keep_rows(c[0], keep);
    Eigen::VectorXd b = Eigen::VectorXd::Zero(A.rows());
    b[7] = 1.0;
    if (which == 1) b = b - Eigen::VectorXd::Constant(b.size(), 1.0 / double(b.size()));
    auto t0 = std::chrono::steady_clock::now();
    const solvers::MultigridSolver mg(A, c, o);
    const double build = seconds_since(t0);
    t0 = std::chrono::steady_clock::now();
    solvers::MultigridReport rep;
    const Eigen::VectorXd x = mg.solve(b, &rep);
    const double solve = seconds_since(t0);
    t0 = std::chrono::steady_clock::now();
    const solvers::SparseMatrix lower = A.triangularView<Eigen::Lower>();
    const solvers::CholeskySolver chol(lower);
    const double factor = seconds_since(t0);
    t0 = std::chrono::steady_clock::now();
    const Eigen::VectorXd y = chol.solve(b);
    const double csolve = seconds_since(t0);
    std::printf(
        "%s: multigrid build %.2f s, %.1f MB, PCG %d iterations, %.3f per cycle, %.2f s; "
        "Cholesky factor %.2f s, %.1f MB, solve %.3f s; |x-y|/|y| %.2g\n",
        which == 0 ? "M + tL" : "pinned L", build, mg.memory_bytes() / 1e6, rep.iterations,
        rep.reduction_per_cycle, solve, factor, 12e-6 * chol.factor_nonzeros(), csolve,
        (x - y).norm() / y.norm());
  }
  return 0;
}

// The pinned Laplacian two ways on the default hierarchy (D-335): vertex 0 eliminated (its row
// of P₀ dropped), or kept as a decoupled row (a_00 = L_00, zero off-diagonal) with P₀ whole.
// PCG iterations, reduction per cycle and seconds for one right-hand side, and the difference.
int pinned(const intrinsic::IntrinsicTriangulation& tri) {
  const solvers::SparseMatrix L = fem::cotan_laplacian(tri);
  auto t0 = std::chrono::steady_clock::now();
  const std::vector<solvers::SparseMatrix> chain = solvers::default_hierarchy_provider()(tri);
  std::printf("hierarchy %.2f s, %zu prolongations\n", seconds_since(t0), chain.size());
  const Eigen::Index n = L.rows();
  std::vector<int> keep;
  for (int v = 1; v < int(n); ++v) keep.push_back(v);
  Eigen::VectorXd b = Eigen::VectorXd::Zero(n);
  b[7] = 1.0;
  b.array() -= 1.0 / double(n);
  b[0] = 0.0;
  solvers::SparseMatrix decoupled = L;
  for (Eigen::Index j = 0; j < n; ++j) {
    for (solvers::SparseMatrix::InnerIterator it(decoupled, j); it; ++it) {
      if ((it.row() == 0 || j == 0) && it.row() != j) it.valueRef() = 0.0;
    }
  }
  Eigen::VectorXd x[2];
  for (int which = 0; which < 2; ++which) {
    std::vector<solvers::SparseMatrix> c = chain;
    solvers::SparseMatrix A;
    Eigen::VectorXd rhs = b;
    if (which == 0) {
      c[0] = test::keep_rows(c[0], keep);
      A = test::keep_rows(solvers::SparseMatrix(test::keep_rows(L, keep).transpose()), keep);
      rhs = b.tail(n - 1);
    } else {
      A = decoupled;
    }
    t0 = std::chrono::steady_clock::now();
    const solvers::MultigridSolver mg(A, c);
    const double build = seconds_since(t0);
    t0 = std::chrono::steady_clock::now();
    solvers::MultigridReport rep;
    const Eigen::VectorXd sol = mg.solve(rhs, &rep);
    x[which] = which == 0 ? Eigen::VectorXd(n) : sol;
    if (which == 0) {
      x[0][0] = 0.0;
      x[0].tail(n - 1) = sol;
    }
    std::printf("%s: build %.2f s, %.1f MB, PCG %d iterations, %.3f per cycle, %.2f s\n",
                which == 0 ? "vertex eliminated, row of P0 dropped" : "decoupled row, P0 whole",
                build, mg.memory_bytes() / 1e6, rep.iterations, rep.reduction_per_cycle,
                seconds_since(t0));
  }
  std::printf("|x_eliminated - x_decoupled| / |x_eliminated| = %.2g\n",
              (x[0] - x[1]).norm() / x[0].norm());
  return 0;
}

}  // namespace

int main(int argc, char** argv) {
  if (argc < 3) {
    std::fprintf(stderr, "usage: %s N direct|multigrid [LEVELS] [STEPS] [jacobi]\n", argv[0]);
    return 2;
  }
  const std::string kind = argv[2];
  if (std::string(argv[1]).find_first_not_of("0123456789") != std::string::npos) {
    if (kind != "linear") return 2;
    const io::SurfaceInput in = io::read_mesh(argv[1]);
    auto tri = intrinsic::IntrinsicTriangulation::from_positions(in.triangles, in.positions);
    tri.flip_to_delaunay();
    std::printf("%s: %d faces, %d vertices\n", argv[1], int(tri.n_faces()), int(tri.n_vertices()));
    return linear(intrinsic::TriangleMesh{}, tri, 0, 0, argc > 4 ? std::atoi(argv[4]) : 1,
                  argc > 5 && std::string(argv[5]) == "jacobi");
  }
  const int n = std::atoi(argv[1]);
  const int levels = argc > 3 ? std::atoi(argv[3]) : 5;
  const int steps = argc > 4 ? std::atoi(argv[4]) : 1;
  const bool jacobi = argc > 5 && std::string(argv[5]) == "jacobi";
  const double time_factor = argc > 6 ? std::atof(argv[6]) : 1.0;
  const int correction_steps = argc > 7 ? std::atoi(argv[7]) : 0;
  auto t0 = std::chrono::steady_clock::now();
  const intrinsic::TriangleMesh mesh = intrinsic::icosphere(n);
  if (kind == "write" && argc > 3) {
    io::write_ply(argv[3], mesh.positions, mesh.faces);
    return 0;
  }
  const auto tri = intrinsic::IntrinsicTriangulation::from_positions(mesh.faces, mesh.positions);
  std::printf("icosphere(%d): %zu faces, %d vertices; mesh %.2f s, peak %.2f GiB\n", n,
              mesh.faces.size(), int(tri.n_vertices()), seconds_since(t0), peak_gib());
  if (kind == "linear") return linear(mesh, tri, n, levels, steps, jacobi);
  if (kind == "pinned") return pinned(tri);
  solvers::HeatDistanceOptions o;
  o.time_factor = time_factor;
  o.correction_steps = correction_steps;
  double hierarchy_s = 0.0;
  if (kind == "multigrid") {
    o.solver.kind = solvers::LinearSolverKind::kMultigrid;
    o.solver.multigrid.smoothing_steps = steps;
    if (jacobi) o.solver.multigrid.smoother = solvers::MultigridOptions::Smoother::kJacobi;
    o.solver.hierarchy = [&](const intrinsic::IntrinsicTriangulation&) {
      const auto h0 = std::chrono::steady_clock::now();
      auto chain = test::icosphere_hierarchy(n, levels);
      hierarchy_s = seconds_since(h0);
      return chain;
    };
  }
  t0 = std::chrono::steady_clock::now();
  const solvers::HeatDistanceSolver solver(tri, o);
  const double setup_s = seconds_since(t0);
  std::printf("set-up %.2f s (of which the test hierarchy %.2f s), peak %.2f GiB\n", setup_s,
              hierarchy_s, peak_gib());
  t0 = std::chrono::steady_clock::now();
  solvers::HeatDistanceReport report;
  const Eigen::VectorXd d = solver.compute_distance({0}, &report);
  const double query_s = seconds_since(t0);
  std::vector<double> rel;
  for (Eigen::Index v = 1; v < d.size(); ++v) {
    const double exact =
        std::acos(std::clamp(mesh.positions.row(v).dot(mesh.positions.row(0)), -1.0, 1.0));
    rel.push_back(std::abs(d[v] - exact) / exact);
  }
  std::nth_element(rel.begin(), rel.begin() + long(rel.size() / 2), rel.end());
  std::printf("query %.2f s, %d stages, peak %.2f GiB; median relative error %.3g%%\n", query_s,
              report.stages, peak_gib(), 100.0 * rel[rel.size() / 2]);
  std::printf("end to end (set-up + query) %.2f s\n", setup_s + query_s);
  return 0;
}
