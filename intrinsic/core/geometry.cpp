// The whole-triangulation geometry of geometry.h (areas, angle sums, defects, cotan weights).
#include "intrinsic/core/geometry.h"

#include <algorithm>
#include <vector>

namespace ifem::intrinsic {

double total_area(const IntrinsicTriangulation& tri) {
  double sum = 0.0;
  for (Index f = 0; f < tri.n_faces(); ++f) sum += face_area(tri, f);
  return sum / tri.multiplicity();
}

Eigen::VectorXd vertex_angle_sums(const IntrinsicTriangulation& tri) {
  Eigen::VectorXd sums = Eigen::VectorXd::Zero(tri.n_vertices());
  for (Index h = 0; h < tri.n_halfedges(); ++h) sums[tri.tail(h)] += corner_angle(tri, h);
  return sums;
}

Eigen::VectorXd angle_defects(const IntrinsicTriangulation& tri) {
  Eigen::VectorXd defect = Eigen::VectorXd::Constant(tri.n_vertices(), 2.0 * kPi);
  defect -= vertex_angle_sums(tri);
  for (Index h = 0; h < tri.n_halfedges(); ++h) {
    if (tri.twin(h) == kInvalidIndex) defect[tri.tail(h)] -= kPi;
  }
  return defect;
}

Eigen::VectorXd cotan_weights(const IntrinsicTriangulation& tri) {
  // one area per face (not one per halfedge): cot of the angle opposite each side
  const Index nf = tri.n_faces();
  std::vector<double> cot(tri.n_halfedges());
#pragma omp parallel for schedule(static) if (nf >= kParallelMin)
  for (Index f = 0; f < nf; ++f) {
    // on lengths normalized by a power of two (exact): cotangents are dimensionless, so the
    // weights are the same bits at every scale and squares never over- or underflow
    double l0 = tri.halfedge_length(3 * f), l1 = tri.halfedge_length(3 * f + 1),
           l2 = tri.halfedge_length(3 * f + 2);
    const double scale = length_normalizer(std::max({l0, l1, l2}));
    if (scale != 1.0) l0 /= scale, l1 /= scale, l2 /= scale;
    const double inv4a = 0.25 / triangle_area(l0, l1, l2);
    const double s0 = l0 * l0, s1 = l1 * l1, s2 = l2 * l2;
    cot[3 * f] = (s1 + s2 - s0) * inv4a;
    cot[3 * f + 1] = (s2 + s0 - s1) * inv4a;
    cot[3 * f + 2] = (s0 + s1 - s2) * inv4a;
  }
  const Index ne = tri.n_edges();
  Eigen::VectorXd w(ne);
#pragma omp parallel for schedule(static) if (ne >= kParallelMin)
  for (Index e = 0; e < ne; ++e) {
    const Index h = tri.edge_halfedge(e);
    const Index t = tri.twin(h);
    w[e] = 0.5 * (cot[h] + (t != kInvalidIndex ? cot[t] : 0.0));
  }
  return w;
}

bool vertex_star_is_disk(const IntrinsicTriangulation& tri, Index v, std::vector<Index>* spokes) {
  using T = IntrinsicTriangulation;
  spokes->clear();
  if (v < 0 || v >= tri.n_vertices()) return false;
  const Index h0 = tri.vertex_halfedge(v);
  if (h0 == kInvalidIndex) return false;
  Index h = h0;
  for (Index guard = 0;; ++guard) {
    if (guard > 4096) return false;
    if (tri.head(h) == v) return false;  // self-edge
    spokes->push_back(h);
    const Index n = tri.twin(T::prev(h));
    if (n == kInvalidIndex) return false;
    if (n == h0) break;
    h = n;
  }
  const std::size_t n = spokes->size();
  if (n < 3) return false;
  std::vector<Index> faces;
  faces.reserve(n);
  for (const Index x : *spokes) faces.push_back(T::face(x));
  std::sort(faces.begin(), faces.end());
  if (std::adjacent_find(faces.begin(), faces.end()) != faces.end()) return false;
  for (const Index x : *spokes) {
    const Index tw = tri.twin(T::next(x));
    if (tw != kInvalidIndex && std::binary_search(faces.begin(), faces.end(), T::face(tw))) {
      return false;
    }
  }
  return true;
}

std::vector<Eigen::Vector2d> flat_star_layout(const IntrinsicTriangulation& tri,
                                              const std::vector<Index>& spokes) {
  std::vector<Eigen::Vector2d> ring;
  ring.reserve(spokes.size());
  double phi = 0.0;
  for (const Index h : spokes) {
    const double l = tri.halfedge_length(h);
    ring.emplace_back(l * std::cos(phi), l * std::sin(phi));
    phi += corner_angle(tri, h);
  }
  return ring;
}

bool inside_star_kernel(const std::vector<Eigen::Vector2d>& ring, const Eigen::Vector2d& p,
                        double min_relative_height) {
  const std::size_t n = ring.size();
  for (std::size_t i = 0; i < n; ++i) {
    const Eigen::Vector2d& a = ring[i];
    const Eigen::Vector2d& b = ring[(i + 1) % n];
    // cross = |ab| × height of p above ab
    if (!(cross2(a - p, b - p) > min_relative_height * (b - a).squaredNorm())) return false;
  }
  return true;
}

bool inserted_vertex_star(const IntrinsicTriangulation& tri, Index v, Index n_input,
                          std::vector<Index>* spokes, std::vector<Eigen::Vector2d>* ring) {
  ring->clear();
  if (v < n_input || !vertex_star_is_disk(tri, v, spokes)) {
    spokes->clear();
    return false;
  }
  *ring = flat_star_layout(tri, *spokes);
  return true;
}

StarMove check_star_move(const IntrinsicTriangulation& tri, Index v, Index n_input,
                         const Eigen::Vector2d& displacement, double min_relative_height,
                         std::vector<Index>* spokes, std::vector<Eigen::Vector2d>* ring) {
  if (!inserted_vertex_star(tri, v, n_input, spokes, ring)) return StarMove::kRefused;
  const double dist = displacement.norm();
  if (!std::isfinite(dist)) return StarMove::kRefused;
  if (!(dist > 0.0)) return StarMove::kStays;
  if (!inside_star_kernel(*ring, displacement, min_relative_height)) return StarMove::kRefused;
  return StarMove::kMoves;
}

}  // namespace ifem::intrinsic
