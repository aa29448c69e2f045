#include "solvers/scalar/path_bounds.h"

#include <algorithm>
#include <cmath>
#include <functional>
#include <limits>
#include <queue>
#include <string>

#include "intrinsic/core/errors.h"

namespace ifem::solvers {

using intrinsic::IntrinsicTriangulation;

namespace {

struct Arc {
  Index a, b;
  double length;
};

// Across the interior edge of halfedge h (a→b, face (a, b, c); twin b→a, face (b, a, d)): the
// diagonal c–d laid out flat, when it crosses the edge strictly inside (convex diamond).
bool diamond_diagonal(const IntrinsicTriangulation& tri, Index h, Arc* out) {
  const Index t = tri.twin(h);
  if (t == kInvalidIndex || t < h) return false;  // boundary, or seen from the twin
  const Index c = tri.tail(IntrinsicTriangulation::prev(h));
  const Index d = tri.tail(IntrinsicTriangulation::prev(t));
  if (c == d) return false;
  const double l = tri.halfedge_length(h);
  // a = (0, 0), b = (l, 0); c above (|ac|, |bc|), d below (|ad|, |bd|)
  const double ac = tri.halfedge_length(IntrinsicTriangulation::prev(h));
  const double bc = tri.halfedge_length(IntrinsicTriangulation::next(h));
  const double ad = tri.halfedge_length(IntrinsicTriangulation::next(t));
  const double bd = tri.halfedge_length(IntrinsicTriangulation::prev(t));
  const double cx = (ac * ac - bc * bc + l * l) / (2 * l),
               dx = (ad * ad - bd * bd + l * l) / (2 * l);
  const double cy = std::sqrt(std::max(0.0, ac * ac - cx * cx));
  const double dy = -std::sqrt(std::max(0.0, ad * ad - dx * dx));
  if (!(cy > 0.0) || !(dy < 0.0)) return false;
  const double x = cx + (dx - cx) * cy / (cy - dy);  // where c–d meets the line of a–b
  if (!(x > 0.0 && x < l)) return false;
  const double len = std::hypot(cx - dx, cy - dy);
  if (!std::isfinite(len)) return false;
  *out = {c, d, len};
  return true;
}

// |x_v − x_s| without overflow or underflow at any scale, and exactly 2^k times as large for
// positions scaled by 2^k (the largest coordinate difference is divided out and multiplied back).
double scaled_norm(const Positions& x, Index v, Index s) {
  const Eigen::RowVector3d diff = x.row(v) - x.row(s);
  const double m = diff.cwiseAbs().maxCoeff();
  return m > 0.0 && std::isfinite(m) ? m * (diff / m).norm() : m;
}

}  // namespace

PathGraph::PathGraph(const IntrinsicTriangulation& tri) {
  // two passes over the same arcs (the edges, then the diamonds' diagonals): count each
  // vertex's arcs, then write them into the CSR arrays; no list of arcs is staged (it was
  // 16 bytes an arc, the largest transient of a multigrid distance at 1M faces: D-365)
  const Index nv = tri.n_vertices();
  auto for_each_arc = [&tri](auto&& visit) {
    for (Index e = 0; e < tri.n_edges(); ++e) {
      const Index h = tri.edge_halfedge(e);
      if (tri.tail(h) != tri.head(h)) visit(Arc{tri.tail(h), tri.head(h), tri.length(e)});
    }
    Arc a{};
    for (Index h = 0; h < tri.n_halfedges(); ++h) {
      if (diamond_diagonal(tri, h, &a)) visit(a);
    }
  };
  offset_.assign(std::size_t(nv) + 1, 0);
  for_each_arc([this](const Arc& x) {
    ++offset_[std::size_t(x.a) + 1];
    ++offset_[std::size_t(x.b) + 1];
  });
  for (Index v = 0; v < nv; ++v) offset_[std::size_t(v) + 1] += offset_[std::size_t(v)];
  target_.resize(std::size_t(offset_[std::size_t(nv)]));
  length_.resize(std::size_t(offset_[std::size_t(nv)]));
  std::vector<Index> fill(offset_.begin(), offset_.end() - 1);
  for_each_arc([&](const Arc& x) {
    for (const auto& [from, to] : {std::pair{x.a, x.b}, std::pair{x.b, x.a}}) {
      const Index slot = fill[std::size_t(from)]++;
      target_[std::size_t(slot)] = to;
      length_[std::size_t(slot)] = x.length;
    }
  });
}

Eigen::VectorXd PathGraph::shortest_paths(
    const std::vector<std::pair<Index, double>>& seeds) const {
  const Index nv = n_vertices();
  Eigen::VectorXd d = Eigen::VectorXd::Constant(nv, std::numeric_limits<double>::infinity());
  using Entry = std::pair<double, Index>;
  std::priority_queue<Entry, std::vector<Entry>, std::greater<Entry>> queue;
  for (const auto& [v, start] : seeds) {
    if (v < 0 || v >= nv) {
      throw InvalidInput("PathGraph: seed vertex " + std::to_string(v) + " out of range [0, " +
                         std::to_string(nv) + ")");
    }
    if (!(start >= 0.0) || !std::isfinite(start)) {
      throw InvalidInput("PathGraph: seed length must be ≥ 0 and finite");
    }
    if (start < d[v]) {
      d[v] = start;
      queue.push({start, v});
    }
  }
  while (!queue.empty()) {
    const auto [dv, v] = queue.top();
    queue.pop();
    if (dv > d[v]) continue;
    for (Index i = offset_[std::size_t(v)]; i < offset_[std::size_t(v) + 1]; ++i) {
      const Index w = target_[std::size_t(i)];
      const double dw = dv + length_[std::size_t(i)];
      if (dw < d[w]) {
        d[w] = dw;
        queue.push({dw, w});
      }
    }
  }
  return d;
}

void clamp_to_bounds(Eigen::Ref<Eigen::VectorXd> d, const Eigen::VectorXd& upper,
                     const Positions& positions, const std::vector<Index>& sources) {
  if (upper.size() != d.size()) throw InvalidInput("clamp_to_bounds: upper has the wrong size");
  for (const Index s : sources) {
    if (s < 0 || s >= Index(positions.rows())) {
      throw InvalidInput("clamp_to_bounds: source " + std::to_string(s) + " has no position");
    }
  }
  const Index n_lower = sources.empty() ? 0 : std::min(Index(positions.rows()), Index(d.size()));
  for (Index v = 0; v < Index(d.size()); ++v) {
    if (!std::isfinite(d[v])) continue;
    double x = std::min(d[v], upper[v]);
    if (v < n_lower) {
      double chord = std::numeric_limits<double>::infinity();
      for (const Index s : sources) chord = std::min(chord, scaled_norm(positions, v, s));
      x = std::max(x, chord);
    }
    d[v] = x;
  }
}

}  // namespace ifem::solvers
