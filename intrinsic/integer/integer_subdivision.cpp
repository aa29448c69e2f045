// Common subdivision from integer coordinates (integer_subdivision.h). Per intrinsic face: the
// boundary is walked counter-clockwise as a cycle of entries (corners, one entry per arc
// leaving a corner, and the crossings on the sides); every arc joins two entries. The polygons
// are the cycles "along the boundary to the next entry, then across its arc", whose interiors
// lie to the left of every step.
#include "intrinsic/integer/integer_subdivision.h"

#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <string>
#include <vector>

#include "intrinsic/core/errors.h"
#include "intrinsic/core/geometry.h"

namespace ifem::intrinsic {
namespace {

using T = IntrinsicTriangulation;

// Barycentric coordinates of a point placed within rounding of its face: negative ones cut to
// zero, renormalized (a point in the closed face).
Eigen::Vector3d clamped(const Eigen::Vector3d& bary) {
  const Eigen::Vector3d b = bary.cwiseMax(0.0);
  return b / b.sum();
}

struct Entry {
  Index vertex;        // output vertex id
  Eigen::Vector2d xy;  // in the face's layout
  int partner = -1;    // entry at the arc's other end
  Index input_edge = kInvalidIndex;
  double at = 0.0;  // fraction along the input edge's edge_halfedge
  int enter = 0;    // a crossing: +1 if the input edge, tail to head, enters the face here, −1 if
                    // it leaves; 0 at a corner
};

struct Polygon {
  Index face = kInvalidIndex;   // intrinsic
  Index input = kInvalidIndex;  // input face, once known
  std::vector<Index> vertex;
  std::vector<Eigen::Vector2d> xy;
};

class Builder {
 public:
  explicit Builder(const NormalCoordinateTriangulation& nc)
      : nc_(nc), tri_(nc.intrinsic()), in_(nc.input()) {}
  CommonSubdivision run();
  /// After run(): the input face each inserted vertex was placed in (−1 otherwise), by id.
  const std::vector<Index>& placed_face() const { return placed_face_; }
  /// After run(): barycentric coordinates of inserted vertex v (placed_face(v) ≥ 0) in its input
  /// face, from the face's intrinsic layout (stable on sliver faces, unlike the 3D plane).
  Eigen::Vector3d placed_bary(Index v) const;

 private:
  void trace_all();
  void face_polygons(Index g);
  std::vector<Entry> boundary(Index g, const Eigen::Vector2d p[3], int counts[3][3],
                              std::vector<int> side_first[3]);
  void walk(Index g, const std::vector<Entry>& b, const std::vector<int>* side_first,
            const int* n_side);
  Index side_input_face(Index h) const;
  void propagate_faces();
  void place_vertices(CommonSubdivision& out);
  void place_in_polygon(CommonSubdivision& out, Index v, std::size_t poly, int k1, int k2);
  const InputSpoke& spoke(Index v, int r, long steps = 0) const {
    return nc_.spokes(v)[nc_.spoke_index(v, r, steps)];
  }

  const NormalCoordinateTriangulation& nc_;
  const IntrinsicTriangulation& tri_;
  const IntrinsicTriangulation& in_;
  std::vector<std::vector<InputCrossing>> trace_;  // #E
  std::vector<Index> first_crossing_;              // #E: output id of its first crossing
  std::vector<Polygon> polys_;
  std::vector<Index> side_poly_;    // #H: the polygon along an uncrossed side (n = 0), or −1
  std::vector<Index> placed_face_;  // #V
  struct Placement {
    std::size_t poly = 0;
    int k1 = -1, k2 = -1;
  };
  std::vector<Placement> placement_;  // #V: the polygon and known pair that placed v
  Eigen::Vector2d input_layout_point(Index f, Index vertex) const;
};

void Builder::trace_all() {
  const Index ne = tri_.n_edges();
  trace_.resize(ne);
  first_crossing_.resize(ne);
  Index next = tri_.n_vertices();
  for (Index e = 0; e < ne; ++e) {
    trace_[e] = nc_.trace_edge(e);
    first_crossing_[e] = next;
    next += static_cast<Index>(trace_[e].size());
  }
}

// The input face to the left of intrinsic side h, which runs along an input edge (n = −1).
Index Builder::side_input_face(Index h) const {
  const Index a = tri_.tail(h), b = tri_.head(h), tw = tri_.twin(h);
  const InputSpoke& sa = spoke(a, nc_.roundabout(h));
  const double at_b =
      tw != kInvalidIndex ? spoke(b, nc_.roundabout(tw)).at : nc_.vertex_at(b, sa.input_edge);
  const Index h0 = in_.edge_halfedge(sa.input_edge);
  return at_b > sa.at ? T::face(h0) : T::face(in_.twin(h0));
}

std::vector<Entry> Builder::boundary(Index g, const Eigen::Vector2d p[3], int c[3][3],
                                     std::vector<int> side_first[3]) {
  // c[0] = clamped n per side, c[1] = corner arcs per corner, c[2] = fan arcs per corner
  std::vector<Entry> b;
  for (int k = 0; k < 3; ++k) {
    const Index h = 3 * g + k, v = tri_.tail(h);
    if (c[2][k] == 0) b.push_back({v, p[k]});
    const long base = nc_.normal_coordinate(tri_.edge(h)) < 0 ? 1 : 0;
    for (int j = c[2][k]; j >= 1; --j) {  // the fan, from side k+2's neighbour to side k's
      const InputSpoke& s = spoke(v, nc_.roundabout(h), base + j - 1);
      b.push_back({v, p[k], -1, s.input_edge, s.at});
    }
    const Index e = tri_.edge(h);
    const auto& tr = trace_[e];
    const int n = c[0][k];
    const bool forward = tri_.edge_halfedge(e) == h;
    side_first[k].assign(1, static_cast<int>(b.size()));
    for (int q = 1; q <= n; ++q) {
      const int i = forward ? q - 1 : n - q;
      const double t = forward ? tr[i].t : 1.0 - tr[i].t;
      b.push_back({first_crossing_[e] + i, p[k] + t * (p[(k + 1) % 3] - p[k]), -1, tr[i].input_edge,
                   tr[i].input_t, tr[i].into_left == forward ? 1 : -1});
    }
  }
  return b;
}

void Builder::face_polygons(Index g) {
  Eigen::Vector2d p[3];
  face_layout(tri_, g, p);
  int c[3][3];
  for (int s = 0; s < 3; ++s) {
    c[0][s] = std::max(0, nc_.normal_coordinate(tri_.edge(3 * g + s)));
    if (static_cast<int>(trace_[tri_.edge(3 * g + s)].size()) != c[0][s]) {
      throw InvalidInput("common_subdivision: trace of an edge disagrees with its coordinate");
    }
  }
  for (int k = 0; k < 3; ++k)
    c[2][k] = std::max(0, c[0][(k + 1) % 3] - c[0][k] - c[0][(k + 2) % 3]);
  for (int k = 0; k < 3; ++k) {
    c[1][k] = (c[0][k] + c[0][(k + 2) % 3] - c[0][(k + 1) % 3] - c[2][(k + 1) % 3] -
               c[2][(k + 2) % 3] + c[2][k]) /
              2;
  }
  std::vector<int> side_first[3];
  std::vector<Entry> b = boundary(g, p, c, side_first);
  auto side_entry = [&](int s, int q) { return side_first[s][0] + q - 1; };
  auto link = [&](int i, int j) { b[i].partner = j, b[j].partner = i; };
  int fan_entry[3] = {0, 0, 0};  // entry of fan arc j = c[2][k] (the first of the corner's)
  {
    int i = 0;
    for (int k = 0; k < 3; ++k) {
      fan_entry[k] = i;
      i += std::max(1, c[2][k]) + c[0][k];
    }
  }
  for (int k = 0; k < 3; ++k) {
    const int s2 = (k + 2) % 3, s1 = (k + 1) % 3;
    for (int q = 1; q <= c[1][k]; ++q) link(side_entry(k, q), side_entry(s2, c[0][s2] - q + 1));
    for (int j = 1; j <= c[2][k]; ++j) {
      link(fan_entry[k] + (c[2][k] - j), side_entry(s1, c[1][s1] + j));
    }
  }
  walk(g, b, side_first, c[0]);
}

void Builder::walk(Index g, const std::vector<Entry>& b, const std::vector<int>* side_first,
                   const int* n_side) {
  const int m = static_cast<int>(b.size());
  // gap i: from entry i along the boundary to entry i+1; the side it lies on (−1: at a corner)
  std::vector<int> gap_side(m, -1);
  for (int s = 0; s < 3; ++s) {
    for (int i = side_first[s][0] - 1; i < side_first[s][0] + n_side[s]; ++i) gap_side[i] = s;
  }
  std::vector<char> seen(m, 0);
  for (int start = 0; start < m; ++start) {
    if (seen[start]) continue;
    Polygon poly;
    poly.face = g;
    auto add = [&](const Entry& x) {
      if (poly.vertex.empty() || poly.vertex.back() != x.vertex) {
        poly.vertex.push_back(x.vertex);
        poly.xy.push_back(x.xy);
      }
    };
    const Index id = static_cast<Index>(polys_.size());
    int cur = start;
    for (int guard = 0; guard <= 2 * m + 2; ++guard) {
      seen[cur] = 1;
      add(b[cur]);
      const int s = gap_side[cur];
      const int nxt = (cur + 1) % m;
      if (s >= 0 && n_side[s] == 0) {  // a whole uncrossed side
        const Index h = 3 * g + s;
        if (nc_.normal_coordinate(tri_.edge(h)) < 0) {
          poly.input = side_input_face(h);
        } else {
          side_poly_[h] = id;
        }
      }
      if (b[nxt].partner >= 0) {
        const Entry &x = b[nxt], &y = b[x.partner];
        const Index h0 = in_.edge_halfedge(x.input_edge);
        // the polygon lies left of the arc x → y: h0's face if that runs tail to head
        const bool rising = x.enter != 0 ? x.enter > 0 : y.enter < 0;
        poly.input = rising ? T::face(h0) : T::face(in_.twin(h0));
        add(x);
        cur = x.partner;
      } else {
        cur = nxt;
      }
      if (cur == start) break;
    }
    if (poly.vertex.size() > 1 && poly.vertex.front() == poly.vertex.back()) {
      poly.vertex.pop_back();
      poly.xy.pop_back();
    }
    polys_.push_back(std::move(poly));
  }
}

// Polygons with no arc and no input side take the input face across an uncrossed side.
void Builder::propagate_faces() {
  for (bool changed = true; changed;) {
    changed = false;
    for (Index h = 0; h < tri_.n_halfedges(); ++h) {
      const Index a = side_poly_[h], tw = tri_.twin(h);
      if (a < 0 || tw == kInvalidIndex || side_poly_[tw] < 0) continue;
      Polygon &pa = polys_[a], &pb = polys_[side_poly_[tw]];
      if (pa.input < 0 && pb.input >= 0) pa.input = pb.input, changed = true;
    }
  }
  for (const Polygon& p : polys_) {
    if (p.input < 0) throw InvalidInput("common_subdivision: a polygon with no input face");
  }
}

// Places vertex v (a corner of polygon poly), with corners k1, k2 known. Where the input face's
// intrinsic lengths are its 3D ones (no mollification), its layout is congruent to the 3D
// triangle: the rigid map of the polygon's layout onto the face's plane taking k1, k2 to their
// positions (well conditioned on needle faces). Where they are not, that map would carry the
// misfit and could put v outside the face (the pieces around v then overlap or leave gaps): v
// gets the barycentric coordinates of its place in the face's intrinsic layout (placed_bary,
// clamped) applied to the 3D corners, as a signpost location, so the pieces tile the 3D face.
void Builder::place_in_polygon(CommonSubdivision& out, Index v, std::size_t poly, int k1, int k2) {
  const Polygon& p = polys_[poly];
  placed_face_[v] = p.input;
  placement_[v] = {poly, k1, k2};
  const Positions& x = nc_.input_positions();
  Eigen::Vector3d c[3];
  bool congruent = true;
  for (int k = 0; k < 3; ++k) c[k] = x.row(in_.tail(3 * p.input + k));
  for (int k = 0; k < 3; ++k) {
    const double l = in_.halfedge_length(3 * p.input + k);
    congruent = congruent && std::abs((c[(k + 1) % 3] - c[k]).norm() - l) <= 1e-12 * l;
  }
  if (!congruent) {
    const Eigen::Vector3d b = clamped(placed_bary(v));
    out.positions.row(v) = b[0] * c[0] + b[1] * c[1] + b[2] * c[2];
    return;
  }
  const Eigen::Vector3d normal = (c[1] - c[0]).cross(c[2] - c[0]).normalized();
  const Eigen::Vector3d q1 = out.positions.row(p.vertex[k1]);
  const Eigen::Vector3d q2 = out.positions.row(p.vertex[k2]);
  const Eigen::Vector3d u = (q2 - q1).normalized(), w = normal.cross(u);
  const Eigen::Vector2d u2 = (p.xy[k2] - p.xy[k1]).normalized(), w2(-u2.y(), u2.x());
  for (std::size_t k = 0; k < p.vertex.size(); ++k) {
    if (p.vertex[k] != v) continue;
    const Eigen::Vector2d d = p.xy[k] - p.xy[k1];
    out.positions.row(v) = q1 + d.dot(u2) * u + d.dot(w2) * w;
    return;
  }
}

// Output vertex `vertex` (an input vertex, a vertex on an input edge, or a crossing) in the
// layout of input face f, which it lies on the boundary of.
Eigen::Vector2d Builder::input_layout_point(Index f, Index vertex) const {
  Eigen::Vector2d p[3];
  face_layout(in_, f, p);
  Index edge = kInvalidIndex;
  double at = 0.0;
  if (vertex < nc_.n_input_vertices()) {
    for (int k = 0; k < 3; ++k) {
      if (in_.tail(3 * f + k) == vertex) return p[k];
    }
  } else if (vertex < tri_.n_vertices() && nc_.spokes(vertex).empty()) {
    // an inserted vertex placed in an earlier round, inside this same input face
    const Eigen::Vector3d b = placed_bary(vertex);
    return b[0] * p[0] + b[1] * p[1] + b[2] * p[2];
  } else if (vertex < tri_.n_vertices()) {
    edge = nc_.spokes(vertex)[0].input_edge;
    at = nc_.spokes(vertex)[0].at;
  } else {
    const auto e = static_cast<Index>(
        std::upper_bound(first_crossing_.begin(), first_crossing_.end(), vertex) -
        first_crossing_.begin() - 1);
    edge = trace_[e][vertex - first_crossing_[e]].input_edge;
    at = trace_[e][vertex - first_crossing_[e]].input_t;
  }
  for (int k = 0; k < 3; ++k) {
    if (in_.edge(3 * f + k) != edge) continue;
    const double t = in_.edge_halfedge(edge) == 3 * f + k ? at : 1.0 - at;
    return p[k] + t * (p[(k + 1) % 3] - p[k]);
  }
  throw InvalidInput("common_subdivision: a known point off its polygon's input face");
}

Eigen::Vector3d Builder::placed_bary(Index v) const {
  const Placement& pl = placement_[v];
  const Polygon& p = polys_[pl.poly];
  const Index f = placed_face_[v];
  const Eigen::Vector2d q1 = input_layout_point(f, p.vertex[pl.k1]);
  const Eigen::Vector2d q2 = input_layout_point(f, p.vertex[pl.k2]);
  const Eigen::Vector2d u = (q2 - q1).normalized(), w(-u.y(), u.x());
  const Eigen::Vector2d u2 = (p.xy[pl.k2] - p.xy[pl.k1]).normalized(), w2(-u2.y(), u2.x());
  Eigen::Vector2d x = q1;
  for (std::size_t k = 0; k < p.vertex.size(); ++k) {
    if (p.vertex[k] != v) continue;
    const Eigen::Vector2d d = p.xy[k] - p.xy[pl.k1];
    x = q1 + d.dot(u2) * u + d.dot(w2) * w;
  }
  Eigen::Vector2d c[3];
  face_layout(in_, f, c);
  const double area = (c[1] - c[0]).x() * (c[2] - c[0]).y() - (c[1] - c[0]).y() * (c[2] - c[0]).x();
  auto cross = [](const Eigen::Vector2d& a, const Eigen::Vector2d& b) {
    return a.x() * b.y() - a.y() * b.x();
  };
  Eigen::Vector3d bary(cross(c[2] - c[1], x - c[1]) / area, cross(c[0] - c[2], x - c[2]) / area,
                       0.0);
  bary[2] = 1.0 - bary[0] - bary[1];
  return bary;
}

void Builder::place_vertices(CommonSubdivision& out) {
  const Index nv = tri_.n_vertices(), n_in = nc_.n_input_vertices();
  std::vector<char> known(out.positions.rows(), 1);
  placed_face_.assign(nv, kInvalidIndex);
  placement_.assign(nv, {});
  const Positions& x = nc_.input_positions();
  for (Index v = 0; v < n_in; ++v) out.positions.row(v) = x.row(v);
  auto on_edge = [&](Index e, double t) {
    const Index h = in_.edge_halfedge(e);
    return Eigen::Vector3d((1.0 - t) * x.row(in_.tail(h)) + t * x.row(in_.head(h)));
  };
  for (Index v = n_in; v < nv; ++v) {
    const auto& s = nc_.spokes(v);
    known[v] = s.empty() ? 0 : 1;
    if (!s.empty()) out.positions.row(v) = on_edge(s[0].input_edge, s[0].at);
  }
  for (Index e = 0; e < tri_.n_edges(); ++e) {
    for (std::size_t i = 0; i < trace_[e].size(); ++i) {
      out.positions.row(first_crossing_[e] + i) =
          on_edge(trace_[e][i].input_edge, trace_[e][i].input_t);
    }
  }
  // an inserted vertex: the layout of a polygon it is a corner of, mapped rigidly onto the
  // polygon's input face plane by two known points; of all such polygons and pairs, the pair
  // farthest apart (where a vertex sits on or within rounding of an input edge, some polygons
  // around it are slivers whose known points nearly coincide: a map fixed by them would be
  // arbitrary). Rounds, for vertices whose polygons have no known pair yet.
  struct Choice {
    double d = 0.0;
    std::size_t poly = 0;
    int k1 = -1, k2 = -1;
  };
  std::vector<Choice> best(nv);
  for (bool changed = true; changed;) {
    changed = false;
    for (std::size_t pi = 0; pi < polys_.size(); ++pi) {
      const Polygon& p = polys_[pi];
      const int np = static_cast<int>(p.vertex.size());
      int k1 = -1, k2 = -1;
      double d_best = 0.0;
      for (int i = 0; i < np; ++i) {
        for (int j = i + 1; j < np && known[p.vertex[i]]; ++j) {
          const double d = (p.xy[j] - p.xy[i]).norm();
          if (known[p.vertex[j]] && d > d_best) d_best = d, k1 = i, k2 = j;
        }
      }
      for (int k = 0; k < np && k2 >= 0; ++k) {
        const Index v = p.vertex[k];
        if (!known[v] && d_best > best[v].d) best[v] = {d_best, pi, k1, k2};
      }
    }
    std::vector<Index> placed;
    for (Index v = n_in; v < nv; ++v) {
      if (known[v] || best[v].k2 < 0) continue;
      place_in_polygon(out, v, best[v].poly, best[v].k1, best[v].k2);
      placed.push_back(v);
    }
    for (const Index v : placed) known[v] = 1;
    changed = !placed.empty();
  }
  for (Index v = n_in; v < nv; ++v) {
    if (!known[v] && tri_.vertex_halfedge(v) != kInvalidIndex) {
      throw InvalidInput("common_subdivision: inserted vertex " + std::to_string(v) +
                         " could not be placed");
    }
  }
}

CommonSubdivision Builder::run() {
  trace_all();
  side_poly_.assign(tri_.n_halfedges(), -1);
  for (Index g = 0; g < tri_.n_faces(); ++g) face_polygons(g);
  propagate_faces();
  CommonSubdivision out;
  const Index n_out = tri_.n_edges() == 0
                          ? tri_.n_vertices()
                          : first_crossing_.back() + static_cast<Index>(trace_.back().size());
  out.crossings = static_cast<std::size_t>(n_out - tri_.n_vertices());
  out.positions.resize(n_out, 3);
  place_vertices(out);
  const std::vector<Index>& origin = nc_.input_face_origin();
  for (const Polygon& p : polys_) {
    for (std::size_t k = 1; k + 1 < p.vertex.size(); ++k) {
      out.faces.push_back({p.vertex[0], p.vertex[k], p.vertex[k + 1]});
      out.intrinsic_face.push_back(p.face);
      out.input_face.push_back(origin[p.input]);
    }
  }
  return out;
}

}  // namespace

CommonSubdivision common_subdivision(const NormalCoordinateTriangulation& nc) {
  return Builder(nc).run();
}

std::vector<SurfacePoint> vertex_locations(const NormalCoordinateTriangulation& nc) {
  const IntrinsicTriangulation& tri = nc.intrinsic();
  const IntrinsicTriangulation& in = nc.input();
  const Index nv = tri.n_vertices(), n_in = nc.n_input_vertices();
  std::vector<SurfacePoint> out(nv);
  for (Index v = 0; v < n_in; ++v) {
    const Index h = in.vertex_halfedge(v);
    if (h == kInvalidIndex) continue;
    out[v].face = T::face(h);
    out[v].bary[T::side(h)] = 1.0;
  }
  bool in_faces = false;
  for (Index v = n_in; v < nv; ++v) {
    const auto& spokes = nc.spokes(v);
    if (spokes.empty()) {
      in_faces = true;
      continue;
    }
    const Index h = in.edge_halfedge(spokes[0].input_edge);
    out[v].face = T::face(h);
    out[v].bary[T::side(h)] = 1.0 - spokes[0].at;
    out[v].bary[(T::side(h) + 1) % 3] = spokes[0].at;
  }
  if (!in_faces) return out;
  Builder builder(nc);
  (void)builder.run();
  for (Index v = n_in; v < nv; ++v) {
    const Index f = builder.placed_face()[v];
    if (!nc.spokes(v).empty() || f == kInvalidIndex) continue;
    // barycentric coordinates in the input face's intrinsic layout
    out[v].face = f;
    out[v].bary = clamped(builder.placed_bary(v));
  }
  return out;
}

}  // namespace ifem::intrinsic
