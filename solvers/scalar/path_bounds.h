// Bounds on the exact geodesic distance that hold on any surface, for clamping an approximate
// distance (the heat method's) into them: a clamp into a true interval never moves a value
// away from the exact one, so it never increases any vertex's error (docs/decisions.md D-141).
#pragma once

#include <Eigen/Core>
#include <utility>
#include <vector>

#include "intrinsic/core/triangulation.h"
#include "intrinsic/core/types.h"

namespace ifem::solvers {

/// The graph of straight surface segments of an intrinsic triangulation: its edges, and across
/// every interior edge whose diamond is strictly convex, the diamond's other diagonal (the
/// segment laid out flat across the two faces, i.e. the flipped edge's length). Each graph edge
/// is a path on the surface, so every shortest path in the graph is an upper bound on the
/// geodesic distance between its ends (within rounding of the lengths).
class PathGraph {
 public:
  PathGraph() = default;
  /// @param tri any intrinsic triangulation (boundary, several components, Δ-complex loops and
  ///        parallel edges allowed; loops and degenerate diamonds add no diagonal)
  explicit PathGraph(const intrinsic::IntrinsicTriangulation& tri);

  /// Shortest graph paths from seeds (vertex, start length ≥ 0): #V lengths in tri's unit, +inf
  /// where no seed reaches.
  /// @throws InvalidInput on a seed vertex out of [0, #V) or a negative / non-finite length
  Eigen::VectorXd shortest_paths(const std::vector<std::pair<Index, double>>& seeds) const;

  Index n_vertices() const { return Index(offset_.empty() ? 0 : offset_.size() - 1); }
  /// Directed arcs (twice the graph's edges).
  Index n_arcs() const { return Index(target_.size()); }

 private:
  std::vector<Index> offset_;   // CSR: arcs of v are [offset_[v], offset_[v + 1])
  std::vector<Index> target_;   // head of each arc
  std::vector<double> length_;  // length of each arc
};

/// d ← max(lower, min(d, upper)) per vertex, lower = the straight-line (chord) distance from
/// the nearest source in `positions` (a geodesic is never shorter than the chord; the sources
/// must be the points measured from, not samples of a curve), upper =
/// `upper` (e.g. PathGraph::shortest_paths). Rows of d beyond positions.rows() get only the
/// upper bound; non-finite entries of d (unreachable) stay.
/// @param d #V distances (absolute), changed in place
/// @param upper #V upper bounds, same unit as d
/// @param positions #V_in×3 vertex positions (#V_in ≤ #V) or empty (no lower bound)
/// @param sources vertex ids with positions (< positions.rows()), or empty (no lower bound)
void clamp_to_bounds(Eigen::Ref<Eigen::VectorXd> d, const Eigen::VectorXd& upper,
                     const Positions& positions, const std::vector<Index>& sources);

}  // namespace ifem::solvers
