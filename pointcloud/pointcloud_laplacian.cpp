#include "pointcloud/pointcloud_laplacian.h"

#include <Eigen/Eigenvalues>
#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <string>
#include <utility>

#include "intrinsic/core/errors.h"
#include "intrinsic/core/timer.h"
#include "intrinsic/core/types.h"
#include "pointcloud/local_delaunay.h"

#ifdef _OPENMP
#include <omp.h>
#endif

namespace ifem::pointcloud {
namespace {

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
  mean /= static_cast<double>(d.size() + 1);      // the centre (offset 0) is part of the sample
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

void PointCloudOptions::validate() const {
  if (k < 2)
    throw InvalidInput("pointcloud::PointCloudOptions::k must be ≥ 2, got " + std::to_string(k));
  if (!(mollify_relative_epsilon >= 0.0) || !std::isfinite(mollify_relative_epsilon)) {
    throw InvalidInput(
        "pointcloud::PointCloudOptions::mollify_relative_epsilon must be finite and ≥ 0");
  }
}

namespace {

// Every point's Delaunay star, in point order: tris[offset[i] .. offset[i+1]) are the
// triangles (i, a, b) of point i.
struct Stars {
  std::vector<Index> offset;
  std::vector<Triangle> tris;
};

// Refuses a neighbour table or a normal array that does not match the points.
void check_star_inputs(Index n, const Neighbours& nb, const Eigen::MatrixX3d* normals) {
  if (nb.k > 0 && nb.ids.size() != static_cast<std::size_t>(nb.k) * n) {
    throw InvalidInput("local_triangulations: neighbour table does not match the points");
  }
  if (normals && normals->rows() != n) {
    throw InvalidInput("local_triangulations: " + std::to_string(normals->rows()) +
                       " normals for " + std::to_string(n) + " points");
  }
}

// One thread's scratch memory for point stars, reused across points (no allocation per point).
struct StarScratch {
  explicit StarScratch(int k) : d(k), q(k) {}
  std::vector<Eigen::Vector3d> d;  // neighbour offsets, scaled by 1 / their largest length
  std::vector<Eigen::Vector2d> q;  // the offsets in the tangent plane
  std::vector<std::array<int, 2>> star;
  StarWorkspace ws;
};

// Unit normal at point i: the input normal when usable (counted in from_normals), otherwise
// PCA of the scaled offsets d.
Eigen::Vector3d star_normal(const Eigen::MatrixX3d* normals, Index i,
                            const std::vector<Eigen::Vector3d>& d, Index& from_normals) {
  if (normals) {
    Eigen::Vector3d nrm = normals->row(i).transpose();
    const double l = nrm.norm();
    if (l > 0.0 && std::isfinite(l)) {
      nrm /= l;
      ++from_normals;
      return nrm;
    }
  }
  return pca_normal(d);
}

// Projects the k offsets d onto the plane ⟂ nrm (t1 from the axis least aligned with nrm).
void project_to_tangent_plane(const Eigen::Vector3d& nrm, int k, StarScratch& s) {
  int axis = 0;
  if (std::abs(nrm[1]) < std::abs(nrm[axis])) axis = 1;
  if (std::abs(nrm[2]) < std::abs(nrm[axis])) axis = 2;
  const Eigen::Vector3d t1 = nrm.cross(Eigen::Vector3d::Unit(axis)).normalized();
  const Eigen::Vector3d t2 = nrm.cross(t1);
  for (int j = 0; j < k; ++j) s.q[j] = Eigen::Vector2d(s.d[j].dot(t1), s.d[j].dot(t2));
}

// Point i's Delaunay star among its k neighbours nbr, as index pairs into nbr in s.star (empty
// when the neighbourhood is degenerate); returns whether a neighbour coincides with point i.
bool point_star(const Positions& points, const Eigen::MatrixX3d* normals, Index i, const Index* nbr,
                int k, StarScratch& s, Index& from_normals) {
  const Eigen::Vector3d pi = points.row(i).transpose();
  double r = 0.0;
  bool has_coincident = false;
  for (int j = 0; j < k; ++j) {
    s.d[j] = points.row(nbr[j]).transpose() - pi;
    const double l = s.d[j].norm();
    r = std::max(r, l);
    if (l == 0.0) has_coincident = true;
  }
  s.star.clear();
  if (k >= 2 && r > 0.0 && std::isfinite(r)) {
    const double inv_r = 1.0 / r;
    for (int j = 0; j < k; ++j) s.d[j] *= inv_r;
    project_to_tangent_plane(star_normal(normals, i, s.d, from_normals), k, s);
    delaunay_star(s.q, s.star, s.ws);
  }
  return has_coincident;
}

// Concatenates the per-thread star triangles into st.tris in point order (st.offset already
// holds the prefix sums); where[i] = (thread, position) of point i's star when spatial.
void gather_stars(std::vector<std::vector<Triangle>>& per_thread,
                  const std::vector<std::pair<int, std::size_t>>& where, bool spatial, Stars& st) {
  const Index n = static_cast<Index>(st.offset.size()) - 1;
  if (spatial) {
    st.tris.resize(st.offset[n]);
#pragma omp parallel for schedule(static) if (n >= kParallelMin)
    for (Index i = 0; i < n; ++i) {
      const Triangle* src = per_thread[where[i].first].data() + where[i].second;
      std::copy(src, src + (st.offset[i + 1] - st.offset[i]), st.tris.data() + st.offset[i]);
    }
    for (auto& v : per_thread) std::vector<Triangle>().swap(v);
  } else {
    st.tris.reserve(st.offset[n]);
    for (auto& v : per_thread) {
      st.tris.insert(st.tris.end(), v.begin(), v.end());
      std::vector<Triangle>().swap(v);
    }
  }
}

Stars compute_stars(const Positions& points, const Neighbours& nb, const Eigen::MatrixX3d* normals,
                    Report* report) {
  const Index n = static_cast<Index>(points.rows());
  check_star_inputs(n, nb, normals);
  const int nt = thread_count();
  std::vector<std::vector<Triangle>> per_thread(nt);
  // points are visited in the kNN's spatial order when available (cache locality); each point's
  // star is written to its thread's buffer and found again through (thread, position)
  const bool spatial = nb.spatial_order.size() == static_cast<std::size_t>(n);
  std::vector<std::pair<int, std::size_t>> where(spatial ? n : 0);
  Stars st;
  st.offset.assign(static_cast<std::size_t>(n) + 1, 0);
  Index starless = 0, from_normals = 0, coincident = 0;
  const int k = nb.k;
#pragma omp parallel reduction(+ : starless, from_normals, coincident)
  {
    const int tid = thread_id();
    std::vector<Triangle>& out = per_thread[tid];
    out.reserve(7 * static_cast<std::size_t>(n) / nt + 64);
    StarScratch scratch(k);
    // static schedule: without a spatial order, thread t gets the t-th contiguous block, so
    // concatenating the per-thread lists in thread order gives point order
#pragma omp for schedule(static)
    for (Index t = 0; t < n; ++t) {
      const Index i = spatial ? nb.spatial_order[t] : t;
      if (spatial) where[i] = {tid, out.size()};
      const Index* nbr = nb.of(i);
      coincident += point_star(points, normals, i, nbr, k, scratch, from_normals);
      if (scratch.star.empty()) ++starless;
      st.offset[i + 1] = static_cast<Index>(scratch.star.size());
      for (const auto& ab : scratch.star) out.push_back({i, nbr[ab[0]], nbr[ab[1]]});
    }
  }
  for (Index i = 0; i < n; ++i) st.offset[i + 1] += st.offset[i];
  gather_stars(per_thread, where, spatial, st);
  if (report) {
    report->local_triangles = checked_index(st.tris.size(), "local_triangulations");
    report->starless_points = starless;
    report->normals_from_input = from_normals;
    report->coincident_points = coincident;
  }
  return st;
}

// The distinct triangles of the union of stars, each once: triangle (i, a, b) of star i is
// kept iff no corner v < i has it in its own star (so it is kept from the first star that has
// it, with that star's orientation). Counts in how many stars each distinct triangle shows up.
// copies[c] = how many times a triangle found in c stars is glued in.
std::vector<Triangle> distinct_triangles(const Stars& st, const int copies[4], Report* report) {
  const Index n = static_cast<Index>(st.offset.size()) - 1;
  const Index nt = static_cast<Index>(st.tris.size());
  auto in_star = [&](Index v, Index x, Index y) {
    for (Index t = st.offset[v]; t < st.offset[v + 1]; ++t) {
      const Triangle& u = st.tris[t];
      if ((u[1] == x && u[2] == y) || (u[1] == y && u[2] == x)) return true;
    }
    return false;
  };
  std::vector<char> keep(nt);  // 0, or the number of stars with the triangle
  Index by_stars[4] = {0, 0, 0, 0};
  Index c1 = 0, c2 = 0, c3 = 0;
#pragma omp parallel for schedule(static) reduction(+ : c1, c2, c3)
  for (Index i = 0; i < n; ++i) {
    for (Index t = st.offset[i]; t < st.offset[i + 1]; ++t) {
      const Index a = st.tris[t][1], b = st.tris[t][2];
      const bool in_a = in_star(a, i, b), in_b = in_star(b, i, a);
      const bool first = !(in_a && a < i) && !(in_b && b < i);
      keep[t] = first ? static_cast<char>(1 + in_a + in_b) : 0;
      if (first) {
        const int c = 1 + in_a + in_b;
        c1 += c == 1;
        c2 += c == 2;
        c3 += c == 3;
      }
    }
  }
  by_stars[1] = c1, by_stars[2] = c2, by_stars[3] = c3;
  std::vector<Triangle> out;
  out.reserve(static_cast<std::size_t>(copies[1] * c1 + copies[2] * c2 + copies[3] * c3));
  for (Index t = 0; t < nt; ++t) {
    for (int c = 0; c < copies[static_cast<int>(keep[t])]; ++c) out.push_back(st.tris[t]);
  }
  (void)n;
  if (report) {
    report->distinct_triangles = c1 + c2 + c3;
    for (int c = 1; c <= 3; ++c) report->triangles_in_stars[c - 1] = by_stars[c];
  }
  return out;
}

}  // namespace

std::vector<Triangle> local_triangulations(const Positions& points, const Neighbours& nb,
                                           const Eigen::MatrixX3d* normals, Report* report) {
  return compute_stars(points, nb, normals, report).tris;
}

intrinsic::IntrinsicTriangulation pointcloud_triangulation(const Positions& points,
                                                           const PointCloudOptions& options,
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
  Stopwatch watch;
  const Neighbours nb = k_nearest(points, options.k);
  rep.k = nb.k;
  rep.seconds_knn = watch.seconds();

  watch.restart();
  std::vector<Triangle> tris;
  int multiplicity = 3;
  {
    Stars st = compute_stars(points, nb, options.use_input_normals ? normals : nullptr, &rep);
    if (options.merge == PointCloudOptions::Merge::kHalf) {
      const int copies[4] = {0, 1, 1, 2};
      tris = distinct_triangles(st, copies, &rep);
      multiplicity = 2;
    } else if (options.merge == PointCloudOptions::Merge::kUnion) {
      const int copies[4] = {0, 1, 1, 1};
      tris = distinct_triangles(st, copies, &rep);
      multiplicity = 1;
    } else {
      rep.distinct_triangles = rep.local_triangles;
      tris = std::move(st.tris);
    }
  }
  rep.seconds_local = watch.seconds();

  watch.restart();
  intrinsic::IntrinsicTriangulation tri =
      intrinsic::tufted_cover(tris, points, multiplicity, &rep.cover);
  rep.mollify = tri.mollify(options.mollify_relative_epsilon);
  rep.seconds_cover = watch.seconds();
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
    watch.restart();
    if (options.self_edges) {
      rep.flips = tri.flip_to_delaunay();
    } else {
      // a flip of edge a–b in the diamond (a, b, c | b, a, d) makes c–d: skipped when c = d
      rep.flips = tri.flip_to_delaunay([&tri](Index e) {
        const Index h = tri.edge_halfedge(e), t = tri.twin(h);
        if (t != kInvalidIndex && tri.tail(intrinsic::IntrinsicTriangulation::prev(h)) ==
                                      tri.tail(intrinsic::IntrinsicTriangulation::prev(t))) {
          return false;
        }
        return tri.flip_edge(e);
      });
    }
    rep.seconds_idt = watch.seconds();
  }
  if (report) *report = std::move(rep);
  return tri;
}

}  // namespace ifem::pointcloud
