// The README's library example, compiled and run by ctest so it cannot rot: load a mesh through
// the library's pipeline (path choice, intrinsic Delaunay, optional refinement), assemble L and
// M, and compute heat-method geodesic distance from vertex 0 on the input's vertices. It runs
// the same code as `ifem distance` (ctest checks the two agree bit for bit).
//
//   example_heat_distance MESH [--refine] [OUT.txt]
#include <cstdio>
#include <string>

#include "fem/operators.h"
#include "intrinsic/io/mesh_io.h"
#include "solvers/recipes/pipeline.h"

int main(int argc, char** argv) {
  std::string mesh, out;
  bool refine = false;
  for (int i = 1; i < argc; ++i) {
    const std::string a = argv[i];
    if (a == "--refine") {
      refine = true;
    } else if (mesh.empty()) {
      mesh = a;
    } else {
      out = a;
    }
  }
  if (mesh.empty()) {
    std::fprintf(stderr, "usage: example_heat_distance MESH [--refine] [OUT.txt]\n");
    return 2;
  }
  try {
    ifem::solvers::PrepareOptions opt;  // manifold / tufted / point cloud chosen for the input
    if (refine) opt.refine = ifem::solvers::accurate_distance_refinement();
    const auto s = ifem::solvers::load_surface(mesh, opt);
    const auto L = ifem::fem::cotan_laplacian(s.tri);                    // #V×#V, PSD
    const auto M = ifem::fem::lumped_mass(s.tri);                        // #V
    const Eigen::VectorXd d = ifem::solvers::geodesic_distance(s, {0});  // #V_in, input order
    if (!out.empty()) ifem::io::write_values(out, d);
    std::printf("%s path, %zu flips, L %ldx%ld, area %.6g, max distance from vertex 0: %.6g\n",
                ifem::intrinsic::to_string(s.path), s.flips.flips, long(L.rows()), long(L.cols()),
                M.sum(), d.maxCoeff());
    return d.allFinite() && d[0] == 0.0 ? 0 : 1;
  } catch (const ifem::Error& e) {
    std::fprintf(stderr, "example_heat_distance: %s\n", e.what());
    return 1;
  }
}
