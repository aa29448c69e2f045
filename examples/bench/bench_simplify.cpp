// Benchmark section "simplify": intrinsic simplification (intrinsic/simplify/simplify.h) of
// icospheres down to --vertices (default 10,000), median over --repeat runs: time (wall, and the
// process's CPU time: on a shared machine the wall time counts the neighbours), vertices removed
// per second, flips per removal, and the prolongation's assembly. Times exclude building the
// triangulation (each run starts from a copy).
//
//   ifem_bench simplify [--repeat 3] [--max-n 224] [--vertices 10000]
#include <cstdio>
#include <ctime>
#include <vector>

#include "bench_util.h"
#include "fem/prolongation.h"
#include "intrinsic/generators/mesh_generators.h"
#include "intrinsic/simplify/simplify.h"

namespace ifem::bench {

int simplify(int argc, char** argv) {
  const int repeat = int(int_option(argc, argv, "--repeat", 3));
  const int max_n = int(int_option(argc, argv, "--max-n", 224));
  const Index target = Index(int_option(argc, argv, "--vertices", 10000));
  print_load_average();
  std::printf("%10s %10s %10s %10s %10s %14s %12s %10s\n", "faces", "vertices", "target", "time s",
              "cpu s", "removed/s", "flips/rem", "P s");
  for (int n : {23, 71, 224, 316}) {
    if (n > max_n) break;
    const intrinsic::TriangleMesh m = intrinsic::icosphere(n);
    const auto fine = intrinsic::IntrinsicTriangulation::from_positions(m.faces, m.positions);
    intrinsic::SimplifyOptions o;
    o.target_vertices = std::min<Index>(target, fine.n_vertices() / 10);
    intrinsic::Simplification s;
    std::vector<double> cpu;
    const double t = time_median(repeat, [&] {
      const std::clock_t c0 = std::clock();
      s = intrinsic::simplify(fine, o);
      cpu.push_back(double(std::clock() - c0) / CLOCKS_PER_SEC);
    });
    const double tp = time_median(repeat, [&] { (void)fem::prolongation(s); });
    std::printf("%10d %10d %10d %10.3f %10.3f %14.0f %12.2f %10.4f\n", int(fine.n_faces()),
                int(fine.n_vertices()), int(o.target_vertices), t, median(cpu),
                s.report.removals / median(cpu),
                double(s.report.flips) / std::max<Index>(s.report.removals, 1), tp);
  }
  return 0;
}

}  // namespace ifem::bench
