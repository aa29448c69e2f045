#include "pointcloud/knn.h"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <nanoflann.hpp>
#include <string>
#include <utility>

#include "intrinsic/core/errors.h"

namespace ifem::pointcloud {
namespace {

// Zero-copy view of a #P×3 row-major array for nanoflann.
struct CloudView {
  const double* xyz = nullptr;
  std::size_t n = 0;
  std::size_t kdtree_get_point_count() const { return n; }
  double kdtree_get_pt(std::size_t i, std::size_t d) const { return xyz[3 * i + d]; }
  template <class Bbox>
  bool kdtree_get_bbox(Bbox&) const {
    return false;
  }
};

using Tree = nanoflann::KDTreeSingleIndexAdaptor<nanoflann::L2_Simple_Adaptor<double, CloudView>,
                                                 CloudView, 3, std::uint32_t>;

}  // namespace

Neighbours k_nearest(const Positions& points, int k) {
  const Index n = checked_index(static_cast<std::size_t>(points.rows()), "k_nearest");
  if (k < 1) throw InvalidInput("k_nearest: k must be ≥ 1, got " + std::to_string(k));
  Neighbours nb;
  nb.k = std::min<Index>(k, std::max<Index>(n - 1, 0));
  if (nb.k == 0) return nb;
  // centre on the bounding box and scale to unit size: LiDAR coordinates (1e5..1e6 m) keep
  // their precision and tiny coordinates do not underflow when squared
  Eigen::RowVector3d lo = points.colwise().minCoeff(), hi = points.colwise().maxCoeff();
  if (!lo.allFinite() || !hi.allFinite()) {
    for (Index i = 0; i < n; ++i) {
      if (!points.row(i).allFinite()) {
        throw InvalidInput("k_nearest: point " + std::to_string(i) +
                           " has a non-finite coordinate");
      }
    }
  }
  const Eigen::RowVector3d centre = 0.5 * (lo + hi);
  double extent = (hi - lo).maxCoeff();
  if (!(extent > 0.0) || !std::isfinite(extent)) extent = 1.0;
  std::vector<double> xyz(3 * static_cast<std::size_t>(n));
  for (Index i = 0; i < n; ++i) {
    for (int d = 0; d < 3; ++d) xyz[3 * i + d] = (points(i, d) - centre[d]) / extent;
  }
  CloudView view{xyz.data(), static_cast<std::size_t>(n)};
  const Tree tree(3, view, nanoflann::KDTreeSingleIndexAdaptorParams(24));
  nb.ids.resize(static_cast<std::size_t>(nb.k) * n);
  nb.spatial_order.assign(tree.vAcc.begin(), tree.vAcc.end());
  const int want = nb.k + 1;
#pragma omp parallel
  {
    std::vector<std::uint32_t> idx(want);
    std::vector<double> dist(want);
    std::vector<std::pair<double, Index>> found;
    // queries in the tree's leaf order (vAcc): consecutive queries are close in space, so
    // their tree paths and neighbours stay in cache (input order may be anything)
#pragma omp for schedule(dynamic, 512)
    for (Index t = 0; t < n; ++t) {
      const Index i = static_cast<Index>(tree.vAcc[t]);
      nanoflann::KNNResultSet<double, std::uint32_t, std::size_t> rs(want);
      rs.init(idx.data(), dist.data());
      tree.findNeighbors(rs, &xyz[3 * static_cast<std::size_t>(i)], nanoflann::SearchParams());
      const std::size_t got = rs.size();
      found.clear();
      for (std::size_t j = 0; j < got; ++j) {
        if (static_cast<Index>(idx[j]) != i)
          found.emplace_back(dist[j], static_cast<Index>(idx[j]));
      }
      std::sort(found.begin(), found.end());
      Index* out = nb.ids.data() + static_cast<std::size_t>(nb.k) * i;
      // `found` has k entries, or k + 1 when i itself was not among the k + 1 nearest (more
      // than k exact duplicates of it): keep the first k
      for (int j = 0; j < nb.k; ++j) {
        out[j] = j < static_cast<int>(found.size()) ? found[j].second : found.back().second;
      }
    }
  }
  return nb;
}

}  // namespace ifem::pointcloud
