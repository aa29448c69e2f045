// Benchmark section `batch`: heat distances from many sources at once
// (HeatDistanceSolver::compute_distances) against one query per source, on the same solver.
//
//   ifem_bench batch [--repeat N] [--min-n 0] [--max-n 224] [--data DIR] [--kernels-only]
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <string>
#include <vector>

#include "bench_util.h"
#include "fem/operators.h"
#include "intrinsic/core/triangulation.h"
#include "intrinsic/generators/mesh_generators.h"
#include "intrinsic/io/mesh_io.h"
#include "solvers/linalg/cholesky.h"
#include "solvers/scalar/heat_distance.h"

namespace ifem::bench {
namespace {

std::vector<Index> spread_sources(Index count, Index nv) {
  std::vector<Index> s;
  for (Index k = 0; k < count; ++k) s.push_back(Index((int64_t(k) * 7919 + 13) % nv));
  return s;
}

void batch_rows(const std::string& name, const std::vector<Triangle>& faces, const Positions& pos,
                int repeat) {
  intrinsic::IntrinsicTriangulation tri =
      intrinsic::IntrinsicTriangulation::from_positions(faces, pos);
  tri.mollify();
  const double t0 = seconds_now();
  const solvers::HeatDistanceSolver solver(tri);
  const double precompute = seconds_now() - t0;
  const Index nv = tri.n_vertices();
  const std::vector<Index> one = spread_sources(1, nv);
  {
    const double single = time_median(repeat, [&] { solver.compute_distance(one); });
    solvers::HeatDistanceOptions o;
    o.precision = solvers::HeatDistanceOptions::Precision::kMixed;
    const solvers::HeatDistanceSolver mixed(tri, o);
    const double t = time_median(repeat, [&] { mixed.compute_distance(one); });
    std::printf("%s: 1 query %.4f s (double), %.4f s (mixed precision)\n", name.c_str(), single, t);
  }
  {
    // the first block pays one-time costs: its buffers and, where CHOLMOD holds the factors, our
    // block kernel over them (built on the first solve with several columns)
    const solvers::HeatDistanceSolver fresh(tri);
    const std::vector<Index> src = spread_sources(32, nv);
    const double t0_first = seconds_now();
    fresh.compute_distances(src);
    const double first = seconds_now() - t0_first;
    const double later = time_median(repeat, [&] { fresh.compute_distances(src); });
    std::printf("%s: a fresh solver's first block of 32 %.4f s, later blocks %.4f s\n",
                name.c_str(), first, later);
  }
  for (const Index k : {1, 8, 32, 128}) {
    const std::vector<Index> src = spread_sources(k, nv);
    // the same batch also written into a matrix kept between calls (no fresh memory to fault
    // in); one query, the batch and the kept batch timed in turn, round by round (each after an
    // untimed call of its own), so that their ratios compare the same moments of a shared
    // machine
    Eigen::MatrixXd kept;
    const double t_guess = seconds_now();
    solver.compute_distances(src, kept);
    // short calls get more rounds (about 0.5 s of each batch, up to 10 × repeat): 9 rounds of
    // 2 ms calls measured 10k faces 6.3× where 201 measured 9.4–10×
    const int rounds =
        std::clamp(int(0.5 / std::max(seconds_now() - t_guess, 1e-6)), repeat, 10 * repeat);
    const bench::InterleavedTimes t = time_interleaved(
        rounds, {[&] { solver.compute_distance(one); }, [&] { solver.compute_distances(src); },
                 [&] { solver.compute_distances(src, kept); }});
    const double single = t.median[0], batch = t.median[1], reused = t.median[2];
    std::printf(
        "| %-16s | %9d | %7.2f | %8.4f | %4d | %8.4f | %8.5f | %6.1f× | %6.1f× | %8.4f | %6.1f× | "
        "%8.0f |\n",
        name.c_str(), tri.n_faces(), precompute, single, k, batch, batch / double(k),
        single * double(k) / batch, t.min[0] * double(k) / t.min[1], reused,
        single * double(k) / reused, peak_rss_mib());
    std::fflush(stdout);
  }
}

// The memory bandwidth one thread reaches (the solves run on one): a triad a = b + s·c over three
// 256 MB arrays, counted as 3 × 256 MB moved (plus write-allocate traffic the hardware adds).
double triad_gb_per_s(int repeat) {
  const Eigen::Index n = Eigen::Index(1) << 25;
  Eigen::VectorXd a = Eigen::VectorXd::Zero(n), b = Eigen::VectorXd::Ones(n),
                  c = Eigen::VectorXd::Constant(n, 2.0);
  const double t = time_median(repeat, [&] { a.noalias() = b + 0.5 * c; });
  return 3.0 * 8.0 * double(n) / t * 1e-9;
}

// One factor of M + L (the heat matrix's pattern) solved by each kernel: CHOLMOD's simplicial
// one (walks the factor once per 4 columns), CHOLMOD's supernodal one (once per block, BLAS-3),
// and ours over the supernodal factor in double and in single precision (once per block, two
// threads on large factors): seconds per solve of k right-hand sides at once, and the factor
// bytes a solve reads per second (once per block; per 4 columns for CHOLMOD's simplicial).
void solve_kernel_rows(const std::string& name, const std::vector<Triangle>& faces,
                       const Positions& pos, int repeat) {
  using Kernel = solvers::CholeskyOptions::SolveKernel;
  Index nf = 0;
  const fem::SparseMatrix A = idt_mass_plus_laplacian(faces, pos, &nf);
  struct Variant {
    const char* name;
    bool simplicial;
    Kernel kernel;
    bool metis = false;
  };
  const Variant variants[] = {{"CHOLMOD simplicial", true, Kernel::kCholmod},
                              {"CHOLMOD supernodal", false, Kernel::kCholmod},
                              {"ours, double", false, Kernel::kSupernodalDouble},
                              {"ours, single", false, Kernel::kSupernodalSingle},
                              {"ours, double, METIS", false, Kernel::kSupernodalDouble, true},
                              {"ours, single, METIS", false, Kernel::kSupernodalSingle, true}};
  Eigen::MatrixXd reference;
  for (const Variant& v : variants) {
    solvers::CholeskyOptions o;
    o.simplicial_solves = v.simplicial;
    o.solve_kernel = v.kernel;
    o.force_metis = v.metis;
    const solvers::CholeskySolver chol(A, o);
    for (const Eigen::Index k : {1, 4, 8, 32}) {
      std::srand(unsigned(k));  // the same right-hand sides for every kernel
      const Eigen::MatrixXd B = Eigen::MatrixXd::Random(A.rows(), k);
      Eigen::MatrixXd X(A.rows(), k);
      const double t = time_median(repeat, [&] { chol.solve(B.data(), X.data(), k); });
      const double reads = v.simplicial ? double((k + 3) / 4) : 1.0;
      if (k == 1 && !reference.size()) reference = X;
      const double error =
          k == 1 ? (X - reference).cwiseAbs().maxCoeff() / reference.cwiseAbs().maxCoeff() : 0.0;
      std::printf("| %-16s | %9d | %-19s | %3d | %9.5f | %9.5f | %7.1f | %6.2f | %8.1e |\n",
                  name.c_str(), nf, v.name, int(k), t, t / double(k), chol.solve_bytes() * 1e-6,
                  chol.solve_bytes() * reads / t * 1e-9, error);
      std::fflush(stdout);
    }
  }
}

}  // namespace

// Queries (--sources K: K at once, compute_distances) on one icosphere or --mesh FILE (for
// profilers: `perf record ifem_bench query`).
int query(int argc, char** argv) {
  const int repeat = int(int_option(argc, argv, "--repeat", 21));
  const int n = int(int_option(argc, argv, "--n", 224));
  print_load_average();
  const std::string mesh = string_option(argc, argv, "--mesh", "");
  std::string name = "icosphere(" + std::to_string(n) + ")";
  std::vector<Triangle> faces;
  Positions pos;
  if (mesh.empty()) {
    auto m = intrinsic::icosphere(n);
    faces = std::move(m.faces);
    pos = std::move(m.positions);
  } else {
    io::SurfaceInput in = io::read_mesh(mesh);
    faces = std::move(in.triangles);
    pos = std::move(in.positions);
    name = std::filesystem::path(mesh).filename().string();
  }
  intrinsic::IntrinsicTriangulation tri =
      intrinsic::IntrinsicTriangulation::from_positions(faces, pos);
  tri.mollify();
  solvers::HeatDistanceOptions o;
  if (has_flag(argc, argv, "--mixed")) {
    o.precision = solvers::HeatDistanceOptions::Precision::kMixed;
  }
  const double t0 = seconds_now();
  const solvers::HeatDistanceSolver solver(tri, o);
  const double precompute = seconds_now() - t0;
  const Index k = Index(int_option(argc, argv, "--sources", 1));
  const std::vector<Index> src = spread_sources(k, tri.n_vertices());
  // --kept: a block written into a matrix kept between calls (no fresh memory to fault in)
  const bool kept = has_flag(argc, argv, "--kept");
  Eigen::MatrixXd out;
  const double t = time_median(repeat, [&] {
    if (k == 1) {
      solver.compute_distance(src);
    } else if (kept) {
      solver.compute_distances(src, out);
    } else {
      solver.compute_distances(src);
    }
  });
  solvers::HeatDistanceReport rep;
  solver.compute_distance({src[0]}, &rep);
  std::printf("first source: %d stage(s), %d unresolved vertices in the first\n", int(rep.stages),
              int(rep.unresolved_vertices));
  std::printf(
      "%s, %d faces: precompute %.3f s, %d source(s) %.4f s, %.5f s per source (median of %d)\n",
      name.c_str(), int(tri.n_faces()), precompute, int(k), t, t / double(k), repeat);
  return 0;
}

int batch(int argc, char** argv) {
  const int repeat = int(int_option(argc, argv, "--repeat", 5));
  const int max_n = int(int_option(argc, argv, "--max-n", 224));
  const std::string data = string_option(argc, argv, "--data", IFEM_SHARED_MESHES);
  print_load_average();
  std::printf("## batched heat distances (median of %d runs)\n\n", repeat);
  std::printf("| %-16s | %9s | %7s | %8s | %4s | %8s | %8s | %7s | %7s | %8s | %7s | %8s |\n",
              "mesh", "faces", "precomp s", "1 query s", "k", "batch s", "per src s", "gain",
              "quiet gain", "kept out s", "gain", "peak MiB");
  std::printf("|---|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|\n");
  const int min_n = int(int_option(argc, argv, "--min-n", 0));
  const bool kernels_only = has_flag(argc, argv, "--kernels-only");
  for (const int n : {23, 71, 224}) {
    if (n > max_n || n < min_n || kernels_only) continue;
    const auto m = intrinsic::icosphere(n);
    batch_rows("icosphere(" + std::to_string(n) + ")", m.faces, m.positions, repeat);
  }
  for (const char* f : {"rocketship.ply", "igea_268k.ply"}) {
    const std::string path = data + "/" + f;
    if (!std::filesystem::exists(path) || kernels_only) continue;
    const io::SurfaceInput in = io::read_mesh(path);
    batch_rows(f, in.triangles, in.positions, repeat);
  }
  std::printf(
      "\ngain = k × (1 query s) / (batch s): how many times cheaper a source is in a batch (one\n"
      "query, the batch and the kept batch timed in turn, round by round, each after an untimed\n"
      "call of its own: medians of each; --repeat rounds, more for short calls);\n"
      "quiet gain: the same from each one's quietest round (minimum), which a busy neighbour\n"
      "cannot inflate (it slows the bandwidth-bound query more than the batch);\n"
      "kept out: compute_distances(sources, out) into a matrix kept between calls (a fresh\n"
      "#V × k matrix is zeroed by the system on first touch)\n");
  std::printf("\n## one solve with k right-hand sides (forward + backward), M + L factor\n\n");
  std::printf("one thread's memory bandwidth (triad over 3 × 256 MB): %.1f GB/s\n\n",
              triad_gb_per_s(repeat));
  std::printf(
      "| mesh | faces | kernel | k | solve s | per column s | MB per read | GB/s | rel. diff |\n");
  std::printf("|---|---:|---|---:|---:|---:|---:|---:|---:|\n");
  for (const int n : {71, 224}) {
    if (n > max_n || n < min_n) continue;
    const auto m = intrinsic::icosphere(n);
    solve_kernel_rows("icosphere(" + std::to_string(n) + ")", m.faces, m.positions, repeat);
  }
  return 0;
}

}  // namespace ifem::bench
