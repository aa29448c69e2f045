#include "fem/operators.h"

#include <algorithm>
#include <vector>

#include "intrinsic/core/geometry.h"

namespace ifem::fem {

using intrinsic::IntrinsicTriangulation;

SparseMatrix cotan_laplacian(const IntrinsicTriangulation& tri) {
  return laplacian_from_weights(tri, intrinsic::cotan_weights(tri));
}

SparseMatrix laplacian_from_weights(const IntrinsicTriangulation& tri, const Eigen::VectorXd& w) {
  // Direct CSC assembly (no triplets): count entries per column, scatter each edge's two
  // off-diagonal entries straight into the matrix arrays, then sort each (small) column by row
  // in parallel, merging parallel edges (multi-edges of a Δ-complex); the diagonal goes last.
  const Index nv = tri.n_vertices();
  const Index ne = tri.n_edges();
  const double scale = 1.0 / tri.multiplicity();
  const auto& tails = tri.tails();
  SparseMatrix L(nv, nv);
  int* outer = L.outerIndexPtr();
  std::fill(outer, outer + nv + 1, 0);
  for (Index e = 0; e < ne; ++e) {
    const Index h = tri.edge_halfedge(e);
    const Index i = tails[h], j = tails[IntrinsicTriangulation::next(h)];
    if (i == j) continue;  // a self-edge adds w and subtracts it again: nothing
    ++outer[i + 1];
    ++outer[j + 1];
  }
  for (Index v = 0; v < nv; ++v) outer[v + 1] += outer[v] + 1;  // +1: the diagonal
  L.resizeNonZeros(outer[nv]);
  int* inner = L.innerIndexPtr();
  double* value = L.valuePtr();
  std::vector<int> fill(outer, outer + nv);
  Eigen::VectorXd diag = Eigen::VectorXd::Zero(nv);
  for (Index e = 0; e < ne; ++e) {
    const Index h = tri.edge_halfedge(e);
    const Index i = tails[h], j = tails[IntrinsicTriangulation::next(h)];
    if (i == j) continue;
    const double we = scale * w[e];
    inner[fill[j]] = i;
    value[fill[j]++] = -we;
    inner[fill[i]] = j;
    value[fill[i]++] = -we;
    diag[i] += we;
    diag[j] += we;
  }
  std::vector<int> count(nv);
#pragma omp parallel for schedule(static) if (nv > kParallelMin)
  for (Index v = 0; v < nv; ++v) {
    int* r = inner + outer[v];
    double* x = value + outer[v];
    int n = fill[v] - outer[v];
    r[n] = v;  // the diagonal
    x[n++] = diag[v];
    for (int a = 1; a < n; ++a) {  // insertion sort by row: columns hold ~7 entries
      const int ra = r[a];
      const double xa = x[a];
      int b = a;
      for (; b > 0 && r[b - 1] > ra; --b) {
        r[b] = r[b - 1];
        x[b] = x[b - 1];
      }
      r[b] = ra;
      x[b] = xa;
    }
    int m = 0;
    for (int a = 0; a < n; ++a) {
      if (m > 0 && r[m - 1] == r[a]) {
        x[m - 1] += x[a];
      } else {
        r[m] = r[a];
        x[m++] = x[a];
      }
    }
    count[v] = m;
  }
  // squeeze out what merged multi-edges freed (nothing moves on an ordinary mesh)
  int out = 0;
  for (Index v = 0; v < nv; ++v) {
    const int begin = outer[v];
    if (out != begin) {
      std::copy(inner + begin, inner + begin + count[v], inner + out);
      std::copy(value + begin, value + begin + count[v], value + out);
    }
    outer[v] = out;
    out += count[v];
  }
  outer[nv] = out;
  L.data().resize(out);
  return L;
}

Eigen::VectorXd face_areas(const IntrinsicTriangulation& tri) {
  const Index nf = tri.n_faces();
  Eigen::VectorXd a(nf);
#pragma omp parallel for schedule(static) if (nf > kParallelMin)
  for (Index f = 0; f < nf; ++f) a[f] = intrinsic::face_area(tri, f);
  return a;
}

Eigen::VectorXd lumped_mass(const IntrinsicTriangulation& tri) {
  const Eigen::VectorXd area = face_areas(tri);
  Eigen::VectorXd m = Eigen::VectorXd::Zero(tri.n_vertices());
  const double third = 1.0 / (3.0 * tri.multiplicity());
  const auto& tail = tri.tails();
  for (Index f = 0; f < tri.n_faces(); ++f) {
    const double a = area[f] * third;
    m[tail[3 * f]] += a;
    m[tail[3 * f + 1]] += a;
    m[tail[3 * f + 2]] += a;
  }
  return m;
}

SparseMatrix galerkin_mass(const IntrinsicTriangulation& tri) {
  const Eigen::VectorXd area = face_areas(tri);
  std::vector<Eigen::Triplet<double>> trip;
  trip.reserve(9 * static_cast<std::size_t>(tri.n_faces()));
  const double s = 1.0 / tri.multiplicity();
  for (Index f = 0; f < tri.n_faces(); ++f) {
    for (int i = 0; i < 3; ++i) {
      for (int j = 0; j < 3; ++j) {
        trip.emplace_back(tri.tail(3 * f + i), tri.tail(3 * f + j),
                          s * area[f] / (i == j ? 6.0 : 12.0));
      }
    }
  }
  SparseMatrix M(tri.n_vertices(), tri.n_vertices());
  M.setFromTriplets(trip.begin(), trip.end());
  M.makeCompressed();
  return M;
}

}  // namespace ifem::fem
