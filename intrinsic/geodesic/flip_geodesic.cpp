// FlipOut geodesic paths (flip_geodesic.h): edge paths, their initial construction, the
// options and their checks, and the 3D traces of paths. shorten() and the wedge angles live
// with the engine, in flip_network.cpp.
#include "intrinsic/geodesic/flip_geodesic.h"

#include <algorithm>
#include <cmath>
#include <functional>
#include <limits>
#include <memory>
#include <queue>
#include <string>
#include <utility>

#include "intrinsic/core/errors.h"
#include "intrinsic/core/geometry.h"

namespace ifem::intrinsic {

namespace {

using T = IntrinsicTriangulation;
constexpr double kInf = std::numeric_limits<double>::infinity();

// Every edge both ways, by tail vertex (CSR): the graph of Dijkstra's searches.
}  // namespace

struct EdgePathFinder::EdgeGraph {
  std::vector<Index> start;  // #V + 1
  std::vector<PathStep> out;
  // the search's arrays, #V, reused: only the entries a search touched are reset after it
  std::vector<double> dist;
  std::vector<PathStep> via;
  std::vector<Index> touched;
  explicit EdgeGraph(const T& tri)
      : start(tri.n_vertices() + 1, 0),
        out(2 * tri.n_edges()),
        dist(tri.n_vertices(), kInf),
        via(tri.n_vertices()) {
    for (Index e = 0; e < tri.n_edges(); ++e) {
      const Index h = tri.edge_halfedge(e);
      ++start[tri.tail(h) + 1];
      ++start[tri.head(h) + 1];
    }
    for (Index v = 0; v < tri.n_vertices(); ++v) start[v + 1] += start[v];
    std::vector<Index> fill(start.begin(), start.end() - 1);
    for (Index e = 0; e < tri.n_edges(); ++e) {
      const Index h = tri.edge_halfedge(e);
      out[fill[tri.tail(h)]++] = {e, true};
      out[fill[tri.head(h)]++] = {e, false};
    }
  }
};

namespace {

using EdgeGraph = EdgePathFinder::EdgeGraph;

// Shortest edge path a → b on the graph, appended to *path; false when b is unreachable.
bool dijkstra(const T& tri, EdgeGraph& g, Index a, Index b, EdgePath* path) {
  std::vector<double>& dist = g.dist;
  std::vector<PathStep>& via = g.via;
  for (const Index v : g.touched) dist[v] = kInf;
  g.touched.clear();
  using Item = std::pair<double, Index>;
  std::priority_queue<Item, std::vector<Item>, std::greater<Item>> queue;
  dist[a] = 0.0;
  g.touched.push_back(a);
  queue.push({0.0, a});
  while (!queue.empty()) {
    const auto [d, v] = queue.top();
    queue.pop();
    if (d > dist[v]) continue;
    if (v == b) break;
    for (Index k = g.start[v]; k < g.start[v + 1]; ++k) {
      const PathStep& s = g.out[k];
      const Index u = step_head(tri, s);
      const double du = d + tri.length(s.edge);
      if (du < dist[u]) {
        if (dist[u] == kInf) g.touched.push_back(u);
        dist[u] = du;
        via[u] = s;
        queue.push({du, u});
      }
    }
  }
  if (!std::isfinite(dist[b])) return false;
  const std::size_t first = path->steps.size();
  for (Index v = b; v != a; v = step_tail(tri, via[v])) path->steps.push_back(via[v]);
  std::reverse(path->steps.begin() + static_cast<std::ptrdiff_t>(first), path->steps.end());
  return true;
}

// The shortest edge from a to b, as a step (edge kInvalidIndex if they are not adjacent).
PathStep direct_edge(const T& tri, const EdgeGraph& g, Index a, Index b) {
  PathStep best;
  for (Index k = g.start[a]; k < g.start[a + 1]; ++k) {
    const PathStep& s = g.out[k];
    if (step_head(tri, s) != b) continue;
    if (best.edge == kInvalidIndex || tri.length(s.edge) < tri.length(best.edge)) best = s;
  }
  return best;
}

void check_vertex(const T& tri, Index v, std::size_t position) {
  if (v < 0 || v >= tri.n_vertices()) {
    throw InvalidInput("vertex " + std::to_string(v) + " (position " + std::to_string(position) +
                       ") is out of range [0, " + std::to_string(tri.n_vertices()) + ")");
  }
}

}  // namespace

Index step_halfedge(const IntrinsicTriangulation& tri, const PathStep& step) {
  const Index h = tri.edge_halfedge(step.edge);
  return step.forward ? h : tri.twin(h);
}

Index step_tail(const IntrinsicTriangulation& tri, const PathStep& step) {
  const Index h = tri.edge_halfedge(step.edge);
  return step.forward ? tri.tail(h) : tri.head(h);
}

Index step_head(const IntrinsicTriangulation& tri, const PathStep& step) {
  const Index h = tri.edge_halfedge(step.edge);
  return step.forward ? tri.head(h) : tri.tail(h);
}

std::vector<Index> path_vertices(const IntrinsicTriangulation& tri, const EdgePath& path) {
  std::vector<Index> v;
  for (const PathStep& s : path.steps) v.push_back(step_tail(tri, s));
  if (!path.closed && !path.steps.empty()) v.push_back(step_head(tri, path.steps.back()));
  return v;
}

double path_length(const IntrinsicTriangulation& tri, const EdgePath& path) {
  double l = 0.0;
  for (const PathStep& s : path.steps) l += tri.length(s.edge);
  return l;
}

EdgePath shortest_edge_path(const IntrinsicTriangulation& tri, Index a, Index b) {
  return edge_path_through(tri, {a, b}, false, false);
}

EdgePath shortest_edge_path(const SignpostTriangulation& st, Index a, Index b) {
  return shortest_edge_path(st.intrinsic(), a, b);
}

EdgePathFinder::EdgePathFinder(const IntrinsicTriangulation& tri)
    : tri_(tri), graph_(std::make_unique<EdgeGraph>(tri)) {}
EdgePathFinder::~EdgePathFinder() = default;

EdgePath edge_path_through(const IntrinsicTriangulation& tri, const std::vector<Index>& vertices,
                           bool closed, bool pin, JoinBy join) {
  return EdgePathFinder(tri).through(vertices, closed, pin, join);
}

EdgePath EdgePathFinder::through(const std::vector<Index>& vertices, bool closed, bool pin,
                                 JoinBy join) {
  const T& tri = tri_;
  EdgeGraph& g = *graph_;
  if (vertices.size() < 2) {
    throw InvalidInput("a path needs at least two vertices, got " +
                       std::to_string(vertices.size()));
  }
  for (std::size_t i = 0; i < vertices.size(); ++i) check_vertex(tri, vertices[i], i);
  EdgePath path;
  path.closed = closed;
  const std::size_t legs = closed ? vertices.size() : vertices.size() - 1;
  for (std::size_t i = 0; i < legs; ++i) {
    const Index a = vertices[i], b = vertices[(i + 1) % vertices.size()];
    if (a == b) {
      throw InvalidInput("vertices at positions " + std::to_string(i) + " and " +
                         std::to_string((i + 1) % vertices.size()) + " are the same vertex " +
                         std::to_string(a) + " (consecutive points must differ)");
    }
    if (i > 0 && pin) path.pinned.push_back(static_cast<Index>(path.steps.size()));
    const PathStep d = join == JoinBy::kDirectEdges ? direct_edge(tri, g, a, b) : PathStep{};
    if (d.edge != kInvalidIndex) {
      path.steps.push_back(d);
    } else if (!dijkstra(tri, g, a, b, &path)) {
      throw InvalidInput("vertex " + std::to_string(b) + " is not reachable from vertex " +
                         std::to_string(a) + " (different connected components)");
    }
  }
  if (closed && pin) path.pinned.insert(path.pinned.begin(), 0);
  return path;
}

void FlipOutOptions::validate() const {
  if (!(angle_epsilon >= 0.0 && angle_epsilon < kPi)) {
    throw InvalidInput("FlipOutOptions::angle_epsilon must be in [0, π), got " +
                       std::to_string(angle_epsilon));
  }
  if (max_iterations < -1) {
    throw InvalidInput("FlipOutOptions::max_iterations must be ≥ −1 (−1: automatic), got " +
                       std::to_string(max_iterations));
  }
  if (!(min_relative_decrease >= 0.0 && min_relative_decrease < 1.0)) {
    throw InvalidInput("FlipOutOptions::min_relative_decrease must be in [0, 1), got " +
                       std::to_string(min_relative_decrease));
  }
}

const char* to_string(FlipOutStop stop) {
  switch (stop) {
    case FlipOutStop::kConverged:
      return "converged";
    case FlipOutStop::kIterationCap:
      return "iteration cap";
    case FlipOutStop::kNoProgress:
      return "no progress";
    case FlipOutStop::kBlocked:
      return "blocked";
  }
  return "unknown";
}

std::vector<char> curve_edge_flags(const IntrinsicTriangulation& tri,
                                   const std::vector<EdgePath>& paths) {
  std::vector<char> flags(tri.n_edges(), 0);
  for (const EdgePath& p : paths) {
    for (const PathStep& s : p.steps) flags[s.edge] = 1;
  }
  return flags;
}

std::vector<SurfacePoint> path_surface_points(const SignpostTriangulation& st,
                                              const EdgePath& path) {
  const T& tri = st.intrinsic();
  std::vector<SurfacePoint> line;
  for (const PathStep& s : path.steps) {
    std::vector<SurfacePoint> pts = st.trace_halfedge(tri.edge_halfedge(s.edge));
    if (!s.forward) std::reverse(pts.begin(), pts.end());
    // the ends are vertices: their own locations, not where a long trace lands (off by
    // round-off that grows with the number of sides crossed)
    pts.front() = st.vertex_location(step_tail(tri, s));
    pts.back() = st.vertex_location(step_head(tri, s));
    line.insert(line.end(), pts.begin() + (line.empty() ? 0 : 1), pts.end());
  }
  return line;
}

std::vector<Eigen::Vector3d> path_polyline(const SignpostTriangulation& st, const EdgePath& path) {
  std::vector<Eigen::Vector3d> line;
  for (const SurfacePoint& p : path_surface_points(st, path)) line.push_back(st.position(p));
  return line;
}

}  // namespace ifem::intrinsic
