#include "intrinsic/core/triangulation.h"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>
#include <sstream>
#include <string>
#include <utility>

#include "intrinsic/core/side_pairs.h"
#include "intrinsic/core/triangle_formulas.h"
#include "intrinsic/core/types.h"

namespace ifem {

Index checked_index(std::size_t n, const char* what) {
  if (n > static_cast<std::size_t>(std::numeric_limits<Index>::max())) {
    throw InvalidInput(std::string(what) + ": " + std::to_string(n) +
                       " elements do not fit 32-bit ids");
  }
  return static_cast<Index>(n);
}

}  // namespace ifem

namespace ifem::intrinsic {
namespace {

using T = IntrinsicTriangulation;

std::string edge_name(Index a, Index b) {
  std::ostringstream s;
  s << "(" << std::min(a, b) << "," << std::max(a, b) << ")";
  return s.str();
}

// Pairs up the sides of the triangles `tail` (3 per face) that join the same two vertices.
// Output: partner[h] = the other side of h's edge or kInvalidIndex, same_dir[h] = 1 if the
// partner runs in the same direction as h.
// @throws NonManifoldInput on the first (by vertex pair) edge with 3+ sides
void pair_sides(const std::vector<Index>& tail, Index n_vertices, std::vector<Index>& partner,
                std::vector<char>& same_dir) {
  const Index nh = static_cast<Index>(tail.size());
  const SideGroups groups = group_sides(tail, n_vertices);
  partner.assign(nh, kInvalidIndex);
  same_dir.assign(nh, 0);
  for (Index g = 0; g < groups.n_groups(); ++g) {
    const Index n = groups.size(g);
    const Index* x = groups.begin(g);
    if (n > 2) {
      std::ostringstream s;
      s << "edge " << edge_name(groups.lo[g], groups.hi[g]) << " has " << n
        << " incident faces (faces";
      for (Index k = 0; k < n && k < 6; ++k) s << " " << T::face(x[k]);
      s << (n > 6 ? " ..." : "") << "); use the tufted cover for nonmanifold input";
      throw NonManifoldInput(s.str());
    }
    if (n == 2) {
      const Index h0 = x[0], h1 = x[1];
      partner[h0] = h1;
      partner[h1] = h0;
      const char same = tail[h0] == tail[h1];
      same_dir[h0] = same;
      same_dir[h1] = same;
    }
  }
}

// Finds a face orientation that makes every glued pair run in opposite directions.
// Returns flip[f] (1 = reverse face f); the first face of each component keeps its order.
// Throws NonManifoldInput if no such orientation exists (non-orientable surface).
std::vector<char> orient_faces(const std::vector<Index>& tail, const std::vector<Index>& partner,
                               const std::vector<char>& same_dir) {
  const Index nf = static_cast<Index>(tail.size() / 3);
  std::vector<char> flip(nf, 0), seen(nf, 0);
  std::vector<Index> stack;
  for (Index root = 0; root < nf; ++root) {
    if (seen[root]) continue;
    seen[root] = 1;
    stack.push_back(root);
    while (!stack.empty()) {
      const Index f = stack.back();
      stack.pop_back();
      for (Index s = 0; s < 3; ++s) {
        const Index h = 3 * f + s;
        const Index p = partner[h];
        if (p == kInvalidIndex) continue;
        const Index g = T::face(p);
        // same direction → the two faces need opposite flips; opposite → equal flips
        const char want = static_cast<char>(flip[f] ^ same_dir[h]);
        if (!seen[g]) {
          seen[g] = 1;
          flip[g] = want;
          stack.push_back(g);
        } else if (flip[g] != want) {
          throw NonOrientableInput(
              "the gluing is non-orientable (a Moebius-like loop closes at edge " +
              edge_name(tail[h], tail[T::next(h)]) + ", faces " + std::to_string(f) + " and " +
              std::to_string(g) + "); use the tufted cover for non-orientable input");
        }
      }
    }
  }
  return flip;
}

// The diamond of triangles (a, b, c) and (b, a, d) sharing side ab, laid out in the plane with
// a = (0,0), b = (l_ab, 0), c above and d below. Returns |c − d|, the length of the flipped
// diagonal, or NaN when the diamond is not strictly convex (the flip would not be a
// triangulation of the same surface).
double flipped_length(double l_ab, double l_bc, double l_ca, double l_ad, double l_db) {
  // on lengths scaled by a power of two (exact): the same flips at every scale, no overflow
  const double s = length_normalizer(std::max({l_ab, l_bc, l_ca, l_ad, l_db}));
  if (s != 1.0) l_ab /= s, l_bc /= s, l_ca /= s, l_ad /= s, l_db /= s;
  const Eigen::Vector2d c = triangle_apex(l_ab, l_bc, l_ca);
  const Eigen::Vector2d d_above = triangle_apex(l_ab, l_db, l_ad);  // d mirrored below ab
  const double cx = c.x(), cy = c.y(), dx = d_above.x(), dy = -d_above.y();
  // where segment cd crosses the line of ab: strictly between a and b iff convex
  const double x = cx + (dx - cx) * cy / (cy - dy);
  if (!(x > 0.0 && x < l_ab)) return std::numeric_limits<double>::quiet_NaN();
  const double l_cd = std::hypot(cx - dx, cy - dy);
  // a diamond flat at a or b (a vertex inserted on a side, such as a Bézier midpoint, has a
  // corner of π up to round-off) can pass the test above and give a new face whose lengths are
  // exactly flat (a + b ≤ c in floating point: area 0): refuse. Judged on the lengths, since
  // the layout's apex heights carry √ε errors there; only exact flatness, so that FlipOut's
  // results elsewhere are unchanged (FlipGeodesicReference)
  if (l_ca + l_ad - l_cd <= 0.0 || l_db + l_bc - l_cd <= 0.0) {
    return std::numeric_limits<double>::quiet_NaN();
  }
  return l_cd * s;
}

}  // namespace

void face_layout(const IntrinsicTriangulation& tri, Index f, Eigen::Vector2d p[3]) {
  const double l0 = tri.halfedge_length(3 * f), l1 = tri.halfedge_length(3 * f + 1),
               l2 = tri.halfedge_length(3 * f + 2);
  p[0] = Eigen::Vector2d::Zero();
  p[1] = Eigen::Vector2d(l0, 0.0);
  p[2] = triangle_apex(l0, l1, l2);
}

// ---------------------------------------------------------------------------------------------
// Construction

IntrinsicTriangulation IntrinsicTriangulation::from_positions(const std::vector<Triangle>& faces,
                                                              const Positions& positions,
                                                              BuildReport* report) {
  const Index nv = checked_index(static_cast<std::size_t>(positions.rows()), "from_positions");
  for (Index v = 0; v < nv; ++v) {
    if (!positions.row(v).allFinite()) {
      throw InvalidInput("from_positions: vertex " + std::to_string(v) +
                         " has a non-finite coordinate");
    }
  }
  const Index nf = checked_index(faces.size(), "from_positions");
  Eigen::MatrixX3d side(nf, 3);
  for (Index f = 0; f < nf; ++f) {
    for (int s = 0; s < 3; ++s) {
      const Index a = faces[f][s], b = faces[f][(s + 1) % 3];
      if (a < 0 || a >= nv || b < 0 || b >= nv) {
        throw InvalidInput("from_positions: face " + std::to_string(f) + " has vertex index " +
                           std::to_string(a < 0 || a >= nv ? a : b) + " out of range [0, " +
                           std::to_string(nv) + ")");
      }
      side(f, s) = side_length(positions.row(a).data(), positions.row(b).data());
    }
  }
  return from_side_lengths(faces, nv, side, report);
}

IntrinsicTriangulation IntrinsicTriangulation::from_side_lengths(
    const std::vector<Triangle>& faces, Index n_vertices, const Eigen::MatrixX3d& side_lengths,
    BuildReport* report) {
  const Index nf_in = checked_index(faces.size(), "from_side_lengths");
  if (n_vertices < 0) throw InvalidInput("from_side_lengths: negative vertex count");
  if (side_lengths.rows() != nf_in) {
    throw InvalidInput("from_side_lengths: " + std::to_string(side_lengths.rows()) +
                       " rows of side lengths for " + std::to_string(nf_in) + " faces");
  }
  BuildReport rep;
  rep.input_faces = nf_in;
  std::vector<Index> tail(3 * faces.size());
  std::vector<double> hlen(3 * faces.size());
  rep.face_origin.resize(faces.size());
  Index kept = 0;
  for (Index f = 0; f < nf_in; ++f) {
    const Triangle& t = faces[f];
    for (int s = 0; s < 3; ++s) {
      if (t[s] < 0 || t[s] >= n_vertices) {
        throw InvalidInput("from_side_lengths: face " + std::to_string(f) + " has vertex index " +
                           std::to_string(t[s]) + " out of range [0, " +
                           std::to_string(n_vertices) + ")");
      }
      const double l = side_lengths(f, s);
      if (!std::isfinite(l) || l < 0.0) {
        throw InvalidInput("from_side_lengths: face " + std::to_string(f) + " side " +
                           std::to_string(s) + " has invalid length " + std::to_string(l));
      }
    }
    if (repeats_vertex(t)) {
      ++rep.dropped_faces;
      continue;
    }
    rep.face_origin[kept] = f;
    for (int s = 0; s < 3; ++s) {
      tail[3 * kept + s] = t[s];
      hlen[3 * kept + s] = side_lengths(f, s);
    }
    ++kept;
  }
  tail.resize(3 * static_cast<std::size_t>(kept));
  hlen.resize(3 * static_cast<std::size_t>(kept));
  rep.face_origin.resize(kept);

  std::vector<Index> partner;
  std::vector<char> same_dir;
  pair_sides(tail, n_vertices, partner, same_dir);
  if (std::find(same_dir.begin(), same_dir.end(), 1) != same_dir.end()) {
    const std::vector<char> flip = orient_faces(tail, partner, same_dir);
    const Index nf = static_cast<Index>(flip.size());
    for (Index f = 0; f < nf; ++f) {
      if (!flip[f]) continue;
      ++rep.reoriented_faces;
      // (v0, v1, v2) → (v0, v2, v1): sides (l0, l1, l2) → (l2, l1, l0)
      std::swap(tail[3 * f + 1], tail[3 * f + 2]);
      std::swap(hlen[3 * f], hlen[3 * f + 2]);
    }
    pair_sides(tail, n_vertices, partner, same_dir);
  }

  IntrinsicTriangulation tri;
  tri.n_vertices_ = n_vertices;
  tri.tail_ = std::move(tail);
  tri.twin_ = std::move(partner);
  tri.build_edges_and_vertices(hlen, /*check_agree=*/true);
  rep.unreferenced_vertices = static_cast<Index>(
      std::count(tri.vertex_halfedge_.begin(), tri.vertex_halfedge_.end(), kInvalidIndex));
  if (report) *report = std::move(rep);
  return tri;
}

IntrinsicTriangulation IntrinsicTriangulation::from_gluing(
    std::vector<Index> tail, std::vector<Index> twin, const std::vector<double>& halfedge_length,
    Index n_vertices, int multiplicity) {
  const std::size_t nh = tail.size();
  if (nh % 3 != 0 || twin.size() != nh || halfedge_length.size() != nh) {
    throw InvalidInput("from_gluing: arrays must all have 3·F entries");
  }
  if (multiplicity < 1) throw InvalidInput("from_gluing: multiplicity must be ≥ 1");
  checked_index(nh, "from_gluing");
  for (std::size_t h = 0; h < nh; ++h) {
    if (tail[h] < 0 || tail[h] >= n_vertices) {
      throw InvalidInput("from_gluing: halfedge " + std::to_string(h) + " has vertex " +
                         std::to_string(tail[h]) + " out of range");
    }
    const Index t = twin[h];
    if (t == kInvalidIndex) continue;
    if (t < 0 || static_cast<std::size_t>(t) >= nh || t == static_cast<Index>(h) ||
        twin[t] != static_cast<Index>(h)) {
      throw InvalidInput("from_gluing: twin is not an involution at halfedge " + std::to_string(h));
    }
  }
  IntrinsicTriangulation tri;
  tri.n_vertices_ = n_vertices;
  tri.multiplicity_ = multiplicity;
  tri.tail_ = std::move(tail);
  tri.twin_ = std::move(twin);
  for (Index h = 0; h < tri.n_halfedges(); ++h) {
    const Index t = tri.twin_[h];
    if (t != kInvalidIndex && tri.tail_[h] != tri.head(t)) {
      throw InvalidInput("from_gluing: glued halfedges " + std::to_string(h) + " and " +
                         std::to_string(t) + " do not run in opposite directions");
    }
  }
  tri.build_edges_and_vertices(halfedge_length, /*check_agree=*/true);
  return tri;
}

void IntrinsicTriangulation::renumber_edges(const std::vector<Index>& eh) {
  if (eh.size() != edge_halfedge_.size()) {
    throw InvalidInput("renumber_edges: " + std::to_string(eh.size()) + " halfedges for " +
                       std::to_string(n_edges()) + " edges");
  }
  std::vector<Index> edge(tail_.size(), kInvalidIndex);
  std::vector<double> len(eh.size());
  for (std::size_t e = 0; e < eh.size(); ++e) {
    const Index h = eh[e];
    if (h < 0 || h >= n_halfedges()) {
      throw InvalidInput("renumber_edges: halfedge " + std::to_string(h) + " out of range");
    }
    for (const Index x : {h, twin_[h]}) {
      if (x == kInvalidIndex) continue;
      if (edge[x] != kInvalidIndex) {
        throw InvalidInput("renumber_edges: halfedge " + std::to_string(x) +
                           " belongs to two listed edges");
      }
      edge[x] = static_cast<Index>(e);
    }
    len[e] = length_[edge_[h]];
  }
  // every halfedge is covered: E edges cover at most as many halfedges as exist, each once
  edge_ = std::move(edge);
  edge_halfedge_ = eh;
  length_ = std::move(len);
}

void IntrinsicTriangulation::build_edges_and_vertices(const std::vector<double>& hlen,
                                                      bool check_agree) {
  const Index nh = n_halfedges();
  edge_.assign(nh, kInvalidIndex);
  edge_halfedge_.clear();
  length_.clear();
  edge_halfedge_.reserve(nh / 2 + 1);
  length_.reserve(nh / 2 + 1);
  for (Index h = 0; h < nh; ++h) {
    if (edge_[h] != kInvalidIndex) continue;
    const Index e = static_cast<Index>(length_.size());
    const Index t = twin_[h];
    edge_[h] = e;
    edge_halfedge_.push_back(h);
    double l = hlen[h];
    if (!std::isfinite(l) || l < 0.0 || (t != kInvalidIndex && !std::isfinite(hlen[t]))) {
      throw InvalidInput("edge " + edge_name(tail_[h], head(h)) + ": length is not finite and ≥ 0");
    }
    if (t != kInvalidIndex) {
      edge_[t] = e;
      if (check_agree && std::abs(hlen[t] - l) > 1e-12 * std::max(l, hlen[t])) {
        throw InvalidInput("edge " + edge_name(tail_[h], head(h)) + ": glued sides have lengths " +
                           std::to_string(l) + " and " + std::to_string(hlen[t]));
      }
      l = 0.5 * (l + hlen[t]);
    }
    length_.push_back(l);
  }
  vertex_halfedge_.assign(n_vertices_, kInvalidIndex);
  for (Index h = 0; h < nh; ++h) {
    Index& vh = vertex_halfedge_[tail_[h]];
    // prefer an outgoing boundary halfedge so that fan walks start at the boundary
    if (vh == kInvalidIndex || (twin_[h] == kInvalidIndex && twin_[vh] != kInvalidIndex)) vh = h;
  }
}

bool IntrinsicTriangulation::has_boundary() const {
  return std::find(twin_.begin(), twin_.end(), kInvalidIndex) != twin_.end();
}

// ---------------------------------------------------------------------------------------------
// Flips

bool IntrinsicTriangulation::is_delaunay(Index e) const {
  const Index h = edge_halfedge_[e];
  const Index t = twin_[h];
  if (t == kInvalidIndex) return true;
  // α + β > π  ⇔  sin(α + β) < 0, and sin(α+β)·(b1 c1 b2 c2) = A1·q2 + A2·q1 with
  // q = b² + c² − a² (law of cosines) and A the areas. Flip only past a small tolerance.
  // on the diamond's lengths normalized by a power of two (exact): the same decision at every
  // scale, and the fourth powers below never over- or underflow
  double a = length_[e];
  double b1 = halfedge_length(next(h)), c1 = halfedge_length(prev(h));
  double b2 = halfedge_length(next(t)), c2 = halfedge_length(prev(t));
  const double scale = length_normalizer(std::max({a, b1, c1, b2, c2}));
  if (scale != 1.0) a /= scale, b1 /= scale, c1 /= scale, b2 /= scale, c2 /= scale;
  const double q1 = b1 * b1 + c1 * c1 - a * a;
  const double q2 = b2 * b2 + c2 * c2 - a * a;
  // both angles opposite e at most π/2 (most edges): s ≥ 0 below, without its square roots
  if (q1 >= 0.0 && q2 >= 0.0) return true;
  const double s = triangle_area(a, b1, c1) * q2 + triangle_area(a, b2, c2) * q1;
  const bool bad = s < -1e-13 * (b1 * c1) * (b2 * c2);  // NaN compares false: Delaunay
  return !bad;
}

void IntrinsicTriangulation::save_diamond(Index e, FlipUndo* u) const {
  const Index h = edge_halfedge_[e], t = twin_[h];
  const Index sides[4] = {next(h), prev(h), next(t), prev(t)};
  u->edge = e;
  u->length = length_[e];
  int n = 0;
  auto keep = [&](Index x) {
    u->halfedge[n] = x, u->tail[n] = tail_[x], u->twin[n] = twin_[x], u->edge_of[n] = edge_[x];
    ++n;
  };
  keep(h), keep(t);
  for (int k = 0; k < 4; ++k) {
    keep(sides[k]);
    const Index o = twin_[sides[k]];
    if (o != kInvalidIndex) keep(o);
    u->side_edge[k] = edge_[sides[k]];
    u->side_edge_halfedge[k] = edge_halfedge_[edge_[sides[k]]];
  }
  u->n_halfedges = n;
  const Index verts[4] = {tail_[h], tail_[t], tail_[prev(h)], tail_[prev(t)]};
  for (int k = 0; k < 4; ++k)
    u->vertex[k] = verts[k], u->vertex_halfedge[k] = vertex_halfedge_[verts[k]];
}

void IntrinsicTriangulation::undo_flip(const FlipUndo& u) {
  // every saved entry holds its value from before the flip: the order of writing is free
  for (int k = 0; k < u.n_halfedges; ++k) {
    const Index x = u.halfedge[k];
    tail_[x] = u.tail[k], twin_[x] = u.twin[k], edge_[x] = u.edge_of[k];
  }
  for (int k = 0; k < 4; ++k) {
    edge_halfedge_[u.side_edge[k]] = u.side_edge_halfedge[k];
    vertex_halfedge_[u.vertex[k]] = u.vertex_halfedge[k];
  }
  length_[u.edge] = u.length;
}

IntrinsicTriangulation::SlotMove IntrinsicTriangulation::record_slot_move(int n, const Index* from,
                                                                          const Index* to) const {
  SlotMove m;
  m.n = n;
  for (int k = 0; k < n; ++k) {
    m.old_slot[k] = from[k];
    m.new_slot[k] = to[k];
    m.old_twin[k] = twin_[from[k]];
    m.old_edge[k] = edge_[from[k]];
  }
  return m;
}

void IntrinsicTriangulation::finish_slot_move(const SlotMove& m) {
  for (int k = 0; k < m.n; ++k) {
    const Index s = m.new_slot[k];
    edge_[s] = m.old_edge[k];
    const Index ot = m.old_twin[k];
    const Index nt = ot == kInvalidIndex ? kInvalidIndex : m.moved(ot);
    twin_[s] = nt;
    if (nt != kInvalidIndex && ot == nt) twin_[ot] = s;  // outside partner points back
    if (edge_halfedge_[m.old_edge[k]] == m.old_slot[k]) edge_halfedge_[m.old_edge[k]] = s;
  }
}

bool IntrinsicTriangulation::flip_edge(Index e) { return flip_edge(e, nullptr); }

bool IntrinsicTriangulation::flip_edge(Index e, FlipUndo* undo) {
  const Index h = edge_halfedge_[e];
  const Index t = twin_[h];
  if (t == kInvalidIndex || face(h) == face(t)) return false;
  const Index h1 = next(h), h2 = prev(h), t1 = next(t), t2 = prev(t);

  const Index a = tail_[h], b = tail_[t], c = tail_[h2], d = tail_[t2];
  const double l_new = flipped_length(length_[e], length_[edge_[h1]], length_[edge_[h2]],
                                      length_[edge_[t1]], length_[edge_[t2]]);
  if (!std::isfinite(l_new) || l_new <= 0.0) return false;
  if (undo != nullptr) save_diamond(e, undo);

  // Old faces (a,b,c) = (h,h1,h2) and (b,a,d) = (t,t1,t2). New faces keep the slots:
  // face(h) = (d,c,a) with h: d→c, h1: c→a (was h2), h2: a→d (was t1);
  // face(t) = (c,d,b) with t: c→d, t1: d→b (was t2), t2: b→c (was h1).
  // record_slot_move() and finish_slot_move() written out for this one pattern (every FlipOut
  // and Delaunay flip passes here; the same writes): 745 → 606 instructions per flip (callgrind,
  // FlipOut on icosphere(71), docs/decisions.md D-147)
  const Index from[4] = {h2, t1, t2, h1};
  const Index to[4] = {h1, h2, t1, t2};
  const auto moved = [&](Index x) {
    return x == h2 ? h1 : x == t1 ? h2 : x == t2 ? t1 : x == h1 ? t2 : x;
  };
  Index old_twin[4], old_edge[4];
  for (int k = 0; k < 4; ++k) old_twin[k] = twin_[from[k]], old_edge[k] = edge_[from[k]];
  // vertex_halfedge entries that pointed into the diamond move with their sides (a Δ-complex
  // may repeat vertices among a, b, c, d: visit each once)
  const Index verts[4] = {a, b, c, d};
  for (int k = 0; k < 4; ++k) {
    if (std::find(verts, verts + k, verts[k]) != verts + k) continue;  // seen already
    Index& vh = vertex_halfedge_[verts[k]];
    if (vh == h)
      vh = h2;  // a: a→d now sits in slot h2
    else if (vh == t)
      vh = t2;  // b: b→c now sits in slot t2
    else
      vh = moved(vh);
  }
  for (int k = 0; k < 4; ++k) {
    const Index s = to[k], ot = old_twin[k];
    edge_[s] = old_edge[k];
    const Index nt = ot == kInvalidIndex ? kInvalidIndex : moved(ot);
    twin_[s] = nt;
    if (nt != kInvalidIndex && ot == nt) twin_[ot] = s;  // outside partner points back
    if (edge_halfedge_[old_edge[k]] == from[k]) edge_halfedge_[old_edge[k]] = s;
  }
  tail_[h] = d;
  tail_[h1] = c;
  tail_[h2] = a;
  tail_[t] = c;
  tail_[t1] = d;
  tail_[t2] = b;
  length_[e] = l_new;
  return true;
}

FlipReport IntrinsicTriangulation::flip_to_delaunay() {
  return flip_to_delaunay([this](Index e) { return flip_edge(e); });
}

FlipReport IntrinsicTriangulation::flip_to_delaunay_from(std::vector<Index> queue,
                                                         std::vector<Index>* touched) {
  return flip_to_delaunay_from(std::move(queue), touched, [this](Index e) { return flip_edge(e); });
}

FlipReport IntrinsicTriangulation::flip_to_delaunay_from(std::vector<Index> stack,
                                                         std::vector<Index>* touched,
                                                         const std::function<bool(Index)>& flip) {
  return flip_stack(stack, nullptr, nullptr, touched, flip);
}

FlipReport IntrinsicTriangulation::flip_to_delaunay(const std::function<bool(Index)>& flip) {
  const Index ne = n_edges();
  std::vector<char> queued(ne, 1);
  std::vector<Index> stack(ne);
  for (Index e = 0; e < ne; ++e) stack[e] = ne - 1 - e;  // pop in increasing order
  // every edge's first test on the OpenMP team (the same flips follow: a test is redone once a
  // flip has changed the edge's diamond)
  std::vector<char> known(ne);
#pragma omp parallel for schedule(static) if (ne >= kParallelMin)
  for (Index e = 0; e < ne; ++e) known[e] = is_delaunay(e) ? 1 : 2;
  return flip_stack(stack, &queued, &known, nullptr, flip);
}

FlipReport IntrinsicTriangulation::flip_stack(std::vector<Index>& stack, std::vector<char>* queued,
                                              std::vector<char>* known, std::vector<Index>* touched,
                                              const std::function<bool(Index)>& flip) {
  FlipReport rep;
  const std::size_t cap = 50 * static_cast<std::size_t>(n_edges()) + 1000;
  while (!stack.empty()) {
    const Index e = stack.back();
    stack.pop_back();
    if (queued) (*queued)[e] = 0;
    if (known && (*known)[e] ? (*known)[e] == 1 : is_delaunay(e)) continue;
    if (rep.flips >= cap) {
      rep.hit_flip_cap = true;
      break;
    }
    if (!flip(e)) {
      ++rep.unflippable;
      continue;
    }
    ++rep.flips;
    const Index h = edge_halfedge_[e];
    const Index t = twin_[h];
    if (known) (*known)[e] = 0;
    if (touched) {
      touched->push_back(face(h));
      touched->push_back(face(t));
    }
    for (const Index x : {next(h), prev(h), next(t), prev(t)}) {
      const Index ex = edge_[x];
      if (known) (*known)[ex] = 0;  // its diamond has a new face
      if (queued) {
        if ((*queued)[ex]) continue;
        (*queued)[ex] = 1;
      }
      stack.push_back(ex);
    }
  }
  return rep;
}

// ---------------------------------------------------------------------------------------------
// Insertion at a point given in a face's layout (the O(1) rewrites are in triangulation_insert.cpp)

Index IntrinsicTriangulation::insert_vertex_in_face(Index f, const Eigen::Vector3d& bary) {
  if (f < 0 || f >= n_faces()) {
    throw InvalidInput("insert_vertex_in_face: face " + std::to_string(f) + " out of range");
  }
  Eigen::Vector2d p[3];
  face_layout(*this, f, p);
  const Eigen::Vector2d x = bary[0] * p[0] + bary[1] * p[1] + bary[2] * p[2];
  return insert_vertex_in_face(f, (x - p[0]).norm(), (x - p[1]).norm(), (x - p[2]).norm());
}

Index IntrinsicTriangulation::split_edge(Index e, double t) {
  if (e < 0 || e >= n_edges()) {
    throw InvalidInput("split_edge: edge " + std::to_string(e) + " out of range");
  }
  // the new vertex at fraction t along side s of a face's layout, to the opposite corner
  auto diagonal = [this](Index h, double u) {
    Eigen::Vector2d p[3];
    face_layout(*this, face(h), p);
    const int s = side(h);
    return (p[s] + u * (p[(s + 1) % 3] - p[s]) - p[(s + 2) % 3]).norm();
  };
  const Index h = edge_halfedge_[e];
  const Index tw = twin_[h];
  const double l_mc = diagonal(h, t);
  const double l_md = tw != kInvalidIndex ? diagonal(tw, 1.0 - t) : 0.0;
  return split_edge(e, t, l_mc, l_md);
}

// ---------------------------------------------------------------------------------------------
// Mollification

MollifyReport IntrinsicTriangulation::mollify(double relative_epsilon) {
  MollifyReport rep;
  if (!(relative_epsilon >= 0.0) || !std::isfinite(relative_epsilon)) {
    throw InvalidInput("mollify: relative epsilon must be finite and ≥ 0, got " +
                       std::to_string(relative_epsilon));
  }
  if (length_.empty()) return rep;
  // the scale is robust: one far outlier vertex must not inflate the margin of every triangle
  rep.epsilon = relative_epsilon * robust_mean_length(length_);
  double delta = 0.0;
  const Index nf = n_faces();
  for (Index f = 0; f < nf; ++f) {
    const double l0 = halfedge_length(3 * f), l1 = halfedge_length(3 * f + 1),
                 l2 = halfedge_length(3 * f + 2);
    const double need = std::max(
        {rep.epsilon - (l0 + l1 - l2), rep.epsilon - (l1 + l2 - l0), rep.epsilon - (l2 + l0 - l1)});
    if (need > 0.0) {
      ++rep.faces_below_margin;
      delta = std::max(delta, need);
    }
  }
  if (delta > 0.0) {
    for (double& l : length_) l += delta;
  }
  rep.delta = delta;
  return rep;
}

// ---------------------------------------------------------------------------------------------
// Validation

void IntrinsicTriangulation::validate() const {
  auto fail = [](const std::string& msg) { throw InvalidInput("validate: " + msg); };
  const Index nh = n_halfedges();
  if (twin_.size() != tail_.size() || edge_.size() != tail_.size() || nh % 3 != 0) {
    fail("array sizes disagree");
  }
  if (static_cast<Index>(vertex_halfedge_.size()) != n_vertices_) fail("vertex array size");
  if (edge_halfedge_.size() != length_.size()) fail("edge array size");
  for (Index h = 0; h < nh; ++h) {
    const std::string hs = "halfedge " + std::to_string(h);
    if (tail_[h] < 0 || tail_[h] >= n_vertices_) fail(hs + ": tail out of range");
    const Index t = twin_[h];
    const Index e = edge_[h];
    if (e < 0 || e >= n_edges()) fail(hs + ": edge out of range");
    if (t != kInvalidIndex) {
      if (t < 0 || t >= nh || t == h || twin_[t] != h) fail(hs + ": twin is not an involution");
      if (tail_[t] != head(h) || head(t) != tail_[h]) fail(hs + ": twin runs the same direction");
      if (edge_[t] != e) fail(hs + ": twin has another edge");
    }
    const Index eh = edge_halfedge_[e];
    if (eh != h && eh != t) fail(hs + ": not a halfedge of its edge");
  }
  for (Index e = 0; e < n_edges(); ++e) {
    if (edge_[edge_halfedge_[e]] != e) fail("edge " + std::to_string(e) + ": bad edge_halfedge");
    if (!std::isfinite(length_[e]) || !(length_[e] > 0.0)) {
      fail("edge " + std::to_string(e) + ": length " + std::to_string(length_[e]) +
           " is not finite and positive");
    }
  }
  for (Index v = 0; v < n_vertices_; ++v) {
    const Index h = vertex_halfedge_[v];
    if (h != kInvalidIndex && (h < 0 || h >= nh || tail_[h] != v)) {
      fail("vertex " + std::to_string(v) + ": vertex_halfedge does not start at it");
    }
  }
  std::vector<char> used(n_vertices_, 0);
  for (Index h = 0; h < nh; ++h) used[tail_[h]] = 1;
  for (Index v = 0; v < n_vertices_; ++v) {
    if (used[v] != (vertex_halfedge_[v] != kInvalidIndex)) {
      fail("vertex " + std::to_string(v) + ": vertex_halfedge disagrees with the faces");
    }
  }
  for (Index f = 0; f < n_faces(); ++f) {
    const double l0 = halfedge_length(3 * f), l1 = halfedge_length(3 * f + 1),
                 l2 = halfedge_length(3 * f + 2);
    const double tol = 1e-12 * (l0 + l1 + l2);
    if (l0 + l1 < l2 - tol || l1 + l2 < l0 - tol || l2 + l0 < l1 - tol) {
      fail("face " + std::to_string(f) + ": lengths " + std::to_string(l0) + ", " +
           std::to_string(l1) + ", " + std::to_string(l2) + " violate the triangle inequality");
    }
  }
}

}  // namespace ifem::intrinsic
