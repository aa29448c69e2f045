// Exact multigrid hierarchies for tests and measurements: nested flat grids and nested
// icospheres (the vertices of the coarse mesh are vertices of the fine one), with P the
// piecewise-linear interpolation of the coarse triangles at the fine vertices.
#pragma once

#include <Eigen/Core>
#include <Eigen/LU>
#include <Eigen/SparseCore>
#include <array>
#include <cmath>
#include <stdexcept>
#include <unordered_map>
#include <vector>

#include "intrinsic/generators/mesh_generators.h"
#include "solvers/linalg/cholesky.h"

namespace ifem::test {

/// Finds vertices by position (a hash of coordinates rounded to 1e-6, neighbour cells probed).
class PositionIndex {
 public:
  explicit PositionIndex(const Positions& p) {
    for (Eigen::Index v = 0; v < p.rows(); ++v) map_[cell(p.row(v))] = int(v);
  }
  /// Vertex at x (within 1e-6); throws if none.
  int find(const Eigen::RowVector3d& x) const {
    const std::array<long long, 3> c = cell(x);
    for (int dx = -1; dx <= 1; ++dx)
      for (int dy = -1; dy <= 1; ++dy)
        for (int dz = -1; dz <= 1; ++dz) {
          const auto it = map_.find({c[0] + dx, c[1] + dy, c[2] + dz});
          if (it != map_.end()) return it->second;
        }
    throw std::runtime_error("PositionIndex: no vertex at this position");
  }

 private:
  static std::array<long long, 3> cell(const Eigen::RowVector3d& x) {
    return {std::llround(x[0] * 1e6), std::llround(x[1] * 1e6), std::llround(x[2] * 1e6)};
  }
  struct Hash {
    std::size_t operator()(const std::array<long long, 3>& c) const {
      return std::size_t((c[0] * 73856093LL) ^ (c[1] * 19349663LL) ^ (c[2] * 83492791LL));
    }
  };
  std::unordered_map<std::array<long long, 3>, int, Hash> map_;
};

/// P (fine #V × coarse #V) of grid(2n, 2n) from grid(n, n) on the unit square: each fine vertex
/// is located in a coarse triangle (by the coarse cell it lies in) and interpolated.
inline solvers::SparseMatrix grid_prolongation(int n) {
  const intrinsic::TriangleMesh fine = intrinsic::grid(2 * n, 2 * n);
  const intrinsic::TriangleMesh coarse = intrinsic::grid(n, n);
  std::vector<std::vector<int>> faces_of_cell(std::size_t(n) * std::size_t(n));
  for (std::size_t f = 0; f < coarse.faces.size(); ++f) {
    Eigen::RowVector3d c = Eigen::RowVector3d::Zero();
    for (int s = 0; s < 3; ++s) c += coarse.positions.row(coarse.faces[f][std::size_t(s)]) / 3.0;
    const int i = int(c[0] * n), j = int(c[1] * n);
    faces_of_cell[std::size_t(j) * std::size_t(n) + std::size_t(i)].push_back(int(f));
  }
  std::vector<Eigen::Triplet<double>> t;
  for (Eigen::Index v = 0; v < fine.positions.rows(); ++v) {
    const double x = fine.positions(v, 0), y = fine.positions(v, 1);
    const int i = std::min(int(x * n), n - 1), j = std::min(int(y * n), n - 1);
    bool found = false;
    for (const int f : faces_of_cell[std::size_t(j) * std::size_t(n) + std::size_t(i)]) {
      const auto& F = coarse.faces[std::size_t(f)];
      Eigen::Matrix3d M;
      for (int s = 0; s < 3; ++s) {
        M(0, s) = coarse.positions(F[std::size_t(s)], 0);
        M(1, s) = coarse.positions(F[std::size_t(s)], 1);
        M(2, s) = 1.0;
      }
      const Eigen::Vector3d w = M.inverse() * Eigen::Vector3d(x, y, 1.0);
      if (w.minCoeff() < -1e-12) continue;
      for (int s = 0; s < 3; ++s) {
        if (w[s] > 1e-14) t.emplace_back(int(v), F[std::size_t(s)], w[s]);
      }
      found = true;
      break;
    }
    if (!found) throw std::runtime_error("grid_prolongation: vertex in no coarse face");
  }
  solvers::SparseMatrix P(fine.positions.rows(), coarse.positions.rows());
  P.setFromTriplets(t.begin(), t.end());
  return P;
}

/// P (fine #V × coarse #V) of icosphere(2n) from icosphere(n): each fine vertex, projected from
/// the centre onto the flat icosahedron face it lies over, is interpolated in the coarse lattice
/// triangle (lattice of icosphere()'s construction) that holds it.
inline solvers::SparseMatrix icosphere_prolongation(int n) {
  const intrinsic::TriangleMesh fine = intrinsic::icosphere(2 * n);
  const intrinsic::TriangleMesh coarse = intrinsic::icosphere(n);
  const intrinsic::TriangleMesh ico = intrinsic::icosphere(1);  // the 12 corners, 20 faces
  const PositionIndex coarse_index(coarse.positions);
  std::vector<Eigen::Matrix3d> inverse(ico.faces.size());
  for (std::size_t f = 0; f < ico.faces.size(); ++f) {
    Eigen::Matrix3d C;
    for (int s = 0; s < 3; ++s)
      C.col(s) = ico.positions.row(ico.faces[f][std::size_t(s)]).transpose();
    inverse[f] = C.inverse();
  }
  auto lattice_vertex = [&](std::size_t f, int a, int b) {
    const auto& F = ico.faces[f];
    const Eigen::RowVector3d c0 = ico.positions.row(F[0]), c1 = ico.positions.row(F[1]),
                             c2 = ico.positions.row(F[2]);
    return coarse_index.find(
        (c0 + (c1 - c0) * (double(a) / n) + (c2 - c0) * (double(b) / n)).normalized());
  };
  std::vector<Eigen::Triplet<double>> t;
  for (Eigen::Index v = 0; v < fine.positions.rows(); ++v) {
    const Eigen::Vector3d d = fine.positions.row(v).transpose();
    std::size_t f = 0;
    Eigen::Vector3d w = Eigen::Vector3d::Zero();  // set by the search below (gcc cannot see it)
    for (; f < ico.faces.size(); ++f) {
      w = inverse[f] * d;
      if (w.minCoeff() >= -1e-9 && w.sum() > 0) break;
    }
    if (f == ico.faces.size()) throw std::runtime_error("icosphere_prolongation: no face");
    w /= w.sum();
    const double x = w[1] * n, y = w[2] * n;
    const int i = std::clamp(int(std::floor(x + 1e-9)), 0, n - 1);
    const int j = std::clamp(int(std::floor(y + 1e-9)), 0, n - 1);
    const double fx = x - i, fy = y - j;
    std::array<std::array<int, 2>, 3> corner;
    std::array<double, 3> weight;
    if (fx + fy <= 1.0 + 1e-9) {
      corner = {{{i, j}, {i + 1, j}, {i, j + 1}}};
      weight = {1.0 - fx - fy, fx, fy};
    } else {
      corner = {{{i + 1, j + 1}, {i + 1, j}, {i, j + 1}}};
      weight = {fx + fy - 1.0, 1.0 - fy, 1.0 - fx};
    }
    for (int s = 0; s < 3; ++s) {
      if (weight[std::size_t(s)] > 1e-9) {
        t.emplace_back(int(v),
                       lattice_vertex(f, corner[std::size_t(s)][0], corner[std::size_t(s)][1]),
                       weight[std::size_t(s)]);
      }
    }
  }
  solvers::SparseMatrix P(fine.positions.rows(), coarse.positions.rows());
  P.setFromTriplets(t.begin(), t.end());
  // rows sum to 1 (weights below 1e-9 dropped): renormalize
  Eigen::VectorXd sums = P * Eigen::VectorXd::Ones(P.cols());
  for (int k = 0; k < P.outerSize(); ++k)
    for (solvers::SparseMatrix::InnerIterator it(P, k); it; ++it) it.valueRef() /= sums[it.row()];
  return P;
}

/// The chain P₀ … P_{levels−2} of icosphere(n) ← icosphere(n/2) ← … (n divisible by
/// 2^(levels−1)).
inline std::vector<solvers::SparseMatrix> icosphere_hierarchy(int n, int levels) {
  std::vector<solvers::SparseMatrix> chain;
  for (int l = 0; l + 1 < levels; ++l) {
    if (n % 2 != 0) throw std::runtime_error("icosphere_hierarchy: n not divisible");
    chain.push_back(icosphere_prolongation(n / 2));
    n /= 2;
  }
  return chain;
}

/// The chain of grid(n) ← grid(n/2) ← …
inline std::vector<solvers::SparseMatrix> grid_hierarchy(int n, int levels) {
  std::vector<solvers::SparseMatrix> chain;
  for (int l = 0; l + 1 < levels; ++l) {
    if (n % 2 != 0) throw std::runtime_error("grid_hierarchy: n not divisible");
    chain.push_back(grid_prolongation(n / 2));
    n /= 2;
  }
  return chain;
}

/// P restricted to the rows `keep` (e.g. the free vertices of a Dirichlet problem).
inline solvers::SparseMatrix keep_rows(const solvers::SparseMatrix& P,
                                       const std::vector<int>& keep) {
  std::vector<Eigen::Triplet<double>> t;
  std::vector<int> new_row(std::size_t(P.rows()), -1);
  for (std::size_t i = 0; i < keep.size(); ++i) new_row[std::size_t(keep[i])] = int(i);
  for (int k = 0; k < P.outerSize(); ++k)
    for (solvers::SparseMatrix::InnerIterator it(P, k); it; ++it)
      if (new_row[std::size_t(it.row())] >= 0)
        t.emplace_back(new_row[std::size_t(it.row())], k, it.value());
  solvers::SparseMatrix out(Eigen::Index(keep.size()), P.cols());
  out.setFromTriplets(t.begin(), t.end());
  return out;
}

}  // namespace ifem::test
