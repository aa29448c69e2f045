// Benchmark section "trace": straight geodesics (solvers/recipes/trace_geodesic.h, what
// `ifem trace` runs) on a unit icosphere of about 100k faces and, when ../shared is present, on
// the armadillo (86k faces): --rays rays (default 1000) from random face points (seeded) in
// random tangent directions, each as long as the mesh's diameter (the icosphere's: π, half a
// great circle; a mesh file's: its bounding-box diagonal). Reported: the tracer's build (once
// per mesh), the median over --repeat runs of the time per ray, the sides crossed per ray and
// the time per crossing. Times are the thread's CPU seconds (a loaded machine does not count
// other processes' time).
//
//   ifem_bench trace [--repeat 3] [--rays 1000] [--mesh FILE|icosphere:N]
#include <cmath>
#include <cstdio>
#include <ctime>
#include <random>
#include <string>
#include <vector>

#include "bench_util.h"
#include "intrinsic/core/errors.h"
#include "intrinsic/generators/mesh_generators.h"
#include "intrinsic/io/mesh_io.h"
#include "solvers/recipes/trace_geodesic.h"

namespace ifem::bench {
namespace {

double cpu_now() {
  timespec t{};
  clock_gettime(CLOCK_THREAD_CPUTIME_ID, &t);
  return static_cast<double>(t.tv_sec) + 1e-9 * static_cast<double>(t.tv_nsec);
}

void trace_row(const std::string& name, const io::SurfaceInput& in, double length, int rays,
               int repeat) {
  double t0 = cpu_now();
  const recipes::GeodesicTracer tracer(in);
  const double build = cpu_now() - t0;
  std::mt19937 rng(42);
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  std::normal_distribution<double> gauss;
  std::vector<recipes::GivenPoint> starts(rays);
  std::vector<Eigen::Vector3d> dirs(rays);
  const Index nf = static_cast<Index>(in.triangles.size());
  for (int i = 0; i < rays; ++i) {
    double u = unit(rng), v = unit(rng);
    if (u + v > 1.0) u = 1.0 - u, v = 1.0 - v;
    starts[i].face = static_cast<Index>(unit(rng) * nf) % nf;
    starts[i].bary = {1.0 - u - v, u, v};
    starts[i].token = "bench";
    dirs[i] = Eigen::Vector3d(gauss(rng), gauss(rng), gauss(rng));
  }
  std::vector<double> per_ray;
  double points = 0.0, traced = 0.0;
  int failed = 0, stopped = 0;
  for (int k = 0; k < repeat; ++k) {
    points = traced = 0.0;
    failed = stopped = 0;
    t0 = cpu_now();
    for (int i = 0; i < rays; ++i) {
      try {
        const recipes::GeodesicRay r = tracer.trace(starts[i], dirs[i], length);
        points += static_cast<double>(r.polyline.size());
        traced += r.length;
        stopped += r.hit_boundary;
      } catch (const Error&) {
        ++failed;  // a random direction along a face normal (never seen)
      }
    }
    per_ray.push_back((cpu_now() - t0) / rays);
  }
  const double t = median(per_ray);
  const double crossings = points / rays - 2.0;
  std::printf(
      "%-22s %8d faces  build %7.3f s  ray length %6.3f  %5d rays: %8.1f µs/ray, %7.0f "
      "crossings/ray, %6.3f µs/crossing, mean traced %.4g, %d stopped at the boundary, %d "
      "refused\n",
      name.c_str(), static_cast<int>(nf), build, length, rays, 1e6 * t, crossings,
      1e6 * t / std::max(crossings, 1.0), traced / rays, stopped, failed);
}

io::SurfaceInput icosphere_input(int n) {
  const intrinsic::TriangleMesh m = intrinsic::icosphere(n);
  io::SurfaceInput in;
  in.positions = m.positions;
  in.triangles = m.faces;
  return in;
}

double diagonal(const io::SurfaceInput& in) {
  return (in.positions.colwise().maxCoeff() - in.positions.colwise().minCoeff()).norm();
}

}  // namespace

int trace(int argc, char** argv) {
  int repeat = 3, rays = 1000;
  std::string mesh;
  for (int i = 1; i + 1 < argc; i += 2) {
    const std::string a = argv[i];
    if (a == "--repeat") repeat = std::max(1, std::atoi(argv[i + 1]));
    if (a == "--rays") rays = std::max(1, std::atoi(argv[i + 1]));
    if (a == "--mesh") mesh = argv[i + 1];
  }
  print_load_average();
  if (!mesh.empty()) {
    if (mesh.rfind("icosphere:", 0) == 0) {
      trace_row(mesh, icosphere_input(std::atoi(mesh.c_str() + 10)), M_PI, rays, repeat);
    } else {
      const io::SurfaceInput in = io::read_surface(mesh);
      trace_row(mesh, in, diagonal(in), rays, repeat);
    }
    return 0;
  }
  trace_row("icosphere 71", icosphere_input(71), M_PI, rays, repeat);
  const std::string armadillo = std::string(IFEM_SHARED_MESHES) + "/armadillo.obj";
  if (std::ifstream(armadillo).good()) {
    const io::SurfaceInput in = io::read_surface(armadillo);
    trace_row("armadillo", in, diagonal(in), rays, repeat);
  } else {
    std::printf("armadillo: %s absent (../shared), skipped\n", armadillo.c_str());
  }
  return 0;
}

}  // namespace ifem::bench
