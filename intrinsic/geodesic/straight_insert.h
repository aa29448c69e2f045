// Straight segments between two vertices made an intrinsic edge by flipping the edges of one
// vertex's fan (internal to single_source_geodesics(): include flip_geodesic.h). The segment
// from p to w is laid out across the wedge at a vertex u between the edges u–p and u–w; when
// every other neighbour of u in that wedge lies strictly beyond the line p–w (seen from u), the
// wedge's faces hold the whole triangle (p, u, w), so the segment exists (a straight line in a
// flat region, no vertex on it) and flipping the wedge's spokes away, ear by ear, leaves it as
// an edge. docs/decisions.md D-205.
#pragma once

#include <Eigen/Core>
#include <functional>
#include <utility>
#include <vector>

#include "intrinsic/geodesic/flip_geodesic.h"

namespace ifem::intrinsic::detail {

/// A segment p → w through the wedge at u, ready to be inserted (plan_fan_segment()).
struct FanSegment {
  Index u = kInvalidIndex, p = kInvalidIndex, w = kInvalidIndex;
  double length = 0.0;           ///< |p w| in the wedge's layout (length unit of the surface)
  double direction_at_p = 0.0;   ///< the segment's signpost direction at p (p's angle units)
  double direction_at_w = 0.0;   ///< and at w (toward p)
  std::vector<Index> spokes;     ///< the edges u–x inside the wedge, in order from p to w
  std::vector<double> x, y;      ///< layout of p, the spokes' far ends and w (u at the origin)
  Index closing = kInvalidIndex; ///< without spokes: the edge p–w of the face (u, p, w)
};

/// Plans the segment from p = head(h_up) to w = head(h_uw) (both halfedges leave u) across the
/// wedge at u of angle < π − margin between them. False when u is on the boundary, the wedge is
/// not < π, a vertex of the wedge is not strictly beyond the line p–w (relative margin 1e-6),
/// a spoke is used (uses[e] > 0: it would be crossed), or vertices repeat.
/// 2: the fan holds the segment (insert_fan_segment()); 1: out's length and directions hold the
/// layout across the fan, but the fan does not hold the segment; 0: neither.
int plan_fan_segment(const SignpostTriangulation& st, Index h_up, Index h_uw,
                     const std::vector<int>& uses, FanSegment* out);

/// A segment p → w found by walking a straight line from p (plan_strip_segment()).
struct StripSegment {
  Index p = kInvalidIndex, w = kInvalidIndex;
  double length = 0.0;          ///< |p w| in the strip's layout
  double direction_at_p = 0.0;  ///< its signpost direction at p
  std::vector<Index> crossed;   ///< edges crossed, in order from p
  std::vector<std::pair<Index, Eigen::Vector2d>> at;  ///< the strip's vertices, laid out
  Index existing = kInvalidIndex;  ///< when p–w is already an edge (nothing crossed)
};

/// Walks the straight line leaving p in direction `theta` (p's signpost units; start the face
/// search at halfedge h_pu leaving p) until a face has w as a corner, then checks that the
/// segment p → w laid out in that strip crosses exactly the edges walked (each strictly between
/// its ends, relative margin 1e-6), none used (uses[e] > 0) or on the boundary, at most
/// max_cross of them, and that no vertex id appears at two places of the strip. False if not.
/// When the segment leaves the strip walked, the walk is repeated toward w as laid out in that
/// strip, up to retries_left more times.
bool plan_strip_segment(const SignpostTriangulation& st, Index h_pu, double theta, Index w,
                        const std::vector<int>& uses, int max_cross, StripSegment* out,
                        int retries_left = 10);

/// Flips the strip's crossed edges until p–w is an edge (Sloan's edge insertion: an edge that
/// still crosses the segment is flipped when its diamond is convex, else retried later) and
/// returns it, calling on_flip(e) after every flip; kInvalidIndex if it stalls (the flips done
/// stay: the surface is unchanged).
Index insert_strip_segment(SignpostTriangulation& st, const StripSegment& plan,
                           const std::function<void(Index)>& on_flip);

/// Flips plan's spokes away (each after its two faces are a convex diamond, ear by ear) and
/// returns the edge p–w, calling on_flip(e) after every flip; kInvalidIndex when a flip is
/// refused (the flips done so far stay: the surface is unchanged).
template <typename OnFlip>
Index insert_fan_segment(SignpostTriangulation& st, const FanSegment& plan, OnFlip&& on_flip);

/// The wedge angles at vertex v between the halfedge `back` (leaving v, toward where a path
/// came from) and a direction `out` (v's signpost units): {counter-clockwise from back to out,
/// the rest of v's angle sum}.
std::pair<double, double> joint_angles_at(const SignpostTriangulation& st, Index back, double out);

// ===== implementation of the template =====
bool fan_ear_convex(const FanSegment& plan, std::size_t a, std::size_t b, std::size_t c);

template <typename OnFlip>
Index insert_fan_segment(SignpostTriangulation& st, const FanSegment& plan, OnFlip&& on_flip) {
  if (plan.spokes.empty()) return plan.closing;
  // chain of layout points: 0 = p, 1..m = spokes' far ends, m + 1 = w
  std::vector<std::size_t> chain(plan.spokes.size() + 2);
  for (std::size_t k = 0; k < chain.size(); ++k) chain[k] = k;
  Index last = kInvalidIndex;
  while (chain.size() > 2) {
    bool flipped = false;
    for (std::size_t i = 1; i + 1 < chain.size(); ++i) {
      if (!fan_ear_convex(plan, chain[i - 1], chain[i], chain[i + 1])) continue;
      const Index e = plan.spokes[chain[i] - 1];
      if (!st.flip_edge(e)) return kInvalidIndex;
      on_flip(e);
      last = e;
      chain.erase(chain.begin() + static_cast<std::ptrdiff_t>(i));
      flipped = true;
      break;
    }
    if (!flipped) return kInvalidIndex;
  }
  const IntrinsicTriangulation& tri = st.intrinsic();
  const Index h = tri.edge_halfedge(last);
  const bool joins = (tri.tail(h) == plan.p && tri.head(h) == plan.w) ||
                     (tri.tail(h) == plan.w && tri.head(h) == plan.p);
  return joins ? last : kInvalidIndex;
}

}  // namespace ifem::intrinsic::detail
