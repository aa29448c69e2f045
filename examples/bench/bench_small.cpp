// Benchmark section `small`: what a short run pays on one mesh, in a fresh process — the first
// L + M (thread start-up included) or the first heat precompute, then the median of repeats —
// so that scripts/bench_small.sh can compare default threads with OMP_NUM_THREADS=1 process by
// process (issue 15, item 3).
//
// `--what factor` times one factorization of the heat matrix M + L (analysis included)
// supernodal-then-simplicial (the default) against simplicial from the start.
//
// `--what precompute-threads` times the precompute with the default OpenMP threads and with one,
// taking turns in one process.
//
// `--retain-memory 0` leaves glibc's default of handing freed memory back to the kernel (the CLI
// keeps it: retain_freed_memory()).
//
//   ifem_bench small --mesh FILE|icosphere:N [--what lm|precompute|precompute-threads|factor]
//   [--repeat N] [--retain-memory 0|1]
#include <cstdio>
#include <ctime>
#include <string>
#include <vector>

#include "bench_util.h"
#include "fem/operators.h"
#include "intrinsic/core/triangulation.h"
#include "intrinsic/generators/mesh_generators.h"
#include "intrinsic/io/mesh_io.h"
#include "solvers/linalg/cholesky.h"
#include "solvers/linalg/memory.h"
#include "solvers/scalar/heat_distance.h"

#if defined(_OPENMP)
#include <omp.h>
#endif

namespace ifem::bench {
namespace {

struct Mesh {
  std::vector<Triangle> faces;
  Positions positions;
};

double process_cpu_seconds() {
  timespec ts{};
  clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &ts);
  return double(ts.tv_sec) + 1e-9 * double(ts.tv_nsec);
}

Mesh load(const std::string& spec) {
  const std::string ico = "icosphere:";
  if (spec.rfind(ico, 0) == 0) {
    const auto m = intrinsic::icosphere(std::stoi(spec.substr(ico.size())));
    return {m.faces, m.positions};
  }
  const io::SurfaceInput in = io::read_mesh(spec);
  return {in.triangles, in.positions};
}

}  // namespace

int small(int argc, char** argv) {
  const int repeat = int(int_option(argc, argv, "--repeat", 5));
  const std::string spec = string_option(argc, argv, "--mesh", "icosphere:23");
  const std::string what = string_option(argc, argv, "--what", "lm");
  if (int_option(argc, argv, "--retain-memory", 1) != 0) retain_freed_memory();  // as the CLI
  const Mesh m = load(spec);
  auto tri = intrinsic::IntrinsicTriangulation::from_positions(m.faces, m.positions);
  tri.mollify();
  std::vector<double> t, cpu;
  if (what == "lm") {
    tri.flip_to_delaunay();
    for (int r = 0; r <= repeat; ++r) {
      const double t0 = seconds_now(), c0 = process_cpu_seconds();
      const fem::SparseMatrix L = fem::cotan_laplacian(tri);
      const Eigen::VectorXd M = fem::lumped_mass(tri);
      t.push_back(seconds_now() - t0);
      cpu.push_back(process_cpu_seconds() - c0);
    }
  } else if (what == "precompute") {
    for (int r = 0; r <= repeat; ++r) {
      const double t0 = seconds_now(), c0 = process_cpu_seconds();
      const solvers::HeatDistanceSolver solver(tri);  // flips to IDT, assembles, factors
      t.push_back(seconds_now() - t0);
      cpu.push_back(process_cpu_seconds() - c0);
    }
  } else if (what == "precompute-threads") {
#if defined(_OPENMP)
    // the default OpenMP threads and one, taking turns in one process: the host's drift
    // between processes (±20 % over minutes here) cancels
    std::vector<double> with_team, one;
    const int team = omp_get_max_threads();
    for (int r = 0; r <= repeat; ++r) {
      for (const int threads : {team, 1}) {
        omp_set_num_threads(threads);
        const double t0 = seconds_now();
        const solvers::HeatDistanceSolver solver(tri);
        (threads == team && team > 1 ? with_team : one).push_back(seconds_now() - t0);
      }
    }
    omp_set_num_threads(team);
    std::printf("%s precompute, %d OpenMP threads %.5f, one %.5f (medians of %d, in turns)\n",
                spec.c_str(), team, median(with_team), median(one), repeat + 1);
    return 0;
#else
    std::fprintf(stderr, "ifem_bench small: built without OpenMP\n");
    return 2;
#endif
  } else if (what == "factor") {
    const fem::SparseMatrix A = idt_mass_plus_laplacian(m.faces, m.positions);
    for (const bool supernodal : {true, false}) {
      solvers::CholeskyOptions opt;
      opt.supernodal = supernodal;
      const double s = time_median(repeat, [&] { const solvers::CholeskySolver chol(A, opt); });
      std::printf("%s factor %s: %.5f s\n", spec.c_str(), supernodal ? "supernodal" : "simplicial",
                  s);
    }
    return 0;
  } else {
    std::fprintf(stderr, "ifem_bench small: --what lm|precompute|precompute-threads|factor\n");
    return 2;
  }
  // first = the cold call (thread start-up, page faults); median over the later ones
  // cpu: the process's CPU time (all threads, spinning included), median over the later ones
  std::printf("%s %s faces %d first %.5f median %.5f cpu %.5f\n", spec.c_str(), what.c_str(),
              int(m.faces.size()), t[0], median(std::vector<double>(t.begin() + 1, t.end())),
              cpu.size() > 1 ? median(std::vector<double>(cpu.begin() + 1, cpu.end())) : 0.0);
  return 0;
}

}  // namespace ifem::bench
