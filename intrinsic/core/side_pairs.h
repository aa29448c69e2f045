// Small combinatorial tools shared by every module that reads a face list: the degenerate-face
// test and the grouping of triangle sides by the unordered pair of vertices they join.
#pragma once

#include <vector>

#include "intrinsic/core/types.h"

namespace ifem::intrinsic {

/// True when the triangle repeats a vertex id (it has no surface; constructors drop it).
inline bool repeats_vertex(const Triangle& t) {
  return t[0] == t[1] || t[1] == t[2] || t[2] == t[0];
}

/// Triangle sides grouped by the unordered pair of vertices they join (one group per edge of
/// the face list). Side x = 3f + s of face f runs from corner s to corner s + 1.
/// Groups are ordered by (lo, hi), the sides within a group by side id.
struct SideGroups {
  std::vector<Index> side;         ///< side ids, group after group
  std::vector<Index> group_begin;  ///< #groups + 1 offsets into `side`
  std::vector<Index> lo, hi;       ///< per group: the smaller and the larger vertex id

  Index n_groups() const { return static_cast<Index>(lo.size()); }
  /// Number of sides in group g (1 = boundary edge, 2 = manifold edge, 3+ = nonmanifold).
  Index size(Index g) const { return group_begin[g + 1] - group_begin[g]; }
  /// The sides of group g: side[group_begin[g]] .. side[group_begin[g + 1] - 1].
  const Index* begin(Index g) const { return side.data() + group_begin[g]; }
};

/// Groups the sides of `faces` by vertex pair in linear time (counting sort by the smaller
/// vertex, then a sort of each small bucket). Faces that repeat a vertex are skipped (their
/// side ids are simply absent). Precondition: every vertex id is in [0, n_vertices).
SideGroups group_sides(const std::vector<Triangle>& faces, Index n_vertices);

/// Same, for faces given as a flat corner array (corner s of face f at tails[3f + s]).
SideGroups group_sides(const std::vector<Index>& tails, Index n_vertices);

}  // namespace ifem::intrinsic
