// The FlipOut engine behind shorten(), bezier_curve() and single_source_geodesics() (internal:
// include flip_geodesic.h). Curves are held as linked lists of steps so that a reroute splices
// in O(chain) and a priority queue of joints (smallest wedge angle first, lazily re-validated)
// finds the next bend without rescanning the curves.
//
// Cost per flip: corner angles are computed once per face between flips (a calloc'ed #H cache,
// touched only where the curves go; the flip's two new corners come from the signpost update),
// and a joint's wedge angles once per change of its steps. The flip test β < π reads the sign
// of sin β from the two corners' atan2 arguments (atan2 only within 1e-9 rad of 0 or π: the
// same answers). A joint at an interior vertex (one closed fan) that is straight by a margin
// is judged from the signposts at its vertex in O(1), and a bent one is summed face by face
// over its side-0 wedge (over at most 32 faces: past that, the signposts' figure). After a flip
// the wedge is updated in O(1) where the flipped faces have one corner at the joint (walked
// again otherwise), and one walk both finds a wedge and checks it is not blocked. All flips
// during a network's life must be its own (the corner cache follows them). docs/decisions.md
// D-128, D-147, D-385.
#pragma once

#include <cstdlib>
#include <functional>
#include <memory>
#include <queue>
#include <utility>
#include <vector>

#include "intrinsic/geodesic/flip_geodesic.h"

namespace ifem::intrinsic::detail {

/// The faces swept counter-clockwise around a vertex b from the edge of `start` (a halfedge
/// leaving b) to the edge of `end` (a halfedge entering b), each given by its halfedge x leaving
/// b (face(x) spans from x to prev(x)), written over *w (its capacity is reused). Empty if either
/// is invalid, a boundary side is met first, or the walk does not close.
void wedge_faces(const IntrinsicTriangulation& tri, Index start, Index end, std::vector<Index>* w);
/// Sum of the corner angles at b of the wedge wedge_faces(tri, start, end) would give, in its
/// order, without storing it (+∞ for an empty one).
double wedge_angle(const IntrinsicTriangulation& tri, Index start, Index end);
/// The (start, end) halfedges of the wedge of side `side` at the joint of steps `in` → `out`
/// (see wedge_angles()), for wedge_faces() and wedge_angle().
std::pair<Index, Index> joint_wedge_ends(const IntrinsicTriangulation& tri, const PathStep& in,
                                         const PathStep& out, int side);

class FlipNetwork {
 public:
  /// `uses`: #E counts of curve steps per edge, shared with the caller (single-source geodesics
  /// keeps the accepted paths counted across runs); `fixed`: optional #E flags never flipped.
  /// Allocates #H doubles and #V bytes (zero pages until used). @throws std::bad_alloc
  FlipNetwork(SignpostTriangulation& st, std::vector<int>& uses, const std::vector<char>* fixed);

  /// What a caller knows of a curve's joints from an earlier run. A joint's wedge angles are
  /// those of the surface between its two steps: flips change them only by rounding, so they
  /// hold as long as the steps do. Joint i is the one between steps i − 1 and i.
  struct KnownJoints {
    Index straight_below = 0;  ///< joints 1 .. straight_below − 1 are not bent, but for `bent`
    std::vector<std::pair<Index, Eigen::Vector2d>> bent;  ///< (joint, its two wedge angles)
  };

  /// Adds a curve (its steps are counted in uses); returns its id. `known` (optional) spares
  /// the wedge walks of joints whose angles are known. @throws InvalidInput if the steps are
  /// not consecutive or a pinned joint is out of range
  Index add(const EdgePath& path, Index id_for_messages, const KnownJoints* known = nullptr);
  /// Forgets every curve without uncounting their steps (they stay as obstacles).
  void release_curves();
  /// Forgets every curve and uncounts its steps.
  void drop_curves();
  /// Shortens all curves; fills the report's counts, stop reason, lengths and collapsed loops.
  void run(const FlipOutOptions& options, FlipOutReport& report);
  /// The current curve c as an EdgePath (pinned joints renumbered).
  EdgePath extract(Index c) const;
  /// The joints of open curve c now bent by less than the last run's limit, for add().
  KnownJoints known_joints(Index c);
  Index n_curves() const { return static_cast<Index>(curves_.size()); }
  /// Called after every successful flip with the flipped edge.
  std::function<void(Index)> on_flip;
  /// Test hook (D-385): when set, the wedge spliced after a flip is compared with the wedge
  /// walked again (std::logic_error naming the flip if they differ), and flips are counted by
  /// how their wedge was updated.
  bool check_splices = false;
  Index spliced_flips = 0, walked_flips = 0;

 private:
  struct Node {
    PathStep step;
    Index prev = kInvalidIndex, next = kInvalidIndex;
    Index curve = kInvalidIndex;
    unsigned stamp = 0;     // changes whenever the joint at this node's head changes
    bool pin_head = false;  // the joint at this node's head is pinned
    bool alive = true;
    bool angles_known = false;  // angles hold the joint's wedge angles at stamp angles_stamp
    unsigned angles_stamp = 0;
    Eigen::Vector2d angles{0.0, 0.0};
  };
  struct Curve {
    Index first = kInvalidIndex;  // kInvalidIndex: no steps
    bool closed = false;
    double length = 0.0;
  };
  struct Bend {
    double angle;
    Index node;
    unsigned stamp;
    bool operator>(const Bend& o) const { return angle > o.angle; }
  };

  bool is_joint(Index a) const;
  Eigen::Vector2d joint_angles(Index a);  // memoized per node and stamp
  Eigen::Vector2d walk_joint_angles(Index a);
  double corner(Index h);  // corner_angle(h), computed once per unflipped face
  bool one_closed_fan(Index v);
  void forget_corners(Index e);                             // after flipping e
  double beta(const std::vector<Index>& w, std::size_t i);  // angle at the far end of w[i]
  bool beta_at_least_flat(const std::vector<Index>& w, std::size_t i);  // β ≥ π − slack
  void set_angles(Index a, const Eigen::Vector2d& angles);
  std::pair<Index, Index> joint_wedge_ends(Index a, int side) const;
  void push_joint(Index a);
  Index new_node(const PathStep& s, Index curve);
  void link(Index a, Index b);
  bool remove_backtrack(Index a);
  bool open_wedge(Index start, Index end, std::vector<Index>* w) const;
  bool flip_wedge(Index a, int side);
  void check_splice(Index a, int side, std::size_t j, Index x, bool spliced);
  void reroute(Index a, int side);
  bool straighten(Index a, const Eigen::Vector2d& angles);
  Index push_all_bends();
  void finish(FlipOutReport& report) const;

  SignpostTriangulation& st_;
  std::vector<int>& uses_;
  const std::vector<char>* fixed_;
  std::vector<Node> nodes_;
  std::vector<Curve> curves_;
  std::priority_queue<Bend, std::vector<Bend>, std::greater<Bend>> queue_;
  double limit_ = 0.0;  // π − ε
  Index flips_ = 0;
  std::vector<Index> wedge_;  // flip_wedge()'s wedge, read by reroute()
  // corner angles by halfedge, 0 where not computed (all flips are this network's)
  std::unique_ptr<double, void (*)(void*)> corner_{nullptr, std::free};
  // per vertex: 0 not yet known, 1 one closed fan, 2 boundary or pinched (one_closed_fan())
  std::unique_ptr<unsigned char, void (*)(void*)> fan_{nullptr, std::free};
  std::vector<PathStep> chain_;  // reroute()'s scratch
};

}  // namespace ifem::intrinsic::detail
