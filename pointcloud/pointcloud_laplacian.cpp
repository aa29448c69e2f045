#include "pointcloud/pointcloud_laplacian.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <string>

#include <Eigen/Eigenvalues>
#include <Eigen/Geometry>

#include "intrinsic/errors.h"
#include "pointcloud/local_delaunay.h"

#ifdef _OPENMP
#include <omp.h>
#endif

namespace ifem::pointcloud {
namespace {

double now() {
  return std::chrono::duration<double>(std::chrono::steady_clock::now().time_since_epoch())
      .count();
}

int thread_count() {
#ifdef _OPENMP
  return omp_get_max_threads();
#else
  return 1;
#endif
}

int thread_id() {
#ifdef _OPENMP
  return omp_get_thread_num();
#else
  return 0;
#endif
}

// Unit normal of a neighbourhood by PCA (eigenvector of the smallest covariance eigenvalue),
// from offsets d_j = p_j − p_i already scaled to O(1). Any unit vector when degenerate.
Eigen::Vector3d pca_normal(const std::vector<Eigen::Vector3d>& d) {
  Eigen::Vector3d mean = Eigen::Vector3d::Zero();
  for (const auto& x : d) mean += x;
  mean /= static_cast<double>(d.size() + 1);  // the centre (offset 0) is part of the sample
  Eigen::Matrix3d cov = mean * mean.transpose();  // the centre's term
  for (const auto& x : d) {
    const Eigen::Vector3d y = x - mean;
    cov += y * y.transpose();
  }
  const double tr = cov.trace();
  if (!(tr > 0.0) || !std::isfinite(tr)) return Eigen::Vector3d::UnitZ();
  cov /= tr;
  Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> es;
  es.computeDirect(cov);
  Eigen::Vector3d n = es.eigenvectors().col(0);
  const double len = n.norm();
  if (!(len > 0.5) || !n.allFinite()) {
    es.compute(cov);  // the iterative solver copes with any symmetric input
    n = es.eigenvectors().col(0);
  }
  n.normalize();
  return n.allFinite() ? n : Eigen::Vector3d::UnitZ();
}

}  // namespace

void Options::validate() const {
  if (k < 2) throw InvalidInput("point cloud: k must be ≥ 2, got " + std::to_string(k));
  if (!(mollify_relative_epsilon >= 0.0) || !std::isfinite(mollify_relative_epsilon)) {
    throw InvalidInput("point cloud: mollification margin must be finite and ≥ 0");
  }
}

std::vector<Triangle> local_triangulations(const Positions& points, const Neighbours& nb,
                                           const Eigen::MatrixX3d* normals, Report* report) {
  const Index n = static_cast<Index>(points.rows());
  if (nb.k > 0 && nb.ids.size() != static_cast<std::size_t>(nb.k) * n) {
    throw InvalidInput("local_triangulations: neighbour table does not match the points");
  }
  if (normals && normals->rows() != n) {
    throw InvalidInput("local_triangulations: " + std::to_string(normals->rows()) +
                       " normals for " + std::to_string(n) + " points");
  }
  const int nt = thread_count();
  std::vector<std::vector<Triangle>> per_thread(nt);
  Index starless = 0, from_normals = 0, coincident = 0;
  const int k = nb.k;
#pragma omp parallel reduction(+ : starless, from_normals, coincident)
  {
    std::vector<Triangle>& out = per_thread[thread_id()];
    std::vector<Eigen::Vector3d> d(k);
    std::vector<Eigen::Vector2d> q(k);
    std::vector<std::array<int, 2>> star;
    // static schedule: thread t gets the t-th contiguous block, so concatenating the
    // per-thread lists in thread order gives point order
#pragma omp for schedule(static)
    for (Index i = 0; i < n; ++i) {
      const Index* nbr = nb.of(i);
      const Eigen::Vector3d pi = points.row(i).transpose();
      double r = 0.0;
      bool has_coincident = false;
      for (int j = 0; j < k; ++j) {
        d[j] = points.row(nbr[j]).transpose() - pi;
        const double l = d[j].norm();
        r = std::max(r, l);
        if (l == 0.0) has_coincident = true;
      }
      coincident += has_coincident;
      star.clear();
      if (k >= 2 && r > 0.0 && std::isfinite(r)) {
        for (int j = 0; j < k; ++j) d[j] /= r;
        Eigen::Vector3d nrm;
        bool have = false;
        if (normals) {
          nrm = normals->row(i).transpose();
          const double l = nrm.norm();
          if (l > 0.0 && std::isfinite(l)) {
            nrm /= l;
            have = true;
            ++from_normals;
          }
        }
        if (!have) nrm = pca_normal(d);
        // tangent basis: t1 ⟂ n from the axis least aligned with n
        int axis = 0;
        if (std::abs(nrm[1]) < std::abs(nrm[axis])) axis = 1;
        if (std::abs(nrm[2]) < std::abs(nrm[axis])) axis = 2;
        const Eigen::Vector3d t1 = nrm.cross(Eigen::Vector3d::Unit(axis)).normalized();
        const Eigen::Vector3d t2 = nrm.cross(t1);
        for (int j = 0; j < k; ++j) q[j] = Eigen::Vector2d(d[j].dot(t1), d[j].dot(t2));
        delaunay_star(q, star);
      }
      if (star.empty()) ++starless;
      for (const auto& ab : star) out.push_back({i, nbr[ab[0]], nbr[ab[1]]});
    }
  }
  std::size_t total = 0;
  for (const auto& v : per_thread) total += v.size();
  std::vector<Triangle> tris;
  tris.reserve(total);
  for (auto& v : per_thread) {
    tris.insert(tris.end(), v.begin(), v.end());
    std::vector<Triangle>().swap(v);
  }
  if (report) {
    report->local_triangles = checked_index(tris.size(), "local_triangulations");
    report->starless_points = starless;
    report->normals_from_input = from_normals;
    report->coincident_points = coincident;
  }
  return tris;
}

intrinsic::IntrinsicTriangulation pointcloud_triangulation(const Positions& points,
                                                           const Options& options,
                                                           const Eigen::MatrixX3d* normals,
                                                           Report* report) {
  options.validate();
  const Index n = checked_index(static_cast<std::size_t>(points.rows()), "point cloud");
  for (Index i = 0; i < n; ++i) {
    if (!points.row(i).allFinite()) {
      throw InvalidInput("point cloud: point " + std::to_string(i) +
                         " has a non-finite coordinate");
    }
  }
  if (normals && normals->rows() != n) {
    throw InvalidInput("point cloud: " + std::to_string(normals->rows()) + " normals for " +
                       std::to_string(n) + " points");
  }
  Report rep;
  rep.points = n;
  double t0 = now();
  const Neighbours nb = k_nearest(points, options.k);
  rep.k = nb.k;
  rep.seconds_knn = now() - t0;

  t0 = now();
  const std::vector<Triangle> tris =
      local_triangulations(points, nb, options.use_input_normals ? normals : nullptr, &rep);
  rep.seconds_local = now() - t0;

  t0 = now();
  intrinsic::IntrinsicTriangulation tri =
      intrinsic::tufted_cover(tris, points, &rep.cover, /*input_multiplicity=*/3);
  rep.mollify = tri.mollify(options.mollify_relative_epsilon);
  rep.seconds_cover = now() - t0;
  rep.isolated_points = rep.cover.unreferenced_vertices;
  for (Index i = 0; i < n; ++i) {
    if (tri.vertex_halfedge(i) == kInvalidIndex) {
      rep.first_isolated_point = i;
      break;
    }
  }
  rep.cover.parent_face.clear();  // the local triangles are not kept: nothing to point at
  rep.cover.parent_face.shrink_to_fit();

  if (options.intrinsic_delaunay) {
    t0 = now();
    rep.flips = tri.flip_to_delaunay();
    rep.seconds_idt = now() - t0;
  }
  if (report) *report = std::move(rep);
  return tri;
}

}  // namespace ifem::pointcloud
