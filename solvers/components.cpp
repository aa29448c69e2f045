#include "solvers/components.h"

#include <numeric>

namespace ifem::solvers {

Components connected_components(const intrinsic::IntrinsicTriangulation& tri) {
  const Index nv = tri.n_vertices();
  std::vector<Index> parent(nv);
  std::iota(parent.begin(), parent.end(), 0);
  auto find = [&](Index v) {
    while (parent[v] != v) {
      parent[v] = parent[parent[v]];
      v = parent[v];
    }
    return v;
  };
  std::vector<char> referenced(nv, 0);
  const auto& tail = tri.tails();
  for (Index h = 0; h < tri.n_halfedges(); ++h) {
    const Index a = find(tail[h]), b = find(tail[intrinsic::IntrinsicTriangulation::next(h)]);
    referenced[tail[h]] = 1;
    if (a != b) parent[a < b ? b : a] = a < b ? a : b;  // root = lowest vertex
  }
  Components c;
  c.label.assign(nv, kInvalidIndex);
  std::vector<Index> root_label(nv, kInvalidIndex);
  for (Index v = 0; v < nv; ++v) {
    if (!referenced[v]) continue;
    const Index r = find(v);
    if (root_label[r] == kInvalidIndex) root_label[r] = c.count++;
    c.label[v] = root_label[r];
  }
  return c;
}

}  // namespace ifem::solvers
