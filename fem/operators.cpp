#include "fem/operators.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>
#include <string>
#include <utility>
#include <vector>

#include "intrinsic/core/errors.h"
#include "intrinsic/core/geometry.h"
#include "intrinsic/core/types.h"

namespace ifem::fem {

using intrinsic::IntrinsicTriangulation;

SparseMatrix cotan_laplacian(const IntrinsicTriangulation& tri) {
  const Eigen::VectorXd w = intrinsic::cotan_weights(tri);
  for (Index e = 0; e < w.size(); ++e) {
    if (!std::isfinite(w[e])) {
      const Index h = tri.edge_halfedge(e);
      throw Error("cotan_laplacian: the weight of edge " + std::to_string(e) + " (" +
                  std::to_string(tri.tail(h)) + "," +
                  std::to_string(tri.tail(IntrinsicTriangulation::next(h))) +
                  ") is not finite: face " + std::to_string(IntrinsicTriangulation::face(h)) +
                  " or its neighbour has zero area (mollify the triangulation first)");
    }
  }
  return laplacian_from_weights(tri, w);
}

namespace {

// The two end vertices of edge e (equal for a self-edge).
inline std::pair<Index, Index> edge_ends(const IntrinsicTriangulation& tri,
                                         const std::vector<Index>& tails, Index e) {
  const Index h = tri.edge_halfedge(e);
  return {tails[h], tails[IntrinsicTriangulation::next(h)]};
}

// Column starts of L: one slot per edge end plus one for the diagonal, as a prefix sum in outer.
void count_columns(const IntrinsicTriangulation& tri, const std::vector<Index>& tails, int* outer) {
  const Index nv = tri.n_vertices();
  std::fill(outer, outer + nv + 1, 0);
  for (Index e = 0; e < tri.n_edges(); ++e) {
    const auto [i, j] = edge_ends(tri, tails, e);
    if (i == j) continue;  // a self-edge adds w and subtracts it again: nothing
    ++outer[i + 1];
    ++outer[j + 1];
  }
  for (Index v = 0; v < nv; ++v) outer[v + 1] += outer[v] + 1;  // +1: the diagonal
}

// Scatters each edge's two off-diagonal entries into their columns (unsorted); returns each
// column's fill end in fill and the accumulated diagonal in diag.
void scatter_edges(const IntrinsicTriangulation& tri, const std::vector<Index>& tails,
                   const Eigen::VectorXd& w, const int* outer, int* inner, double* value,
                   std::vector<int>& fill, Eigen::VectorXd& diag) {
  const Index nv = tri.n_vertices();
  const double scale = 1.0 / tri.multiplicity();
  fill.assign(outer, outer + nv);
  diag = Eigen::VectorXd::Zero(nv);
  for (Index e = 0; e < tri.n_edges(); ++e) {
    const auto [i, j] = edge_ends(tri, tails, e);
    if (i == j) continue;
    const double we = scale * w[e];
    inner[fill[j]] = i;
    value[fill[j]++] = -we;
    inner[fill[i]] = j;
    value[fill[i]++] = -we;
    diag[i] += we;
    diag[j] += we;
  }
}

}  // namespace

int sort_and_merge_column(int* r, double* x, int n) {
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
  return m;
}

int squeeze_columns(Index nv, const std::vector<int>& count, int* outer, int* inner,
                    double* value) {
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
  return out;
}

SparseMatrix laplacian_from_weights(const IntrinsicTriangulation& tri, const Eigen::VectorXd& w) {
  // Direct CSC assembly (no triplets): count entries per column, scatter each edge's two
  // off-diagonal entries straight into the matrix arrays, then sort each (small) column by row
  // in parallel, merging parallel edges (multi-edges of a Δ-complex); the diagonal goes last.
  const Index nv = tri.n_vertices();
  const auto& tails = tri.tails();
  SparseMatrix L(nv, nv);
  int* outer = L.outerIndexPtr();
  count_columns(tri, tails, outer);
  L.resizeNonZeros(outer[nv]);
  int* inner = L.innerIndexPtr();
  double* value = L.valuePtr();
  std::vector<int> fill;
  Eigen::VectorXd diag;
  scatter_edges(tri, tails, w, outer, inner, value, fill, diag);
  std::vector<int> count(nv);
#pragma omp parallel for schedule(static) if (nv >= kParallelMin)
  for (Index v = 0; v < nv; ++v) {
    int* r = inner + outer[v];
    double* x = value + outer[v];
    int n = fill[v] - outer[v];
    r[n] = v;  // the diagonal
    x[n++] = diag[v];
    count[v] = sort_and_merge_column(r, x, n);
  }
  L.data().resize(squeeze_columns(nv, count, outer, inner, value));
  return L;
}

Eigen::VectorXd face_areas(const IntrinsicTriangulation& tri) {
  const Index nf = tri.n_faces();
  Eigen::VectorXd a(nf);
#pragma omp parallel for schedule(static) if (nf >= kParallelMin)
  for (Index f = 0; f < nf; ++f) a[f] = intrinsic::face_area(tri, f);
  return a;
}

namespace {

// Face areas must be representable: at lengths beyond ~1e154 they overflow, below ~1e-154 they
// underflow to 0 although the face is a real triangle (its normalized area is positive). Either
// way the mass would be silently wrong (inf or 0): refuse, naming the face.
void require_representable(const IntrinsicTriangulation& tri, const Eigen::VectorXd& area) {
  for (Index f = 0; f < tri.n_faces(); ++f) {
    if (std::isfinite(area[f]) && area[f] >= std::numeric_limits<double>::min()) continue;
    double l[3];
    for (int k = 0; k < 3; ++k) l[k] = tri.halfedge_length(3 * f + k);
    const double scale = intrinsic::power_of_two_scale(std::max({l[0], l[1], l[2]}));
    if (std::isfinite(area[f]) &&
        !(intrinsic::triangle_area(l[0] / scale, l[1] / scale, l[2] / scale) > 0.0)) {
      continue;  // a degenerate face: zero area is its true area
    }
    char length[32];
    std::snprintf(length, sizeof length, "%.3g", l[0]);
    throw Error("mass matrix: the area of face " + std::to_string(f) + " (edge lengths around " +
                length + ") is not representable in double precision; scale the input towards " +
                "unit size (distances are computed scale-free, mass is not)");
  }
}

}  // namespace

Eigen::VectorXd lumped_mass(const IntrinsicTriangulation& tri) {
  const Eigen::VectorXd area = face_areas(tri);
  require_representable(tri, area);
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
  require_representable(tri, area);
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
