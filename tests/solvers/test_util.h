// Helpers for the solvers tests.
#pragma once

#include "intrinsic/mesh_generators.h"
#include "intrinsic/triangulation.h"
#include "helpers.h"

namespace ifem::test {

inline intrinsic::IntrinsicTriangulation make_tri(const intrinsic::TriangleMesh& m,
                                                  bool delaunay = true) {
  auto tri = intrinsic::IntrinsicTriangulation::from_positions(m.faces, m.positions);
  if (delaunay) tri.flip_to_delaunay();
  return tri;
}

/// Two copies of a mesh side by side (the second shifted by `dx` in x), plus `extra` isolated
/// (unreferenced) vertices at the end.
inline intrinsic::TriangleMesh two_copies(const intrinsic::TriangleMesh& m, double dx, int extra) {
  intrinsic::TriangleMesh out;
  const Eigen::Index n = m.positions.rows();
  out.positions.resize(2 * n + extra, 3);
  out.positions.topRows(n) = m.positions;
  out.positions.middleRows(n, n) = m.positions;
  out.positions.middleRows(n, n).col(0).array() += dx;
  for (int i = 0; i < extra; ++i) out.positions.row(2 * n + i) << -5.0 - i, 0.0, 0.0;
  out.faces = m.faces;
  for (const auto& f : m.faces) {
    out.faces.push_back({f[0] + Index(n), f[1] + Index(n), f[2] + Index(n)});
  }
  return out;
}

}  // namespace ifem::test
