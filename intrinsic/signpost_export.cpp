// Export of the common subdivision: traced intrinsic edges as a PLY line set, and the overlay
// of the intrinsic and input triangulations as a triangle mesh.
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <filesystem>
#include <string>
#include <unordered_map>
#include <utility>

#include "intrinsic/io_detail.h"
#include "intrinsic/signpost.h"

namespace ifem::intrinsic {

void write_polylines_ply(const std::string& path,
                         const std::vector<std::vector<Eigen::Vector3d>>& polylines,
                         bool binary) {
  std::size_t nv = 0, ne = 0;
  for (const auto& line : polylines) {
    nv += line.size();
    if (line.size() > 1) ne += line.size() - 1;
  }
  if (nv > static_cast<std::size_t>(INT32_MAX)) {
    throw IoError(path + ": too many polyline vertices for 32-bit ids");
  }
  const std::string tmp = path + ".tmp";
  std::FILE* f = std::fopen(tmp.c_str(), binary ? "wb" : "w");
  if (!f) throw IoError(path + ": cannot open for writing");
  std::fprintf(f,
               "ply\nformat %s 1.0\ncomment ifem: traced intrinsic edges over the input surface\n"
               "element vertex %zu\nproperty double x\nproperty double y\nproperty double z\n"
               "element edge %zu\nproperty int vertex1\nproperty int vertex2\nend_header\n",
               binary ? "binary_little_endian" : "ascii", nv, ne);
  for (const auto& line : polylines) {
    for (const Eigen::Vector3d& x : line) {
      if (binary) {
        const double xyz[3] = {x.x(), x.y(), x.z()};  // x86/ARM hosts: little-endian
        std::fwrite(xyz, sizeof(double), 3, f);
      } else {
        std::fprintf(f, "%.17g %.17g %.17g\n", x.x(), x.y(), x.z());
      }
    }
  }
  std::int32_t base = 0;
  for (const auto& line : polylines) {
    for (std::size_t i = 1; i < line.size(); ++i) {
      const std::int32_t ab[2] = {base + static_cast<std::int32_t>(i - 1),
                                  base + static_cast<std::int32_t>(i)};
      if (binary) {
        std::fwrite(ab, sizeof(std::int32_t), 2, f);
      } else {
        std::fprintf(f, "%d %d\n", ab[0], ab[1]);
      }
    }
    base += static_cast<std::int32_t>(line.size());
  }
  io::detail::close_and_rename(f, true, tmp, path);
}

// ---------------------------------------------------------------------------------------------
// Common subdivision. Every intrinsic edge is traced over the input; a traced path is a chain of
// straight segments, each inside one input face. In each input face G the segments and G's
// sides (cut at the points where paths cross them) form a planar straight-line graph whose
// bounded faces are the polygons G ∩ F (F an intrinsic face, convex: both are flat triangles).
// A polygon's intrinsic face is read off a traced segment on its boundary (face(h) lies left
// of halfedge h); polygons bounded by input sides only take the label across a side, from the
// neighbouring input face.

namespace {

using T = IntrinsicTriangulation;

struct Segment {
  Index a, b;               // global node ids
  Eigen::Vector3d ba, bb;   // barycentric coordinates in the segment's input face
  Index h;                  // intrinsic halfedge running a → b
};

struct Polygon {
  Index input_face = kInvalidIndex;
  Index label = kInvalidIndex;
  std::vector<Index> nodes;
  std::vector<std::pair<int, std::pair<double, double>>> sides;  // (side k, [t0, t1])
};

constexpr double kSideTol = 1e-10;

}  // namespace

CommonSubdivision common_subdivision(const SignpostTriangulation& st) {
  const IntrinsicTriangulation& tri = st.intrinsic();
  const IntrinsicTriangulation& in = st.input();
  const Index n_in = st.n_input_vertices(), nvi = tri.n_vertices(), ne = tri.n_edges();

  // ---- trace every edge (from the halfedge trace_edge() would use)
  std::vector<Index> traced(ne);
  std::vector<std::vector<SurfacePoint>> paths(ne);
  std::string failure;
#pragma omp parallel for schedule(dynamic, 256)
  for (Index e = 0; e < ne; ++e) {
    Index h = tri.edge_halfedge(e);
    if (tri.tail(h) >= n_in && tri.head(h) < n_in && tri.twin(h) != kInvalidIndex) h = tri.twin(h);
    traced[e] = h;
    try {
      paths[e] = st.trace_halfedge(h);
    } catch (const Error& err) {
#pragma omp critical(ifem_common_subdivision_failure)
      if (failure.empty()) failure = "edge " + std::to_string(e) + ": " + err.what();
    }
  }
  if (!failure.empty()) throw Error("common_subdivision: " + failure);

  // ---- node ids: input vertices, inserted vertices, then one per interior path point
  std::vector<Index> offset(ne + 1, 0);
  for (Index e = 0; e < ne; ++e) {
    offset[e + 1] = offset[e] + Index(std::max<std::size_t>(paths[e].size(), 2) - 2);
  }
  const Index n_nodes = nvi + offset[ne];
  Positions node_x(n_nodes, 3);
  std::vector<char> node_used(n_nodes, 0);
  for (Index v = 0; v < n_in; ++v) node_x.row(v) = st.input_positions().row(v);
  for (Index v = n_in; v < nvi; ++v) node_x.row(v) = st.position(st.vertex_location(v)).transpose();

  // ---- segments per input face
  std::vector<std::vector<Segment>> per_face(in.n_faces());
  auto to_face = [&](const SurfacePoint& p, Index g_face) -> Eigen::Vector3d {
    if (p.face == g_face) return p.bary;
    // p lies on a side shared with g_face: re-express it there
    int best = -1;
    double best_b = 2.0;
    for (int s2 = 0; s2 < 3; ++s2) {
      const Index tw = in.twin(3 * p.face + s2);
      if (tw == kInvalidIndex || T::face(tw) != g_face) continue;
      if (p.bary[(s2 + 2) % 3] < best_b) {
        best_b = p.bary[(s2 + 2) % 3];
        best = s2;
      }
    }
    if (best < 0) throw Error("common_subdivision: traced path jumps between faces");
    const Index tw = in.twin(3 * p.face + best);
    const int s = int(T::side(tw));
    Eigen::Vector3d b = Eigen::Vector3d::Zero();
    b[s] = p.bary[(best + 1) % 3];
    b[(s + 1) % 3] = p.bary[best];
    return b;
  };
  for (Index e = 0; e < ne; ++e) {
    const auto& path = paths[e];
    const Index h = traced[e];
    const std::size_t n = path.size();
    if (n < 2) continue;
    for (std::size_t i = 0; i + 1 < n; ++i) {
      const Index g = path[i].face;
      Segment sg;
      sg.h = h;
      sg.a = i == 0 ? tri.tail(h) : nvi + offset[e] + Index(i - 1);
      sg.b = i + 2 == n ? tri.head(h) : nvi + offset[e] + Index(i);
      sg.ba = path[i].bary;
      sg.bb = to_face(path[i + 1], g);
      per_face[g].push_back(sg);
    }
  }

  // ---- intrinsic edges that run along an input side label that side on both of its faces
  //      (the trace records such a segment in one of the two faces only)
  struct SideLabel {
    int k;
    double t0, t1;
    Index label;
  };
  std::vector<std::vector<SideLabel>> side_labels(in.n_faces());
  auto snapped = [&](Index id, Index g, Eigen::Vector3d b) {
    for (int k = 0; k < 3; ++k) {
      if (id == in.tail(3 * g + k)) return Eigen::Vector3d(Eigen::Vector3d::Unit(k));
    }
    for (int k = 0; k < 3; ++k) {
      if (b[k] < kSideTol) b[k] = 0.0;
    }
    return Eigen::Vector3d(b / b.sum());
  };
  for (Index g = 0; g < in.n_faces(); ++g) {
    for (const Segment& sg : per_face[g]) {
      const Eigen::Vector3d ba = snapped(sg.a, g, sg.ba), bb = snapped(sg.b, g, sg.bb);
      for (int k = 0; k < 3; ++k) {
        if (ba[(k + 2) % 3] != 0.0 || bb[(k + 2) % 3] != 0.0) continue;
        const double ta = ba[(k + 1) % 3], tb = bb[(k + 1) % 3];
        if (ta == tb) continue;
        const Index tw_h = tri.twin(sg.h);
        const Index left_face = T::face(sg.h);
        const Index right_face = tw_h == kInvalidIndex ? kInvalidIndex : T::face(tw_h);
        // g's interior is left of its side run corner k → k+1 (t increasing)
        side_labels[g].push_back({k, std::min(ta, tb), std::max(ta, tb),
                                  ta < tb ? left_face : right_face});
        const Index tw = in.twin(3 * g + k);
        if (tw != kInvalidIndex) {
          side_labels[T::face(tw)].push_back({int(T::side(tw)), 1.0 - std::max(ta, tb),
                                              1.0 - std::min(ta, tb),
                                              ta < tb ? right_face : left_face});
        }
      }
    }
  }

  // ---- per input face: planar graph, its bounded faces
  std::vector<Polygon> polys;
  std::vector<std::vector<Index>> face_polys(in.n_faces());
  for (Index g = 0; g < in.n_faces(); ++g) {
    Eigen::Vector2d corner[3];
    face_layout(in, g, corner);
    const Index cv[3] = {in.tail(3 * g), in.tail(3 * g + 1), in.tail(3 * g + 2)};
    std::unordered_map<Index, int> local;
    std::vector<Index> gid;
    std::vector<Eigen::Vector3d> bary;
    auto node = [&](Index id, Eigen::Vector3d b) -> int {
      // snap to a corner of g when the node is (numerically) one
      for (int k = 0; k < 3; ++k) {
        if (id == cv[k] || (id >= nvi && b[k] > 1.0 - kSideTol)) {
          id = cv[k];
          b = Eigen::Vector3d::Zero();
          b[k] = 1.0;
          break;
        }
      }
      const auto it = local.find(id);
      if (it != local.end()) return it->second;
      for (int k = 0; k < 3; ++k) {
        if (b[k] < kSideTol) b[k] = 0.0;
      }
      b /= b.sum();
      if (id >= nvi) {
        // a path point where another node already is (a trace leaving a vertex that lies on a
        // side): the same node
        for (std::size_t i = 0; i < bary.size(); ++i) {
          if ((bary[i] - b).squaredNorm() < kSideTol * kSideTol) return int(i);
        }
      }
      if (id >= nvi && !node_used[id]) {
        Eigen::Vector3d x = Eigen::Vector3d::Zero();
        for (int k = 0; k < 3; ++k) x += b[k] * st.input_positions().row(cv[k]).transpose();
        node_x.row(id) = x.transpose();
      }
      node_used[id] = 1;
      local.emplace(id, int(gid.size()));
      gid.push_back(id);
      bary.push_back(b);
      return int(gid.size()) - 1;
    };
    for (int k = 0; k < 3; ++k) node(cv[k], Eigen::Vector3d::Unit(k));
    // directed edges: (from, to) → label of the face on the left (-1 unknown, -2 outside)
    std::vector<std::vector<int>> adj;
    std::unordered_map<long long, Index> left;
    auto key = [](int a, int b) { return (static_cast<long long>(a) << 32) | unsigned(b); };
    std::vector<std::pair<int, int>> inner;
    std::vector<Index> inner_h;
    for (const Segment& sg : per_face[g]) {
      const int a = node(sg.a, sg.ba), b = node(sg.b, sg.bb);
      if (a == b) continue;
      bool along_side = false;
      for (int k = 0; k < 3; ++k) {
        if (bary[a][(k + 2) % 3] == 0.0 && bary[b][(k + 2) % 3] == 0.0) along_side = true;
      }
      if (along_side) continue;  // labels its side (side_labels)
      inner.push_back({a, b});
      inner_h.push_back(sg.h);
    }
    const int nl = int(gid.size());
    adj.assign(nl, {});
    auto add_edge = [&](int a, int b, Index lab_ab, Index lab_ba) {
      if (left.count(key(a, b)) || left.count(key(b, a))) return;
      left[key(a, b)] = lab_ab;
      left[key(b, a)] = lab_ba;
      adj[a].push_back(b);
      adj[b].push_back(a);
    };
    // sides, cut at the nodes on them
    for (int k = 0; k < 3; ++k) {
      std::vector<std::pair<double, int>> on;
      for (int i = 0; i < nl; ++i) {
        if (bary[i][(k + 2) % 3] == 0.0) on.push_back({bary[i][(k + 1) % 3], i});
      }
      std::sort(on.begin(), on.end());
      for (std::size_t i = 0; i + 1 < on.size(); ++i) {
        const double tm = 0.5 * (on[i].first + on[i + 1].first);
        Index lab = -1;
        for (const SideLabel& sl : side_labels[g]) {
          if (sl.k == k && sl.t0 <= tm && tm <= sl.t1 && sl.label != kInvalidIndex) {
            lab = sl.label;
          }
        }
        add_edge(on[i].second, on[i + 1].second, lab, -2);
      }
    }
    for (std::size_t i = 0; i < inner.size(); ++i) {
      const Index h = inner_h[i];
      add_edge(inner[i].first, inner[i].second, T::face(h),
               tri.twin(h) == kInvalidIndex ? -1 : T::face(tri.twin(h)));
    }
    // 2D positions, neighbours sorted counter-clockwise
    std::vector<Eigen::Vector2d> p(nl);
    for (int i = 0; i < nl; ++i) {
      p[i] = bary[i][0] * corner[0] + bary[i][1] * corner[1] + bary[i][2] * corner[2];
    }
    for (int i = 0; i < nl; ++i) {
      auto& nb = adj[i];
      std::sort(nb.begin(), nb.end(), [&](int x, int y) {
        const Eigen::Vector2d dx = p[x] - p[i], dy = p[y] - p[i];
        return std::atan2(dx.y(), dx.x()) < std::atan2(dy.y(), dy.x());
      });
    }
    std::unordered_map<long long, char> seen;
    for (int a0 = 0; a0 < nl; ++a0) {
      for (const int b0 : adj[a0]) {
        if (seen.count(key(a0, b0))) continue;
        Polygon poly;
        poly.input_face = g;
        double area2 = 0.0;
        bool outside = false;
        int a = a0, b = b0;
        for (int guard = 0; guard <= 2 * nl + 4; ++guard) {
          seen[key(a, b)] = 1;
          poly.nodes.push_back(a);
          const Index lab = left[key(a, b)];
          if (lab == -2) outside = true;
          if (lab >= 0 && poly.label < 0) poly.label = lab;
          area2 += p[a].x() * p[b].y() - p[b].x() * p[a].y();
          // on a side of g (both ends on side k, going ccw): remember it for labels
          for (int k = 0; k < 3; ++k) {
            if (bary[a][(k + 2) % 3] == 0.0 && bary[b][(k + 2) % 3] == 0.0) {
              const double ta = bary[a][(k + 1) % 3], tb = bary[b][(k + 1) % 3];
              if (ta < tb) poly.sides.push_back({k, {ta, tb}});
            }
          }
          // next: the neighbour of b before a in counter-clockwise order
          const auto& nb = adj[b];
          const auto it = std::find(nb.begin(), nb.end(), a);
          const int c = nb[(std::size_t(it - nb.begin()) + nb.size() - 1) % nb.size()];
          a = b;
          b = c;
          if (a == a0 && b == b0) break;
        }
        if (outside || !(area2 > 0.0)) continue;
        for (Index& x : poly.nodes) x = gid[std::size_t(x)];
        face_polys[g].push_back(Index(polys.size()));
        polys.push_back(std::move(poly));
      }
    }
  }

  // ---- labels across input sides, for polygons with no traced segment on their boundary
  for (bool progress = true; progress;) {
    progress = false;
    for (Polygon& poly : polys) {
      if (poly.label >= 0) continue;
      for (const auto& [k, range] : poly.sides) {
        const Index tw = in.twin(3 * poly.input_face + k);
        if (tw == kInvalidIndex) continue;
        const double t = 1.0 - 0.5 * (range.first + range.second);
        const int k2 = int(T::side(tw));
        for (const Index q : face_polys[T::face(tw)]) {
          if (polys[q].label < 0) continue;
          for (const auto& [k3, r3] : polys[q].sides) {
            if (k3 == k2 && r3.first <= t && t <= r3.second) poly.label = polys[q].label;
          }
        }
        if (poly.label >= 0) break;
      }
      if (poly.label >= 0) progress = true;
    }
  }

  // ---- output: compact nodes (input vertices keep their ids), fan polygons
  CommonSubdivision cs;
  std::vector<Index> id(n_nodes, kInvalidIndex);
  Index n_out = 0;
  for (Index v = 0; v < n_nodes; ++v) {
    if (v < nvi || node_used[v]) id[v] = n_out++;
  }
  std::vector<Eigen::Vector3d> extra;
  for (const Polygon& poly : polys) {
    const std::size_t m = poly.nodes.size();
    const Index fi = st.input_face_origin().empty() ? poly.input_face
                                                    : st.input_face_origin()[poly.input_face];
    auto emit = [&](Index a, Index b, Index c) {
      cs.faces.push_back({a, b, c});
      cs.intrinsic_face.push_back(poly.label);
      cs.input_face.push_back(fi);
    };
    if (m == 3) {
      emit(id[poly.nodes[0]], id[poly.nodes[1]], id[poly.nodes[2]]);
      continue;
    }
    // a fan around the centroid: no sliver triangles from collinear nodes on the sides
    Eigen::Vector3d c = Eigen::Vector3d::Zero();
    for (const Index x : poly.nodes) c += node_x.row(x).transpose();
    extra.push_back(c / double(m));
    const Index ci = n_out + Index(extra.size()) - 1;
    for (std::size_t i = 0; i < m; ++i) {
      emit(ci, id[poly.nodes[i]], id[poly.nodes[(i + 1) % m]]);
    }
  }
  cs.positions.resize(n_out + Index(extra.size()), 3);
  for (Index v = 0; v < n_nodes; ++v) {
    if (id[v] != kInvalidIndex) cs.positions.row(id[v]) = node_x.row(v);
  }
  for (std::size_t i = 0; i < extra.size(); ++i) {
    cs.positions.row(n_out + Index(i)) = extra[i].transpose();
  }
  return cs;
}

void write_common_subdivision_ply(const std::string& path, const CommonSubdivision& cs,
                                  bool binary) {
  if (cs.positions.rows() > INT32_MAX || cs.faces.size() > std::size_t(INT32_MAX)) {
    throw IoError(path + ": too many vertices for 32-bit ids");
  }
  const std::string tmp = path + ".tmp";
  std::FILE* f = std::fopen(tmp.c_str(), binary ? "wb" : "w");
  if (!f) throw IoError(path + ": cannot open for writing");
  std::fprintf(f,
               "ply\nformat %s 1.0\n"
               "comment ifem: common subdivision of the intrinsic and input triangulations\n"
               "element vertex %ld\nproperty double x\nproperty double y\nproperty double z\n"
               "element face %zu\nproperty list uchar int vertex_indices\n"
               "property int intrinsic_face\nproperty int input_face\nend_header\n",
               binary ? "binary_little_endian" : "ascii", long(cs.positions.rows()),
               cs.faces.size());
  for (Eigen::Index v = 0; v < cs.positions.rows(); ++v) {
    const double xyz[3] = {cs.positions(v, 0), cs.positions(v, 1), cs.positions(v, 2)};
    if (binary) {
      std::fwrite(xyz, sizeof(double), 3, f);  // x86/ARM hosts: little-endian
    } else {
      std::fprintf(f, "%.17g %.17g %.17g\n", xyz[0], xyz[1], xyz[2]);
    }
  }
  for (std::size_t i = 0; i < cs.faces.size(); ++i) {
    const std::int32_t rec[5] = {std::int32_t(cs.faces[i][0]), std::int32_t(cs.faces[i][1]),
                                 std::int32_t(cs.faces[i][2]), std::int32_t(cs.intrinsic_face[i]),
                                 std::int32_t(cs.input_face[i])};
    if (binary) {
      const unsigned char three = 3;
      std::fwrite(&three, 1, 1, f);
      std::fwrite(rec, sizeof(std::int32_t), 5, f);
    } else {
      std::fprintf(f, "3 %d %d %d %d %d\n", rec[0], rec[1], rec[2], rec[3], rec[4]);
    }
  }
  io::detail::close_and_rename(f, true, tmp, path);
}

}  // namespace ifem::intrinsic
