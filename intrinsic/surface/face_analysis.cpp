#include "intrinsic/surface/face_analysis.h"

#include <algorithm>
#include <array>
#include <numeric>

namespace ifem::intrinsic {
namespace {

struct UnionFind {
  std::vector<Index> parent;
  explicit UnionFind(Index n) : parent(n) { std::iota(parent.begin(), parent.end(), 0); }
  Index find(Index x) {
    while (parent[x] != x) x = parent[x] = parent[parent[x]];
    return x;
  }
  void unite(Index a, Index b) { parent[find(a)] = find(b); }
};

}  // namespace

FaceListStats analyze_faces(const std::vector<Triangle>& faces, Index n_vertices) {
  FaceListStats st;
  st.vertices = n_vertices;
  st.faces = static_cast<Index>(faces.size());
  // one record per face side: (lo, hi, corner id of lo, corner id of hi, forward?)
  struct Side {
    Index lo, hi, face, side;
  };
  std::vector<Side> sides;
  sides.reserve(3 * faces.size());
  std::vector<std::array<Index, 3>> sorted_faces;
  std::vector<char> referenced(n_vertices, 0);
  UnionFind vertex_uf(n_vertices);
  for (Index f = 0; f < st.faces; ++f) {
    const Triangle& t = faces[f];
    if (t[0] == t[1] || t[1] == t[2] || t[2] == t[0]) {
      ++st.degenerate_faces;
      continue;
    }
    std::array<Index, 3> s = t;
    std::sort(s.begin(), s.end());
    sorted_faces.push_back(s);
    for (Index k = 0; k < 3; ++k) {
      referenced[t[k]] = 1;
      const Index a = t[k], b = t[(k + 1) % 3];
      sides.push_back({std::min(a, b), std::max(a, b), f, k});
      vertex_uf.unite(a, b);
    }
  }
  std::sort(sorted_faces.begin(), sorted_faces.end());
  for (std::size_t i = 1; i < sorted_faces.size(); ++i) {
    st.duplicate_faces += sorted_faces[i] == sorted_faces[i - 1];
  }
  std::sort(sides.begin(), sides.end(), [](const Side& x, const Side& y) {
    return x.lo != y.lo ? x.lo < y.lo : x.hi != y.hi ? x.hi < y.hi : x.face < y.face;
  });
  // corners (3F) joined across 2-face edges: the fans around each vertex
  UnionFind corner_uf(3 * st.faces);
  UnionFind boundary_uf(n_vertices);
  std::vector<char> on_boundary(n_vertices, 0);
  for (std::size_t i = 0; i < sides.size();) {
    std::size_t j = i + 1;
    while (j < sides.size() && sides[j].lo == sides[i].lo && sides[j].hi == sides[i].hi) ++j;
    const std::size_t n = j - i;
    ++st.edges;
    if (n == 1) {
      ++st.boundary_edges;
      boundary_uf.unite(sides[i].lo, sides[i].hi);
      on_boundary[sides[i].lo] = on_boundary[sides[i].hi] = 1;
    } else if (n == 2) {
      const Side& x = sides[i];
      const Side& y = sides[i + 1];
      const Index xa = faces[x.face][x.side], ya = faces[y.face][y.side];
      if (xa == ya) ++st.inconsistent_edges;
      // the corner of x.face at vertex v and the corner of y.face at v lie in one fan
      for (const Index v : {x.lo, x.hi}) {
        auto corner = [&](const Side& s) {
          const Triangle& t = faces[s.face];
          const Index k = t[0] == v ? 0 : t[1] == v ? 1 : 2;
          return 3 * s.face + k;
        };
        corner_uf.unite(corner(x), corner(y));
      }
    } else {
      if (st.nonmanifold_edges == 0) {
        st.first_nonmanifold_edge[0] = sides[i].lo;
        st.first_nonmanifold_edge[1] = sides[i].hi;
      }
      ++st.nonmanifold_edges;
    }
    i = j;
  }
  // count fans per vertex
  std::vector<Index> first_root(n_vertices, kInvalidIndex);
  std::vector<char> nonmanifold(n_vertices, 0);
  for (Index f = 0; f < st.faces; ++f) {
    const Triangle& t = faces[f];
    if (t[0] == t[1] || t[1] == t[2] || t[2] == t[0]) continue;
    for (Index k = 0; k < 3; ++k) {
      const Index r = corner_uf.find(3 * f + k);
      Index& fr = first_root[t[k]];
      if (fr == kInvalidIndex)
        fr = r;
      else if (fr != r)
        nonmanifold[t[k]] = 1;
    }
  }
  for (Index v = 0; v < n_vertices; ++v) {
    st.nonmanifold_vertices += nonmanifold[v];
    st.unreferenced_vertices += !referenced[v];
    if (referenced[v] && vertex_uf.find(v) == v) ++st.components;
    if (on_boundary[v] && boundary_uf.find(v) == v) ++st.boundary_loops;
  }
  return st;
}

double mean_side_length(const std::vector<Triangle>& faces, const Positions& positions) {
  double sum = 0.0;
  std::size_t n = 0;
  for (const Triangle& t : faces) {
    for (int i = 0; i < 3; ++i) {
      sum += (positions.row(t[i]) - positions.row(t[(i + 1) % 3])).norm();
      ++n;
    }
  }
  return n ? sum / static_cast<double>(n) : 0.0;
}

}  // namespace ifem::intrinsic
