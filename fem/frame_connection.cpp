#include "fem/frame_connection.h"

#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <string>
#include <vector>

#include "intrinsic/core/errors.h"

namespace ifem::fem {

namespace {

// Below this 1 + n_i·n_j the normals count as opposite (no minimal rotation).
constexpr double kOpposite = 1e-12;

void check_frames(const SparseMatrix& L, const Eigen::MatrixX3d& normal, const Eigen::MatrixX3d& e1,
                  const Eigen::MatrixX3d& e2, int symmetry) {
  const std::string f = "connection_laplacian_from_frames: ";
  if (symmetry < 1) throw InvalidInput(f + "symmetry must be ≥ 1, got " + std::to_string(symmetry));
  if (L.rows() != L.cols()) throw InvalidInput(f + "L is not square");
  for (const Eigen::MatrixX3d* m : {&normal, &e1, &e2}) {
    if (m->rows() != L.rows()) {
      throw InvalidInput(f + "a frame matrix has " + std::to_string(m->rows()) + " rows for " +
                         std::to_string(L.rows()) + " vertices");
    }
    if (!m->allFinite()) throw InvalidInput(f + "a frame vector is not finite");
  }
}

}  // namespace

std::complex<double> frame_transport(const Eigen::Vector3d& n_i, const Eigen::Vector3d& e1_i,
                                     const Eigen::Vector3d& n_j, const Eigen::Vector3d& e1_j,
                                     const Eigen::Vector3d& e2_j) {
  const double c = n_i.dot(n_j);
  Eigen::Vector3d moved;
  if (c > -1.0 + kOpposite) {
    // Rodrigues with axis v = n_i × n_j (|v| = sin, c = cos): R x = c x + v × x + v (v·x)/(1+c)
    const Eigen::Vector3d v = n_i.cross(n_j);
    moved = c * e1_i + v.cross(e1_i) + v * (v.dot(e1_i) / (1.0 + c));
  } else {
    moved = e1_i;  // the half turn about e1_i keeps e1_i
  }
  const std::complex<double> r(moved.dot(e1_j), moved.dot(e2_j));
  const double len = std::abs(r);
  return len > 0.0 ? r / len : std::complex<double>(1.0, 0.0);
}

ComplexSparseMatrix connection_laplacian_from_frames(const SparseMatrix& L,
                                                     const Eigen::MatrixX3d& normal,
                                                     const Eigen::MatrixX3d& e1,
                                                     const Eigen::MatrixX3d& e2, int symmetry) {
  check_frames(L, normal, e1, e2, symmetry);
  const Index n = static_cast<Index>(L.rows());
  std::vector<Eigen::Triplet<std::complex<double>>> entries;
  entries.reserve(static_cast<std::size_t>(L.nonZeros()) + static_cast<std::size_t>(n));
  std::vector<double> diagonal(static_cast<std::size_t>(n), 0.0);
  for (Index j = 0; j < n; ++j) {  // column j: the entries (i, j), i.e. transport j → i
    for (SparseMatrix::InnerIterator it(L, j); it; ++it) {
      const Index i = static_cast<Index>(it.row());
      if (i == j) continue;
      const double w = -it.value();
      if (!std::isfinite(w)) {
        throw InvalidInput("connection_laplacian_from_frames: L(" + std::to_string(i) + "," +
                           std::to_string(j) + ") is not finite");
      }
      // r_{j→i}, computed from the lower id to the higher one so that (i, j) and (j, i) are
      // exact conjugates
      const Index a = std::min(i, j), b = std::max(i, j);
      const std::complex<double> q =
          frame_transport(normal.row(a).transpose(), e1.row(a).transpose(),
                          normal.row(b).transpose(), e1.row(b).transpose(), e2.row(b).transpose());
      const std::complex<double> r = j < i ? q : std::conj(q);
      entries.emplace_back(i, j, -w * std::polar(1.0, symmetry * std::arg(r)));
      diagonal[i] += w;
    }
  }
  for (Index v = 0; v < n; ++v) entries.emplace_back(v, v, diagonal[v]);
  ComplexSparseMatrix out(n, n);
  out.setFromTriplets(entries.begin(), entries.end());
  out.makeCompressed();
  return out;
}

}  // namespace ifem::fem
