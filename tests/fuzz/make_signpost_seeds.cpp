// Writes the signpost seeds (tests/fuzz/seeds/signpost/) with SignpostTriangulation::save, so
// that they follow the format exactly: a tetrahedron, the same with an inserted vertex and a
// split edge, and a mollified open square. Built on request only:
//   cmake --build build-fuzz --target make_signpost_seeds
//   build-fuzz/tests/fuzz/make_signpost_seeds tests/fuzz/seeds/signpost
#include <Eigen/Core>
#include <cstdio>
#include <string>
#include <vector>

#include "intrinsic/refine/signpost.h"

int main(int argc, char** argv) {
  using ifem::Positions;
  using ifem::Triangle;
  using ifem::intrinsic::SignpostTriangulation;
  if (argc != 2) {
    std::fprintf(stderr, "usage: make_signpost_seeds DIR\n");
    return 2;
  }
  const std::string dir = argv[1];
  Positions tet(4, 3);
  tet << 0, 0, 0, 1, 0, 0, 0, 1, 0, 0, 0, 1;
  const std::vector<Triangle> tet_faces = {{0, 2, 1}, {0, 1, 3}, {0, 3, 2}, {1, 2, 3}};
  SignpostTriangulation(tet_faces, tet).save(dir + "/tet.signpost");

  SignpostTriangulation inserted(tet_faces, tet);
  inserted.insert_vertex(0, Eigen::Vector3d(0.2, 0.3, 0.5));
  inserted.split_edge(1, 0.4);
  inserted.flip_to_delaunay();
  inserted.save(dir + "/tet_inserted.signpost");

  Positions square(4, 3);
  square << 0, 0, 0, 1, 0, 0, 1, 1, 0, 0, 1, 0;
  const std::vector<Triangle> square_faces = {{0, 1, 2}, {0, 2, 3}};
  SignpostTriangulation(square_faces, square, 1e-6).save(dir + "/square_mollified.signpost");
  return 0;
}
