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

}  // namespace ifem::intrinsic
