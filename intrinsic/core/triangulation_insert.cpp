// Vertex insertion primitives of IntrinsicTriangulation: a vertex inside a face, a vertex on an
// edge. Both are O(1) rewrites that append faces, edges and vertices ("insertions append"), so
// existing vertex ids never change; the slot layout is documented in triangulation.h.
#include <string>

#include "intrinsic/core/triangulation.h"

namespace ifem::intrinsic {

Index IntrinsicTriangulation::insert_vertex_in_face(Index f, double l0, double l1, double l2) {
  if (f < 0 || f >= n_faces()) {
    throw InvalidInput("insert_vertex_in_face: face " + std::to_string(f) + " out of range");
  }
  const Index v = n_vertices_++;
  vertex_halfedge_.push_back(kInvalidIndex);
  const Index f1 = n_faces(), f2 = f1 + 1;
  const Index a = 3 * f, b = a + 1, c = a + 2;
  const Index c0 = tail_[a], c1 = tail_[b], c2 = tail_[c];
  const Index from[2] = {b, c};
  const Index to[2] = {3 * f1, 3 * f2};
  const SlotMove mv = record_slot_move(2, from, to);

  const std::size_t nh = 3 * static_cast<std::size_t>(f2 + 1);
  tail_.resize(nh);
  twin_.resize(nh);
  edge_.resize(nh);
  const Index e0 = n_edges(), e1 = e0 + 1, e2 = e0 + 2;
  length_.insert(length_.end(), {l0, l1, l2});
  edge_halfedge_.insert(edge_halfedge_.end(), {c, 3 * f1 + 2, 3 * f2 + 2});

  finish_slot_move(mv);
  for (const Index x : {c0, c1, c2}) vertex_halfedge_[x] = mv.moved(vertex_halfedge_[x]);
  vertex_halfedge_[v] = c;

  tail_[b] = c1;  // a = c0→c1 unchanged
  tail_[c] = v;
  tail_[3 * f1] = c1;
  tail_[3 * f1 + 1] = c2;
  tail_[3 * f1 + 2] = v;
  tail_[3 * f2] = c2;
  tail_[3 * f2 + 1] = c0;
  tail_[3 * f2 + 2] = v;
  auto glue = [&](Index x, Index y, Index e) {
    twin_[x] = y;
    twin_[y] = x;
    edge_[x] = e;
    edge_[y] = e;
  };
  glue(b, 3 * f1 + 2, e1);
  glue(3 * f1 + 1, 3 * f2 + 2, e2);
  glue(3 * f2 + 1, c, e0);
  return v;
}

Index IntrinsicTriangulation::split_edge(Index e, double t, double l_mc, double l_md) {
  if (e < 0 || e >= n_edges()) {
    throw InvalidInput("split_edge: edge " + std::to_string(e) + " out of range");
  }
  const Index h = edge_halfedge_[e];
  const Index tw = twin_[h];
  if (tw != kInvalidIndex && face(tw) == face(h)) {
    throw InvalidInput("split_edge: edge " + std::to_string(e) +
                       " has both sides in one face (not supported)");
  }
  const bool interior = tw != kInvalidIndex;
  const Index h1 = next(h), h2 = prev(h);
  const Index a = tail_[h], b = tail_[h1], c = tail_[h2];
  const Index t1 = interior ? next(tw) : kInvalidIndex;
  const Index t2 = interior ? prev(tw) : kInvalidIndex;
  const Index d = interior ? tail_[t2] : kInvalidIndex;
  const double L = length_[e];
  const Index m = n_vertices_++;
  vertex_halfedge_.push_back(kInvalidIndex);
  const Index g1 = n_faces(), g2 = g1 + 1;

  const int nm = interior ? 2 : 1;
  const Index from[2] = {h1, t1};
  const Index to[2] = {3 * g1 + 1, 3 * g2 + 1};
  const SlotMove mv = record_slot_move(nm, from, to);

  const std::size_t nh = 3 * static_cast<std::size_t>(interior ? g2 + 1 : g1 + 1);
  tail_.resize(nh);
  twin_.resize(nh);
  edge_.resize(nh);
  const Index e_mb = n_edges(), e_mc = e_mb + 1, e_md = e_mb + 2;
  length_[e] = t * L;
  length_.push_back((1.0 - t) * L);
  length_.push_back(l_mc);
  edge_halfedge_.push_back(3 * g1);
  edge_halfedge_.push_back(h1);
  if (interior) {
    length_.push_back(l_md);
    edge_halfedge_.push_back(t1);
  }

  finish_slot_move(mv);
  for (const Index x : {a, b, c, d}) {
    if (x != kInvalidIndex) vertex_halfedge_[x] = mv.moved(vertex_halfedge_[x]);
  }

  auto glue = [&](Index x, Index y, Index edge_id) {
    twin_[x] = y;
    edge_[x] = edge_id;
    if (y != kInvalidIndex) {
      twin_[y] = x;
      edge_[y] = edge_id;
    }
  };
  tail_[h1] = m;
  tail_[3 * g1] = m;
  tail_[3 * g1 + 1] = b;
  tail_[3 * g1 + 2] = c;
  glue(h1, 3 * g1 + 2, e_mc);
  if (interior) {
    tail_[t1] = m;
    tail_[3 * g2] = m;
    tail_[3 * g2 + 1] = a;
    tail_[3 * g2 + 2] = d;
    glue(h, 3 * g2, e);
    glue(tw, 3 * g1, e_mb);
    glue(t1, 3 * g2 + 2, e_md);
    vertex_halfedge_[m] = h1;
  } else {
    glue(3 * g1, kInvalidIndex, e_mb);
    vertex_halfedge_[m] = 3 * g1;
  }
  return m;
}

}  // namespace ifem::intrinsic
