#include "intrinsic/surface/face_analysis.h"

#include <algorithm>
#include <array>

#include "intrinsic/core/geometry.h"
#include "intrinsic/core/side_pairs.h"
#include "intrinsic/core/union_find.h"

namespace ifem::intrinsic {
namespace {

// Faces on the same vertex set as an earlier (non-degenerate) face.
Index count_duplicate_faces(const std::vector<Triangle>& faces) {
  std::vector<std::array<Index, 3>> sorted_faces;
  for (const Triangle& t : faces) {
    if (repeats_vertex(t)) continue;
    std::array<Index, 3> s = t;
    std::sort(s.begin(), s.end());
    sorted_faces.push_back(s);
  }
  std::sort(sorted_faces.begin(), sorted_faces.end());
  Index n = 0;
  for (std::size_t i = 1; i < sorted_faces.size(); ++i) n += sorted_faces[i] == sorted_faces[i - 1];
  return n;
}

// Vertices whose corners form 2+ fans (corner classes of `corner_uf`, corner 3f + k).
std::vector<char> nonmanifold_vertex_mask(const std::vector<Triangle>& faces, Index n_vertices,
                                          UnionFind& corner_uf) {
  std::vector<Index> first_root(n_vertices, kInvalidIndex);
  std::vector<char> nonmanifold(n_vertices, 0);
  const Index nf = static_cast<Index>(faces.size());
  for (Index f = 0; f < nf; ++f) {
    const Triangle& t = faces[f];
    if (repeats_vertex(t)) continue;
    for (Index k = 0; k < 3; ++k) {
      const Index r = corner_uf.find(3 * f + k);
      Index& fr = first_root[t[k]];
      if (fr == kInvalidIndex)
        fr = r;
      else if (fr != r)
        nonmanifold[t[k]] = 1;
    }
  }
  return nonmanifold;
}

}  // namespace

FaceListStats analyze_faces(const std::vector<Triangle>& faces, Index n_vertices) {
  FaceListStats st;
  st.vertices = n_vertices;
  st.faces = static_cast<Index>(faces.size());
  std::vector<char> referenced(n_vertices, 0);
  UnionFind vertex_uf(n_vertices);
  for (const Triangle& t : faces) {
    if (repeats_vertex(t)) {
      ++st.degenerate_faces;
      continue;
    }
    for (Index k = 0; k < 3; ++k) {
      referenced[t[k]] = 1;
      vertex_uf.unite(t[k], t[(k + 1) % 3]);
    }
  }
  st.duplicate_faces = count_duplicate_faces(faces);
  // corners (3F) joined across 2-face edges: the fans around each vertex
  const SideGroups groups = group_sides(faces, n_vertices);
  UnionFind corner_uf(3 * st.faces);
  UnionFind boundary_uf(n_vertices);
  std::vector<char> on_boundary(n_vertices, 0);
  for (Index g = 0; g < groups.n_groups(); ++g) {
    const Index n = groups.size(g), lo = groups.lo[g], hi = groups.hi[g];
    ++st.edges;
    if (n == 1) {
      ++st.boundary_edges;
      boundary_uf.unite(lo, hi);
      on_boundary[lo] = on_boundary[hi] = 1;
    } else if (n == 2) {
      const Index x = groups.begin(g)[0], y = groups.begin(g)[1];
      if (faces[x / 3][x % 3] == faces[y / 3][y % 3]) ++st.inconsistent_edges;
      // the corner of x's face at vertex v and the corner of y's face at v lie in one fan
      for (const Index v : {lo, hi}) {
        auto corner = [&](Index side) {
          const Triangle& t = faces[side / 3];
          const Index k = t[0] == v ? 0 : t[1] == v ? 1 : 2;
          return 3 * (side / 3) + k;
        };
        corner_uf.unite(corner(x), corner(y));
      }
    } else {
      if (st.nonmanifold_edges == 0) {
        st.first_nonmanifold_edge[0] = lo;
        st.first_nonmanifold_edge[1] = hi;
      }
      ++st.nonmanifold_edges;
    }
  }
  const std::vector<char> nonmanifold = nonmanifold_vertex_mask(faces, n_vertices, corner_uf);
  for (Index v = 0; v < n_vertices; ++v) {
    st.nonmanifold_vertices += nonmanifold[v];
    st.unreferenced_vertices += !referenced[v];
    if (referenced[v] && vertex_uf.find(v) == v) ++st.components;
    if (on_boundary[v] && boundary_uf.find(v) == v) ++st.boundary_loops;
  }
  return st;
}

std::vector<char> boundary_vertex_mask(const std::vector<Triangle>& faces, Index n_vertices) {
  std::vector<char> mask(n_vertices, 0);
  const SideGroups groups = group_sides(faces, n_vertices);
  for (Index g = 0; g < groups.n_groups(); ++g) {
    if (groups.size(g) == 1) mask[groups.lo[g]] = mask[groups.hi[g]] = 1;
  }
  return mask;
}

double mean_side_length(const std::vector<Triangle>& faces, const Positions& positions) {
  if (faces.empty()) return 0.0;
  double mean = 0.0;  // divided as it goes: huge lengths cannot overflow the sum
  const double inv_n = 1.0 / (3.0 * static_cast<double>(faces.size()));
  for (const Triangle& t : faces) {
    for (int i = 0; i < 3; ++i) {
      mean += side_length(positions.row(t[i]).data(), positions.row(t[(i + 1) % 3]).data()) * inv_n;
    }
  }
  return mean;
}

double robust_side_length(const std::vector<Triangle>& faces, const Positions& positions) {
  std::vector<double> sides;
  sides.reserve(3 * faces.size());
  for (const Triangle& t : faces) {
    for (int i = 0; i < 3; ++i) {
      sides.push_back(
          side_length(positions.row(t[i]).data(), positions.row(t[(i + 1) % 3]).data()));
    }
  }
  return robust_mean_length(std::move(sides));
}

}  // namespace ifem::intrinsic
