// Disjoint sets over 0..n-1 (connected components of vertices, corner fans, ...).
#pragma once

#include <numeric>
#include <vector>

#include "intrinsic/core/types.h"

namespace ifem {

/// Union-find with path halving. Which element becomes a set's root is an implementation
/// detail: callers compare roots or count them (find(x) == x), never rely on their ids.
class UnionFind {
 public:
  explicit UnionFind(Index n) : parent_(static_cast<std::size_t>(n)) {
    std::iota(parent_.begin(), parent_.end(), 0);
  }
  /// The root of x's set.
  Index find(Index x) {
    while (parent_[x] != x) x = parent_[x] = parent_[parent_[x]];
    return x;
  }
  /// Joins the sets of a and b; false if they were one set already.
  bool unite(Index a, Index b) {
    a = find(a);
    b = find(b);
    if (a == b) return false;
    parent_[b] = a;
    return true;
  }

 private:
  std::vector<Index> parent_;
};

}  // namespace ifem
