#include "intrinsic/refine/conforming.h"

#include <algorithm>
#include <cmath>

#include "intrinsic/core/geometry.h"

namespace ifem::intrinsic::detail {
namespace {

using T = IntrinsicTriangulation;

// The halfedges leaving v: counter-clockwise from vertex_halfedge(v), then clockwise from it if
// the first walk stopped at the boundary (repeats possible on a Δ-complex; bounded walks).
void outgoing(const IntrinsicTriangulation& tri, Index v, std::vector<Index>& out) {
  out.clear();
  const Index h0 = tri.vertex_halfedge(v);
  if (h0 == kInvalidIndex) return;
  const Index guard = tri.n_halfedges();
  Index h = h0;
  for (Index k = 0; k < guard; ++k) {
    out.push_back(h);
    h = tri.twin(T::prev(h));
    if (h == kInvalidIndex) break;
    if (h == h0) return;
  }
  h = h0;
  for (Index k = 0; k < guard; ++k) {
    const Index t = tri.twin(h);
    if (t == kInvalidIndex) return;
    h = T::next(t);
    if (h == h0) return;
    out.push_back(h);
  }
}

// Fraction from the tail of edge_halfedge(e) at which to split e: a concentric shell around
// its one corner end, else the midpoint (see conforming.h).
double split_fraction(const ConformHost& host, Index e, bool* shell) {
  const IntrinsicTriangulation& tri = host.tri;
  const Index h = tri.edge_halfedge(e);
  const bool corner_tail = tri.tail(h) < host.first_inserted;
  const bool corner_head = tri.head(h) < host.first_inserted;
  *shell = false;
  if (corner_tail == corner_head) return 0.5;
  const double len = tri.length(e);
  const double d = std::ldexp(1.0, static_cast<int>(std::lround(std::log2(0.5 * len))));
  const double t = std::clamp(d / len, 0.25, 0.75);  // [1/(2√2), 1/√2] up to rounding
  *shell = t != 0.5;
  return corner_tail ? t : 1.0 - t;
}

bool is_barrier(const IntrinsicTriangulation& tri, const std::vector<char>* flags, Index e) {
  return tri.twin(tri.edge_halfedge(e)) == kInvalidIndex || is_flagged(flags, e);
}

}  // namespace

bool negative_weight(const IntrinsicTriangulation& tri, Index e, double* relative) {
  const Index h = tri.edge_halfedge(e);
  const double a = halfedge_cotan(tri, h);
  const Index t = tri.twin(h);
  const double b = t == kInvalidIndex ? 0.0 : halfedge_cotan(tri, t);
  const double scale = std::abs(a) + std::abs(b);
  if (relative) *relative = scale > 0.0 ? (a + b) / scale : 0.0;
  return a + b < -1e-12 * scale;
}

ConformOutcome conform_barriers(const ConformHost& host) {
  const IntrinsicTriangulation& tri = host.tri;
  ConformOutcome out;
  std::vector<Index> stack, star, queue, touched;
  for (Index e = 0; e < tri.n_edges(); ++e) {
    if (is_barrier(tri, host.flags, e)) stack.push_back(e);
  }
  // barrier sides of face f go on the stack
  auto push_sides = [&](Index f) {
    for (int k = 0; k < 3; ++k) {
      const Index e = tri.edge(3 * f + k);
      if (is_barrier(tri, host.flags, e)) stack.push_back(e);
    }
  };
  while (!stack.empty()) {
    const Index e = stack.back();
    stack.pop_back();
    if (!negative_weight(tri, e)) continue;
    if (tri.length(e) < host.floor || !tri.can_split_edge(e)) continue;  // counted below
    if (out.splits >= host.max_splits) {
      out.hit_cap = true;
      break;
    }
    bool shell = false;
    const double t = split_fraction(host, e, &shell);
    const Index v = host.split(e, t);
    if (v == kInvalidIndex) continue;  // counted by the host
    ++out.splits;
    if (shell) ++out.shell_splits;
    outgoing(tri, v, star);
    queue.clear();
    touched.clear();
    for (const Index h : star) queue.push_back(tri.edge(T::next(h)));
    out.flips += host.flip_from(queue, &touched);
    outgoing(tri, v, star);
    for (const Index h : star) push_sides(T::face(h));
    for (const Index f : touched) push_sides(f);
  }
  for (Index e = 0; e < tri.n_edges(); ++e) {
    double rel = 0.0;
    if (!is_barrier(tri, host.flags, e) || !negative_weight(tri, e, &rel)) continue;
    ++out.negative_left;
    if (tri.length(e) < host.floor) ++out.floor_left;
    out.min_relative_weight = std::min(out.min_relative_weight, rel);
  }
  return out;
}

}  // namespace ifem::intrinsic::detail
