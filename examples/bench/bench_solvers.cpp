// Benchmark section `solvers`: heat-method precompute (IDT + assembly + factorizations) and
// per-query time from 10k to 1M+ faces; then the `eigen` section (bench_eigen.cpp).
//
//   ifem_bench solvers [--repeat N] [--max-n 224] [--data DIR] [--skip-eigen 1]
#include <cstdio>
#include <filesystem>
#include <fstream>
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

int eigen(int argc, char** argv);  // bench_eigen.cpp

namespace {

// What CHOLMOD chose for M + L of this mesh (ordering, supernodal, fill, flops): the heat
// method's matrices have this pattern.
std::string factor_stats(const std::vector<Triangle>& faces, const Positions& pos) {
  const fem::SparseMatrix A = idt_mass_plus_laplacian(faces, pos);
  const double t0 = seconds_now();
  const solvers::CholeskySolver chol(A);
  char buf[160];
  std::snprintf(buf, sizeof(buf), "%s %s, nnz(L) %.3g, %.3g GFlop, one factorization %.3f s",
                chol.ordering(), chol.supernodal() ? "supernodal" : "simplicial",
                chol.factor_nonzeros(), chol.factor_flops() * 1e-9, seconds_now() - t0);
  return buf;
}

void heat_row(const std::string& name, const std::vector<Triangle>& faces, const Positions& pos,
              int repeat, std::vector<std::string>& notes) {
  std::vector<double> pre, query, stages;
  int st = 1;
  Index nf = 0;
  for (int r = 0; r < repeat; ++r) {
    const double t0 = seconds_now();
    intrinsic::IntrinsicTriangulation tri =
        intrinsic::IntrinsicTriangulation::from_positions(faces, pos);
    tri.mollify();
    solvers::HeatDistanceSolver solver(tri);  // flips to IDT, assembles, factors
    pre.push_back(seconds_now() - t0);
    nf = tri.n_faces();
    for (int q = 0; q < 3; ++q) {
      solvers::HeatDistanceReport rep;
      const double t1 = seconds_now();
      solver.compute_distance({Index((q * 7919) % tri.n_vertices())}, &rep);
      query.push_back(seconds_now() - t1);
      st = std::max(st, rep.stages);
    }
  }
  std::printf("| %-22s | %9d | %10.3f | %10.4f | %6d | %8.0f |\n", name.c_str(), nf, median(pre),
              median(query), st, peak_rss_mib());
  std::fflush(stdout);
  notes.push_back(name + ": " + factor_stats(faces, pos));
}

}  // namespace

int solvers(int argc, char** argv) {
  const int repeat = int(int_option(argc, argv, "--repeat", 3));
  const int max_n = int(int_option(argc, argv, "--max-n", 224));
  const std::string data = string_option(argc, argv, "--data", IFEM_SHARED_MESHES);
  print_load_average();
  std::vector<std::string> notes;
  std::printf("## heat method (median of %d runs; query = median of 3 sources per run)\n\n",
              repeat);
  std::printf("| %-22s | %9s | %10s | %10s | %6s | %8s |\n", "mesh", "faces", "precomp s",
              "query s", "stages", "peak MiB");
  std::printf("|---|---|---|---|---|---|\n");
  for (const int n : {23, 71, 100, 158, 224}) {
    if (n > max_n) continue;
    const auto m = intrinsic::icosphere(n);
    heat_row("icosphere(" + std::to_string(n) + ")", m.faces, m.positions, repeat, notes);
  }
  for (const char* f : {"rocketship.ply", "igea_268k.ply"}) {
    const std::string path = data + "/" + f;
    if (!std::filesystem::exists(path)) continue;
    const io::SurfaceInput in = io::read_mesh(path);
    heat_row(f, in.triangles, in.positions, repeat, notes);
  }
  std::printf("\nCHOLMOD on M + L (peak MiB above is the process's so far, not per row):\n");
  for (const auto& n : notes) std::printf("- %s\n", n.c_str());
  if (int_option(argc, argv, "--skip-eigen", 0)) return 0;
  std::printf("\n");
  return eigen(argc, argv);
}

}  // namespace ifem::bench
