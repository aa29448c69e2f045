// k nearest neighbours of every point of a cloud (nanoflann k-d tree, hidden behind this
// interface).
#pragma once

#include <vector>

#include "intrinsic/core/types.h"

namespace ifem::pointcloud {

/// For each point, its k nearest other points, nearest first (ties by index).
struct Neighbours {
  int k = 0;               ///< neighbours per point
  std::vector<Index> ids;  ///< #P·k, row-major: ids[k·i + j] is the j-th neighbour of point i
  const Index* of(Index i) const { return ids.data() + static_cast<std::size_t>(k) * i; }
  /// All point ids in a spatially coherent order (the k-d tree's leaf order), for loops that
  /// gain from cache locality; empty if not computed (then use 0..#P−1).
  std::vector<Index> spatial_order;
};

/// k nearest neighbours of every point, the point itself excluded (an exact duplicate of it
/// is a neighbour at distance 0). k is clamped to #P − 1. Coordinates are centred and scaled
/// internally, so huge (LiDAR, 1e6 m) and tiny coordinates behave alike. Parallel (OpenMP)
/// over points.
/// @throws InvalidInput on a non-finite coordinate or k < 1
Neighbours k_nearest(const Positions& points, int k);

}  // namespace ifem::pointcloud
