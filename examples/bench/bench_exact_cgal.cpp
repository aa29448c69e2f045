// Exact geodesic distance, ifem against CGAL's Surface_mesh_shortest_path (Xin–Wang's
// sequence tree, exact predicates with double constructions), from one source vertex, the two
// interleaved in one run (BENCHMARKS.md, "Exact geodesic distance"). Built only with
// -DIFEM_BUILD_CGAL_BENCH=ON (needs Debian's libcgal-dev; not part of setup.sh).
//   ifem_bench_exact_cgal MESH|ico:N SOURCE [REPEATS]
// prints per repeat the two times, then the medians, their ratio (ifem / CGAL) and the largest
// relative difference between the two distance vectors.
#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>
#include <CGAL/Surface_mesh.h>
#include <CGAL/Surface_mesh_shortest_path.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <string>
#include <vector>

#include "intrinsic/generators/mesh_generators.h"
#include "intrinsic/geodesic/exact_distance.h"
#include "intrinsic/io/mesh_io.h"

namespace {

using Kernel = CGAL::Exact_predicates_inexact_constructions_kernel;
using Mesh = CGAL::Surface_mesh<Kernel::Point_3>;
using Traits = CGAL::Surface_mesh_shortest_path_traits<Kernel, Mesh>;
using ShortestPath = CGAL::Surface_mesh_shortest_path<Traits>;
using Clock = std::chrono::steady_clock;

double seconds_since(Clock::time_point t) {
  return std::chrono::duration<double>(Clock::now() - t).count();
}

double median(std::vector<double> v) {
  std::sort(v.begin(), v.end());
  return v[v.size() / 2];
}

}  // namespace

int main(int argc, char** argv) {
  using namespace ifem;
  if (argc < 3) {
    std::fprintf(stderr, "usage: %s MESH|ico:N SOURCE [REPEATS]\n", argv[0]);
    return 2;
  }
  const std::string what = argv[1];
  const Index src = Index(std::stol(argv[2]));
  const int repeats = argc > 3 ? std::stoi(argv[3]) : 3;
  Positions x;
  std::vector<Triangle> faces;
  if (what.rfind("ico:", 0) == 0) {
    intrinsic::TriangleMesh m = intrinsic::icosphere(std::stoi(what.substr(4)));
    x = m.positions;
    faces = m.faces;
  } else {
    io::SurfaceInput in = io::read_mesh(what);
    x = in.positions;
    faces = in.triangles;
  }
  Mesh mesh;
  std::vector<Mesh::Vertex_index> vid;
  for (Eigen::Index v = 0; v < x.rows(); ++v) {
    vid.push_back(mesh.add_vertex(Kernel::Point_3(x(v, 0), x(v, 1), x(v, 2))));
  }
  for (const Triangle& t : faces) {
    if (mesh.add_face(vid[t[0]], vid[t[1]], vid[t[2]]) == Mesh::null_face()) {
      std::fprintf(stderr, "CGAL refused a face (nonmanifold input)\n");
      return 1;
    }
  }
  const auto tri = intrinsic::IntrinsicTriangulation::from_positions(faces, x);
  std::printf("%s: %d vertices, %d faces, source %d\n", what.c_str(), int(x.rows()),
              int(faces.size()), int(src));
  std::vector<double> t_ifem, t_cgal;
  Eigen::VectorXd d_ifem, d_cgal(x.rows());
  std::size_t windows = 0;
  for (int r = 0; r < repeats; ++r) {
    auto t0 = Clock::now();
    intrinsic::ExactDistance d = intrinsic::exact_distance(tri, std::vector<Index>{src});
    t_ifem.push_back(seconds_since(t0));
    d_ifem = d.distance;
    windows = d.windows;
    t0 = Clock::now();
    {
      ShortestPath sp(mesh);
      sp.add_source_point(vid[src]);
      sp.build_sequence_tree();
      for (Eigen::Index v = 0; v < x.rows(); ++v)
        d_cgal[v] = sp.shortest_distance_to_source_points(vid[v]).first;
    }
    t_cgal.push_back(seconds_since(t0));
    std::printf("repeat %d: ifem %.3f s (%zu windows), CGAL %.3f s\n", r, t_ifem.back(), windows,
                t_cgal.back());
    std::fflush(stdout);
  }
  double worst = 0.0;
  for (Eigen::Index v = 0; v < x.rows(); ++v) {
    if (d_cgal[v] > 0 && std::isfinite(d_cgal[v])) {
      worst = std::max(worst, std::abs(d_ifem[v] - d_cgal[v]) / d_cgal[v]);
    }
  }
  const double mi = median(t_ifem), mc = median(t_cgal);
  std::printf("median: ifem %.3f s, CGAL %.3f s, ratio ifem/CGAL %.3f; max rel diff %.2e\n", mi, mc,
              mi / mc, worst);
  return 0;
}
