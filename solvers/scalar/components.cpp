#include "solvers/scalar/components.h"

#include "intrinsic/core/union_find.h"

namespace ifem::solvers {

Components connected_components(const intrinsic::IntrinsicTriangulation& tri) {
  const Index nv = tri.n_vertices();
  UnionFind sets(nv);
  std::vector<char> referenced(nv, 0);
  const auto& tail = tri.tails();
  for (Index h = 0; h < tri.n_halfedges(); ++h) {
    referenced[tail[h]] = 1;
    sets.unite(tail[h], tail[intrinsic::IntrinsicTriangulation::next(h)]);
  }
  Components c;
  c.label.assign(nv, kInvalidIndex);
  std::vector<Index> root_label(nv, kInvalidIndex);
  for (Index v = 0; v < nv; ++v) {
    if (!referenced[v]) continue;
    const Index r = sets.find(v);
    if (root_label[r] == kInvalidIndex) root_label[r] = c.count++;
    c.label[v] = root_label[r];
  }
  return c;
}

}  // namespace ifem::solvers
