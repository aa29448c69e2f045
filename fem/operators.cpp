#include "fem/operators.h"

#include <vector>

#include "intrinsic/geometry.h"

namespace ifem::fem {

using intrinsic::IntrinsicTriangulation;

SparseMatrix cotan_laplacian(const IntrinsicTriangulation& tri) {
  return laplacian_from_weights(tri, intrinsic::cotan_weights(tri));
}

SparseMatrix laplacian_from_weights(const IntrinsicTriangulation& tri,
                                    const Eigen::VectorXd& w) {
  // Two counting-sort passes instead of triplets + sort: (1) vertex → incident edges,
  // (2) walk rows in increasing order and append to the transposed position, which leaves
  // every column sorted by row; parallel edges (multi-edges) merge on the fly.
  const Index nv = tri.n_vertices();
  const Index ne = tri.n_edges();
  const double scale = 1.0 / tri.multiplicity();
  std::vector<Index> adj_start(static_cast<std::size_t>(nv) + 1, 0);
  for (Index e = 0; e < ne; ++e) {
    const Index h = tri.edge_halfedge(e);
    const Index i = tri.tail(h), j = tri.head(h);
    if (i == j) continue;
    ++adj_start[i + 1];
    ++adj_start[j + 1];
  }
  for (Index v = 0; v < nv; ++v) adj_start[v + 1] += adj_start[v];
  std::vector<Index> adj_vertex(adj_start[nv]);
  std::vector<double> adj_weight(adj_start[nv]);
  {
    std::vector<Index> fill(adj_start.begin(), adj_start.end() - 1);
    for (Index e = 0; e < ne; ++e) {
      const Index h = tri.edge_halfedge(e);
      const Index i = tri.tail(h), j = tri.head(h);
      if (i == j) continue;
      const double we = scale * w[e];
      adj_vertex[fill[i]] = j;
      adj_weight[fill[i]++] = we;
      adj_vertex[fill[j]] = i;
      adj_weight[fill[j]++] = we;
    }
  }
  // column j holds its diagonal and its neighbours: at most adj count + 1 entries
  std::vector<int> col_start(static_cast<std::size_t>(nv) + 1, 0);
  for (Index v = 0; v < nv; ++v) col_start[v + 1] = col_start[v] + (adj_start[v + 1] - adj_start[v]) + 1;
  std::vector<int> rows(col_start[nv]);
  std::vector<double> vals(col_start[nv]);
  std::vector<int> fill(col_start.begin(), col_start.end() - 1);
  for (Index i = 0; i < nv; ++i) {
    double diag = 0.0;
    for (Index k = adj_start[i]; k < adj_start[i + 1]; ++k) diag += adj_weight[k];
    // the diagonal goes to column i now: rows < i are already there, rows > i come later
    rows[fill[i]] = i;
    vals[fill[i]++] = diag;
    for (Index k = adj_start[i]; k < adj_start[i + 1]; ++k) {
      const Index j = adj_vertex[k];
      int& pos = fill[j];
      if (pos > col_start[j] && rows[pos - 1] == i) {
        vals[pos - 1] -= adj_weight[k];  // another edge between i and j
      } else {
        rows[pos] = i;
        vals[pos++] = -adj_weight[k];
      }
    }
  }
  // compact away the room reserved for merged duplicates
  SparseMatrix L(nv, nv);
  int nnz = 0;
  for (Index j = 0; j < nv; ++j) nnz += fill[j] - col_start[j];
  L.resizeNonZeros(nnz);
  int* outer = L.outerIndexPtr();
  int* inner = L.innerIndexPtr();
  double* value = L.valuePtr();
  int out = 0;
  for (Index j = 0; j < nv; ++j) {
    outer[j] = out;
    for (int k = col_start[j]; k < fill[j]; ++k) {
      inner[out] = rows[k];
      value[out++] = vals[k];
    }
  }
  outer[nv] = out;
  return L;
}

Eigen::VectorXd face_areas(const IntrinsicTriangulation& tri) {
  const Index nf = tri.n_faces();
  Eigen::VectorXd a(nf);
#pragma omp parallel for schedule(static)
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
