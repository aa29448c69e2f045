// The README's library example, compiled and run by ctest so it cannot rot: load a mesh, build
// its intrinsic Delaunay triangulation (manifold or tufted cover), assemble L and M, and compute
// heat-method geodesic distance from vertex 0.
//
//   example_heat_distance MESH
#include <cstdio>

#include "fem/operators.h"
#include "intrinsic/io/mesh_io.h"
#include "intrinsic/surface/build_surface.h"
#include "solvers/heat_distance.h"

int main(int argc, char** argv) {
  if (argc != 2) {
    std::fprintf(stderr, "usage: example_heat_distance MESH\n");
    return 2;
  }
  try {
    const auto in = ifem::io::read_mesh(argv[1]);
    auto s = ifem::intrinsic::build_surface(in.triangles, in.positions);  // manifold or tufted
    const auto L = ifem::fem::cotan_laplacian(s.tri);                     // #V×#V, PSD
    const auto M = ifem::fem::lumped_mass(s.tri);                         // #V
    ifem::solvers::HeatDistanceSolver heat(s.tri);                        // factor once
    const Eigen::VectorXd d = heat.compute_distance({0});                 // solve many
    std::printf("%s path, %zu flips, L %ldx%ld, area %.6g, max distance from vertex 0: %.6g\n",
                s.path_name(), s.flips.flips, long(L.rows()), long(L.cols()), M.sum(),
                d.maxCoeff());
    return d.allFinite() && d[0] == 0.0 ? 0 : 1;
  } catch (const ifem::Error& e) {
    std::fprintf(stderr, "example_heat_distance: %s\n", e.what());
    return 1;
  }
}
