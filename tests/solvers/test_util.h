// Helpers for the solvers tests.
#pragma once

#include <Eigen/Core>
#include <algorithm>
#include <cmath>

#include "helpers.h"
#include "intrinsic/core/triangulation.h"
#include "intrinsic/generators/mesh_generators.h"
#include "intrinsic/io/mesh_io.h"

namespace ifem::test {

/// Mean and max of |d − exact| / exact over the vertices with a finite, positive exact distance
/// (a non-finite d counts as 1e9), for comparisons against ../shared/data/reference.
struct Rel {
  double mean = 0, max = 0;
};

inline Rel relative_error(const Eigen::VectorXd& d, const Eigen::VectorXd& exact) {
  Rel r;
  double sum = 0;
  int n = 0;
  for (Eigen::Index v = 0; v < exact.size(); ++v) {
    if (!std::isfinite(exact[v]) || exact[v] <= 0) continue;
    const double e = std::abs(d[v] - exact[v]) / exact[v];
    sum += std::isfinite(e) ? e : 1e9;
    r.max = std::max(r.max, e);
    ++n;
  }
  r.mean = sum / std::max(n, 1);
  return r;
}

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

/// The mesh as an input read from a file (positions and triangles).
inline io::SurfaceInput as_input(const intrinsic::TriangleMesh& m) {
  io::SurfaceInput in;
  in.positions = m.positions;
  in.triangles = m.faces;
  in.n_polygons = static_cast<Index>(m.faces.size());
  return in;
}

/// A Möbius strip: n quads around a half-twisted band, each split in two (non-orientable).
inline intrinsic::TriangleMesh moebius(int n) {
  intrinsic::TriangleMesh m;
  m.positions.resize(2 * n, 3);
  for (int i = 0; i < n; ++i) {
    const double t = 2.0 * intrinsic::kPi * i / n;
    for (int s = 0; s < 2; ++s) {
      const double w = s == 0 ? -0.3 : 0.3;
      m.positions.row(2 * i + s) << (1 + w * std::cos(t / 2)) * std::cos(t),
          (1 + w * std::cos(t / 2)) * std::sin(t), w * std::sin(t / 2);
    }
  }
  for (int i = 0; i < n; ++i) {
    const Index a = 2 * i, b = 2 * i + 1;
    // the last quad closes with the two rows swapped: the half twist
    const Index c = i + 1 < n ? 2 * (i + 1) : 1, d = i + 1 < n ? 2 * (i + 1) + 1 : 0;
    m.faces.push_back({a, c, b});
    m.faces.push_back({b, c, d});
  }
  return m;
}

}  // namespace ifem::test
