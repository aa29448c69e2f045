#include "intrinsic/core/side_pairs.h"

#include <algorithm>
#include <cstdint>

#include "intrinsic/core/types.h"

namespace ifem::intrinsic {
namespace {

// Buckets sides by their smaller vertex (counting sort) as 64-bit keys (larger vertex << 32 |
// side id), sorts each bucket, then cuts the buckets into groups. `corner(f, s)` reads the face
// list; `n_faces` faces.
template <class Corner>
SideGroups group_sides_impl(Index n_faces, Index n_vertices, const Corner& corner) {
  auto degenerate = [&](Index f) {
    return corner(f, 0) == corner(f, 1) || corner(f, 1) == corner(f, 2) ||
           corner(f, 2) == corner(f, 0);
  };
  std::vector<Index> start(static_cast<std::size_t>(n_vertices) + 1, 0);
  for (Index f = 0; f < n_faces; ++f) {
    if (degenerate(f)) continue;
    for (int s = 0; s < 3; ++s) ++start[std::min(corner(f, s), corner(f, (s + 1) % 3)) + 1];
  }
  for (Index v = 0; v < n_vertices; ++v) start[v + 1] += start[v];
  std::vector<std::uint64_t> key(static_cast<std::size_t>(start[n_vertices]));
  {
    std::vector<Index> fill(start.begin(), start.end() - 1);
    for (Index f = 0; f < n_faces; ++f) {
      if (degenerate(f)) continue;
      for (int s = 0; s < 3; ++s) {
        const Index a = corner(f, s), b = corner(f, (s + 1) % 3);
        key[fill[std::min(a, b)]++] = static_cast<std::uint64_t>(std::max(a, b)) << 32 |
                                      static_cast<std::uint32_t>(3 * f + s);
      }
    }
  }
  // buckets are small (about the vertex degree): insertion sort, std::sort for the rare big one
#pragma omp parallel for schedule(dynamic, 256) if (n_vertices >= kParallelMin)
  for (Index v = 0; v < n_vertices; ++v) {
    if (start[v + 1] - start[v] < 2) continue;  // nothing to sort (and key may be empty)
    std::uint64_t* b = key.data() + start[v];
    std::uint64_t* e = key.data() + start[v + 1];
    if (e - b > 32) {
      std::sort(b, e);
      continue;
    }
    for (std::uint64_t* i = b + 1; i < e; ++i) {
      const std::uint64_t x = *i;
      std::uint64_t* j = i;
      for (; j > b && *(j - 1) > x; --j) *j = *(j - 1);
      *j = x;
    }
  }
  SideGroups g;
  g.side.resize(key.size());
  g.group_begin.reserve(key.size() / 2 + 2);
  for (Index v = 0; v < n_vertices; ++v) {
    for (Index i = start[v]; i < start[v + 1]; ++i) {
      const Index hi = static_cast<Index>(key[i] >> 32);
      if (i == start[v] || hi != g.hi.back()) {
        g.group_begin.push_back(i);
        g.lo.push_back(v);
        g.hi.push_back(hi);
      }
      g.side[i] = static_cast<Index>(key[i] & 0xffffffffu);
    }
  }
  g.group_begin.push_back(static_cast<Index>(key.size()));
  return g;
}

}  // namespace

SideGroups group_sides(const std::vector<Triangle>& faces, Index n_vertices) {
  checked_index(3 * faces.size(), "group_sides");  // side ids fit in Index
  return group_sides_impl(static_cast<Index>(faces.size()), n_vertices,
                          [&](Index f, int s) { return faces[f][s]; });
}

SideGroups group_sides(const std::vector<Index>& tails, Index n_vertices) {
  checked_index(tails.size(), "group_sides");
  return group_sides_impl(static_cast<Index>(tails.size() / 3), n_vertices,
                          [&](Index f, int s) { return tails[3 * f + s]; });
}

}  // namespace ifem::intrinsic
