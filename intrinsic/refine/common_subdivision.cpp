// Export of the common subdivision: traced intrinsic edges as a PLY line set, and the overlay
// of the intrinsic and input triangulations as a triangle mesh.
#include "intrinsic/refine/common_subdivision.h"

#include <algorithm>
#include <array>
#include <atomic>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <filesystem>
#include <iomanip>
#include <sstream>
#include <string>
#include <tuple>
#include <utility>
#include <vector>

#include "intrinsic/core/first_error.h"
#include "intrinsic/core/types.h"
#include "intrinsic/io/detail.h"
#include "intrinsic/refine/delaunay_refine.h"

namespace ifem::intrinsic {

void write_polylines_ply(const std::string& path,
                         const std::vector<std::vector<Eigen::Vector3d>>& polylines, bool binary,
                         const std::string& comment) {
  std::size_t nv = 0, ne = 0;
  for (const auto& line : polylines) {
    nv += line.size();
    if (line.size() > 1) ne += line.size() - 1;
  }
  if (nv > static_cast<std::size_t>(INT32_MAX)) {
    throw IoError(path + ": too many polyline vertices for 32-bit ids");
  }
  std::FILE* f = io::detail::open_temporary(path, binary);
  std::fprintf(f,
               "ply\nformat %s 1.0\ncomment ifem: %s\n"
               "element vertex %zu\nproperty double x\nproperty double y\nproperty double z\n"
               "element edge %zu\nproperty int vertex1\nproperty int vertex2\nend_header\n",
               binary ? "binary_little_endian" : "ascii", comment.c_str(), nv, ne);
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
  io::detail::close_and_rename(f, true, path);
}

// ---------------------------------------------------------------------------------------------
// Common subdivision. Every intrinsic edge is traced over the input; a traced path is a chain of
// straight segments, each inside one input face. In each input face G the segments and G's
// sides (cut at the points where paths cross them) form a planar straight-line graph whose
// bounded faces are the polygons G ∩ F (F an intrinsic face, convex: both are flat triangles).
// A polygon's intrinsic face is read off a traced segment on its boundary (face(h) lies left
// of halfedge h); polygons bounded by input sides only take the label across a side, from the
// neighbouring input face.
//
// Input faces are assembled independently (in parallel, in chunks of consecutive faces), each
// in time about linear in its number of segments: hash tables instead of scans, a path point is
// compared for coincidence only with the nodes near it on its side, side labels are swept in
// order, and the adjacency is flat with the reverse of every directed edge. The results are
// merged in face order, so the output does not depend on the number of threads: polygons of G
// in the order of their smallest local node (nodes numbered as they are met) and then of
// direction (atan2), a path point's position taken in the first face that makes it a node.

namespace {

using T = IntrinsicTriangulation;

constexpr double kSideTol = 1e-10;
constexpr Index kChunkFaces = 256;  // input faces per unit of parallel work

// Segment i of traced edge e: from path point i to path point i + 1, in input face
// paths[e][i].face.
struct SegmentRef {
  Index e, i;
};

// A traced edge as the per-face assembly reads it (one cache line holds two).
struct EdgePath {
  const SurfacePoint* points;  // its path
  Index n;                     // points on it
  Index base;                  // node id of path point 1 (then 2, ...)
  Index tail, head;            // its endpoints (intrinsic vertices)
  Index h;                     // the intrinsic halfedge traced
};

// Asks for the cache line at p ahead of its use.
inline void prefetch(const void* p) {
#if defined(__GNUC__) || defined(__clang__)
  __builtin_prefetch(p);
#else
  (void)p;
#endif
}

// A part [t0, t1] of side k of an input face (t: barycentric coordinate of corner k + 1) that an
// intrinsic edge runs along, with the intrinsic face on the input face's side of it.
struct SideLabel {
  int k;
  double t0, t1;
  Index label;
};

// A part [t0, t1] of side k of an input face on a polygon's boundary.
struct SideRun {
  int k;
  double t0, t1;
};

// A polygon of the overlay: its nodes are Chunk::nodes[node_begin, next polygon's node_begin).
struct PolyRec {
  Index input_face;
  Index label;  // intrinsic face, -1 while unknown
  Index node_begin;
};

// Output of the assembly of a range of input faces.
struct Chunk {
  std::vector<PolyRec> polys;
  std::vector<Index> nodes;            // global node ids
  std::vector<Index> face_poly_begin;  // per face of the chunk, + 1
  std::vector<Index> unlabeled_faces;  // faces with a polygon of unknown label
  std::size_t n_out_faces = 0, n_extra = 0;
};

// Polygon sides of one input face (kept only for faces involved in labels across sides).
struct FaceSides {
  std::vector<Index> begin;  // per polygon, + 1
  std::vector<SideRun> runs;
};

// Open-addressing hash map from non-negative 64-bit keys to int. reset() clears in time
// proportional to the keys inserted since the last reset.
class FlatMap {
 public:
  void reset(std::size_t n) {
    std::size_t cap = 16;
    while (cap < 2 * n) cap *= 2;
    if (cap > keys_.size()) {
      keys_.assign(cap, -1);
      vals_.resize(cap);
      shift_ = 64;
      for (std::size_t c = cap; c > 1; c /= 2) --shift_;
    } else {
      for (const std::size_t s : used_) keys_[s] = -1;
    }
    used_.clear();
  }
  // The value stored for key, or -1.
  int find(std::int64_t key) const {
    for (std::size_t s = slot(key);; s = (s + 1) & (keys_.size() - 1)) {
      if (keys_[s] == key) return vals_[s];
      if (keys_[s] < 0) return -1;
    }
  }
  // Stores (key, val) unless key is there; returns the value stored for key.
  int insert(std::int64_t key, int val) {
    std::size_t s = slot(key);
    for (; keys_[s] >= 0; s = (s + 1) & (keys_.size() - 1)) {
      if (keys_[s] == key) return vals_[s];
    }
    keys_[s] = key;
    vals_[s] = val;
    used_.push_back(s);
    return val;
  }
  // Sets the value of key, inserting it if absent; returns the former value or -1.
  int exchange(std::int64_t key, int val) {
    std::size_t s = slot(key);
    while (keys_[s] >= 0 && keys_[s] != key) s = (s + 1) & (keys_.size() - 1);
    int old = -1;
    if (keys_[s] < 0) {
      used_.push_back(s);
    } else {
      old = vals_[s];
    }
    keys_[s] = key;
    vals_[s] = val;
    return old;
  }
  // Sets the value of key, inserting it if absent.
  void set(std::int64_t key, int val) {
    std::size_t s = slot(key);
    while (keys_[s] >= 0 && keys_[s] != key) s = (s + 1) & (keys_.size() - 1);
    if (keys_[s] < 0) used_.push_back(s);
    keys_[s] = key;
    vals_[s] = val;
  }

 private:
  std::size_t slot(std::int64_t key) const {
    return std::size_t((std::uint64_t(key) * 0x9E3779B97F4A7C15ull) >> shift_);
  }
  std::vector<std::int64_t> keys_;
  std::vector<int> vals_;
  std::vector<std::size_t> used_;
  int shift_ = 64;
};

// Inputs of the per-face assembly, shared by the threads (read only, created excepted).
struct Inputs {
  const IntrinsicTriangulation* tri;
  const IntrinsicTriangulation* in;
  Index nvi;
  const std::vector<EdgePath>* edges;   // per intrinsic edge
  const std::vector<Index>* seg_begin;  // per input face, + 1: its segments in segs
  const std::vector<SegmentRef>* segs;
  const std::vector<Index>* label_begin;  // per input face, + 1: its side labels in labels
  const std::vector<SideLabel>* labels;
  // 2 bytes per path point: made a node in the face of the segment it starts / ends. Each
  // byte belongs to the one input face holding that segment.
  std::vector<unsigned char>* created;
};

// p (in its face, or on a side of it shared with g_face) in barycentric coordinates of g_face;
// false if p.face and g_face share no side.
bool to_face(const IntrinsicTriangulation& in, const SurfacePoint& p, Index g_face,
             Eigen::Vector3d& out) {
  if (p.face == g_face) {
    out = p.bary;
    return true;
  }
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
  if (best < 0) return false;
  const Index tw = in.twin(3 * p.face + best);
  const int s = int(T::side(tw));
  out = Eigen::Vector3d::Zero();
  out[s] = p.bary[(best + 1) % 3];
  out[(s + 1) % 3] = p.bary[best];
  return true;
}

// Barycentric coordinates of a node: those below the tolerance are zero (on a side), the rest
// normalized.
Eigen::Vector3d snap_to_sides(Eigen::Vector3d b) {
  for (int k = 0; k < 3; ++k) {
    if (b[k] < kSideTol) b[k] = 0.0;
  }
  b /= b.sum();
  return b;
}

// Builds the planar graph of one input face and walks its bounded faces. One per thread, its
// buffers reused from face to face.
class FaceAssembler {
 public:
  explicit FaceAssembler(const Inputs& inputs) : x_(inputs) {}

  // Appends the polygons of input face g to out, and their sides to `sides` when given.
  void assemble(Index g, Chunk& out, FaceSides* sides);

 private:
  int node(Index id, Eigen::Vector3d b, int role);
  void start_face(Index g);
  void gather_segments(Index g);
  void add_edge(int a, int b, Index lab_ab, Index lab_ba, bool may_repeat);
  void label_sides(Index g);
  void add_inner_edges();
  void lay_out(Index g);
  void build_adjacency();
  void fill_slots();
  void sort_neighbours(int i);
  bool sort_by_pseudo_angle(int i, int s0, int deg);
  void sort_by_atan2(int i, int s0, int s1);
  void link_faces();
  void walk(Index g, Chunk& out, FaceSides* sides);
  // bucket of the nodes with coordinate j below kSideTol, by their coordinate j + 2: cells
  // 2^-30 wide (monotone in t; t ≥ −1e-9 here, so cells are ≥ −1 and the cast is a floor)
  static std::int64_t bucket_key(int j, std::int64_t cell) {
    return (std::int64_t(j) << 40) | (cell + 1);
  }
  bool on_two_sides(int i) const {
    const Eigen::Vector3d& b = bary_[std::size_t(i)];
    return (b[0] == 0.0) + (b[1] == 0.0) + (b[2] == 0.0) >= 2;
  }
  static std::int64_t cell_of(double t) { return std::int64_t(t * 1073741824.0 + 1.0) - 1; }
  // orders (angle, slot) pairs by angle
  static bool by_angle(const std::pair<double, int>& u, const std::pair<double, int>& v) {
    return u.first < v.first;
  }

  const Inputs& x_;
  Index cv_[3] = {kInvalidIndex, kInvalidIndex, kInvalidIndex};
  // nodes (local ids, in the order made)
  std::vector<Index> gid_;
  std::vector<Eigen::Vector3d> bary_;
  std::vector<Eigen::Vector2d> p_;
  FlatMap local_;   // global id → local id (intrinsic vertices only)
  FlatMap bucket_;  // bucket_key → last node made in that bucket
  std::vector<std::array<int, 3>> next_in_bucket_;  // per node and coordinate j: the node made
                                                    // before it in its bucket
  std::vector<std::pair<double, int>> on_side_[3];  // per side k: (t, node) of its nodes
  // traced segments not along a side, and intrinsic halfedges
  std::vector<std::pair<int, int>> inner_;
  std::vector<Index> inner_h_;
  std::vector<int> uses_;  // per node: segments ending there
  // undirected edges in the order added (of duplicates, the first), labels left of a→b, b→a
  FlatMap edge_seen_;
  std::vector<std::pair<int, int>> edges_;
  std::vector<std::pair<Index, Index>> edge_labels_;
  // side sweep
  struct Run {
    double t0, t1;
    Index order, label;
  };
  std::vector<Run> runs_, heap_;
  // directed edges leaving node a: slots first_[a] .. first_[a + 1] - 1, counter-clockwise
  std::vector<int> first_, fill_, nbr_, half_, slot_of_, nbr2_, half2_;
  std::vector<Index> left_;  // per slot: label of the face on its left (-2: outside g)
  std::vector<int> next_;    // per slot: the next directed edge around the face on its left
  std::vector<std::pair<double, int>> ang_;
  std::vector<double> key_;
  std::vector<int> order_;
  std::vector<char> seen_;
};

// The local id of the node at (id, b), made if new. role: 0 if the node starts a segment, 1 if
// it ends one (a path point is made a node by one or both of the faces it is on). A path point
// comes here once per face: when it both ends and starts a segment of g, the caller reuses the
// first answer (the same the second call would give).
int FaceAssembler::node(Index id, Eigen::Vector3d b, int role) {
  const Index nvi = x_.nvi;
  // snap to a corner of g when the node is (numerically) one
  for (int k = 0; k < 3; ++k) {
    if (id == cv_[k] || (id >= nvi && b[k] > 1.0 - kSideTol)) {
      id = cv_[k];
      b = Eigen::Vector3d::Zero();
      b[k] = 1.0;
      break;
    }
  }
  if (id < nvi) {
    const int found = local_.find(id);
    if (found >= 0) return found;
  }
  b = snap_to_sides(b);
  if (id >= nvi) {
    // a path point where another node already is (a trace leaving a vertex that lies on a
    // side): the same node, the first one made within kSideTol. Every coordinate of a node
    // that close differs from b's by less than kSideTol: if b is on a side (coordinate j
    // zero), only the nodes with coordinate j below kSideTol in the cells next to b's
    // coordinate j + 2 need a look.
    int j = -1;
    for (int k = 2; k >= 0; --k) {
      if (b[k] == 0.0) j = k;
    }
    int best = -1;
    if (j >= 0) {
      const double t = b[(j + 2) % 3];
      const std::int64_t c1 = cell_of(t + 1.5 * kSideTol);
      for (std::int64_t c = cell_of(t - 1.5 * kSideTol); c <= c1; ++c) {
        for (int i = bucket_.find(bucket_key(j, c)); i >= 0;
             i = next_in_bucket_[std::size_t(i)][std::size_t(j)]) {
          if ((best < 0 || i < best) &&
              (bary_[std::size_t(i)] - b).squaredNorm() < kSideTol * kSideTol) {
            best = i;
          }
        }
      }
    } else {
      for (std::size_t i = 0; i < bary_.size(); ++i) {
        if ((bary_[i] - b).squaredNorm() < kSideTol * kSideTol) {
          best = int(i);
          break;
        }
      }
    }
    if (best >= 0) return best;
    (*x_.created)[2 * std::size_t(id - nvi) + std::size_t(role)] = 1;
  }
  const int me = int(gid_.size());
  if (id < nvi) local_.set(id, me);
  gid_.push_back(id);
  bary_.push_back(b);
  next_in_bucket_.push_back({-1, -1, -1});
  for (int j = 0; j < 3; ++j) {
    if (!(b[j] < kSideTol)) continue;
    next_in_bucket_.back()[std::size_t(j)] =
        bucket_.exchange(bucket_key(j, cell_of(b[(j + 2) % 3])), me);
    // on side k = j + 1, at t = its coordinate k + 1 = j + 2
    if (b[j] == 0.0) on_side_[(j + 1) % 3].emplace_back(b[(j + 2) % 3], me);
  }
  return me;
}

// Adds edge a–b unless it is there already (the first one counts). `may_repeat` false: the
// caller knows no edge a–b was or will be added before it.
void FaceAssembler::add_edge(int a, int b, Index lab_ab, Index lab_ba, bool may_repeat) {
  if (may_repeat) {
    const std::int64_t key = (std::int64_t(std::min(a, b)) << 32) | std::max(a, b);
    const int slot = int(edges_.size());
    if (edge_seen_.insert(key, slot) != slot) return;
  }
  edges_.emplace_back(a, b);
  edge_labels_.emplace_back(lab_ab, lab_ba);
}

// The sides of g cut at the nodes on them, labelled where an intrinsic edge runs along: by the
// last side label (in the order made) covering the part's midpoint.
void FaceAssembler::label_sides(Index g) {
  const Index l_begin = (*x_.label_begin)[g], l_end = (*x_.label_begin)[g + 1];
  auto later = [](const Run& u, const Run& v) { return u.order < v.order; };
  for (int k = 0; k < 3; ++k) {
    std::vector<std::pair<double, int>>& on = on_side_[k];
    std::sort(on.begin(), on.end());
    runs_.clear();
    for (Index l = l_begin; l < l_end; ++l) {
      const SideLabel& sl = (*x_.labels)[l];
      if (sl.k == k && sl.label != kInvalidIndex) runs_.push_back({sl.t0, sl.t1, l, sl.label});
    }
    std::sort(runs_.begin(), runs_.end(), [](const Run& u, const Run& v) { return u.t0 < v.t0; });
    heap_.clear();
    std::size_t next = 0;
    for (std::size_t i = 0; i + 1 < on.size(); ++i) {
      const double tm = 0.5 * (on[i].first + on[i + 1].first);  // nondecreasing in i
      for (; next < runs_.size() && runs_[next].t0 <= tm; ++next) {
        heap_.push_back(runs_[next]);
        std::push_heap(heap_.begin(), heap_.end(), later);
      }
      // a run ending before tm ends before every later midpoint too
      while (!heap_.empty() && !(tm <= heap_.front().t1)) {
        std::pop_heap(heap_.begin(), heap_.end(), later);
        heap_.pop_back();
      }
      // the same two nodes are consecutive on another side only if both are at a corner
      const int u = on[i].second, v = on[i + 1].second;
      add_edge(u, v, heap_.empty() ? -1 : heap_.front().label, -2,
               on_two_sides(u) && on_two_sides(v));
    }
  }
}

// Flat adjacency of the edges, each node's neighbours sorted counter-clockwise by atan2 (from
// −π), with the same comparisons as sorting the neighbour lists in the order added; then for
// every directed edge a→b the next one on the face to its left: b→c, c the neighbour of b
// before a.
void FaceAssembler::build_adjacency() {
  fill_slots();
  const std::size_t n_slots = nbr_.size();
  slot_of_.resize(n_slots);  // per directed edge (2 i + direction): its sorted slot
  nbr2_.resize(n_slots);
  half2_.resize(n_slots);
  for (int i = 0; i < int(gid_.size()); ++i) sort_neighbours(i);
  nbr_.swap(nbr2_);
  link_faces();
}

// Slots of the directed edges leaving each node (first_), in the order the edges were added:
// their heads (nbr_) and directed edge ids 2 i (a→b) or 2 i + 1 (b→a) (half_).
void FaceAssembler::fill_slots() {
  const int nl = int(gid_.size());
  first_.assign(std::size_t(nl) + 1, 0);
  for (const auto& [a, b] : edges_) {
    ++first_[std::size_t(a) + 1];
    ++first_[std::size_t(b) + 1];
  }
  for (int i = 0; i < nl; ++i) first_[std::size_t(i) + 1] += first_[std::size_t(i)];
  const std::size_t n_slots = 2 * edges_.size();
  fill_.assign(first_.begin(), first_.end() - 1);
  nbr_.resize(n_slots);
  half_.resize(n_slots);
  for (std::size_t i = 0; i < edges_.size(); ++i) {  // in the order added
    const auto [a, b] = edges_[i];
    const int sa = fill_[std::size_t(a)]++, sb = fill_[std::size_t(b)]++;
    nbr_[std::size_t(sa)] = b;
    nbr_[std::size_t(sb)] = a;
    half_[std::size_t(sa)] = int(2 * i);  // a→b
    half_[std::size_t(sb)] = int(2 * i + 1);
  }
}

// Writes node i's slots in counter-clockwise order into nbr2_ and half2_, and their new
// places into slot_of_.
void FaceAssembler::sort_neighbours(int i) {
  const int s0 = first_[std::size_t(i)], s1 = first_[std::size_t(i) + 1];
  if (s1 - s0 < 2) {
    for (int s = s0; s < s1; ++s) {
      nbr2_[std::size_t(s)] = nbr_[std::size_t(s)];
      half2_[std::size_t(s)] = half_[std::size_t(s)];
      slot_of_[std::size_t(half_[std::size_t(s)])] = s;
    }
    return;
  }
  const int deg = s1 - s0;
  if (!sort_by_pseudo_angle(i, s0, deg)) sort_by_atan2(i, s0, s1);
  for (int r = 0; r < deg; ++r) {
    const std::size_t from = std::size_t(order_[std::size_t(r)]), to = std::size_t(s0 + r);
    nbr2_[to] = nbr_[from];
    half2_[to] = half_[from];
    slot_of_[std::size_t(half_[from])] = int(to);
  }
}

// Sorts node i's slots s0 .. s0 + deg - 1 into order_ by a pseudo-angle: increasing with atan2
// on (−π, π] (from −π at y = −0, x < 0), |d key / d angle| ∈ [1/2, 1]. Where all neighbours'
// keys differ by more than 1e-12, their atan2 (a few ulp off at most) differ too and come in the
// same order: that order is the only one a sort by atan2 can return, and this returns true.
// Otherwise (near ties, zero vectors) false: the order must come from atan2 itself.
bool FaceAssembler::sort_by_pseudo_angle(int i, int s0, int deg) {
  key_.resize(std::size_t(deg));
  order_.resize(std::size_t(deg));
  bool exact = true;
  for (int r = 0; r < deg; ++r) {
    const Eigen::Vector2d d = p_[std::size_t(nbr_[std::size_t(s0 + r)])] - p_[std::size_t(i)];
    const double l1 = std::abs(d.x()) + std::abs(d.y());
    if (!(l1 > 0.0) || !std::isfinite(l1)) exact = false;
    const double key = 1.0 - d.x() / l1;  // [0, 2] on the upper half plane
    key_[std::size_t(r)] = std::signbit(d.y()) ? -key : key;
    order_[std::size_t(r)] = s0 + r;
  }
  if (!exact) return false;
  if (deg <= 16) {  // insertion sort (degrees are mostly 2 or 3)
    for (int r = 1; r < deg; ++r) {
      const double k = key_[std::size_t(r)];
      const int o = order_[std::size_t(r)];
      int q = r;
      for (; q > 0 && key_[std::size_t(q - 1)] > k; --q) {
        key_[std::size_t(q)] = key_[std::size_t(q - 1)];
        order_[std::size_t(q)] = order_[std::size_t(q - 1)];
      }
      key_[std::size_t(q)] = k;
      order_[std::size_t(q)] = o;
    }
  } else {
    ang_.clear();
    for (int r = 0; r < deg; ++r) ang_.emplace_back(key_[std::size_t(r)], order_[std::size_t(r)]);
    std::sort(ang_.begin(), ang_.end(), by_angle);
    for (int r = 0; r < deg; ++r) {
      key_[std::size_t(r)] = ang_[std::size_t(r)].first;
      order_[std::size_t(r)] = ang_[std::size_t(r)].second;
    }
  }
  for (int r = 1; r < deg; ++r) {  // the order is atan2's if the keys are apart
    if (!(key_[std::size_t(r)] - key_[std::size_t(r - 1)] > 1e-12)) return false;
  }
  return true;
}

// Sorts node i's slots s0 .. s1 - 1 into order_ by atan2, from the order added (as the
// comparisons of a sort by atan2 decide near ties).
void FaceAssembler::sort_by_atan2(int i, int s0, int s1) {
  ang_.clear();
  for (int s = s0; s < s1; ++s) {
    const Eigen::Vector2d d = p_[std::size_t(nbr_[std::size_t(s)])] - p_[std::size_t(i)];
    ang_.emplace_back(std::atan2(d.y(), d.x()), s);
  }
  std::sort(ang_.begin(), ang_.end(), by_angle);
  for (int r = 0; r < s1 - s0; ++r) order_[std::size_t(r)] = ang_[std::size_t(r)].second;
}

// Per slot (sorted): the label left of its directed edge a→b, and the next directed edge
// around that face, b→c with c the neighbour of b before a.
void FaceAssembler::link_faces() {
  const std::size_t n_slots = nbr_.size();
  left_.resize(n_slots);
  next_.resize(n_slots);
  for (std::size_t s = 0; s < n_slots; ++s) {
    const int h = half2_[s];
    const auto& labels = edge_labels_[std::size_t(h / 2)];
    left_[s] = h % 2 == 0 ? labels.first : labels.second;
    const int r = slot_of_[std::size_t(h ^ 1)];  // b→a
    const std::size_t b = std::size_t(nbr_[s]);
    next_[s] = r == first_[b] ? first_[b + 1] - 1 : r - 1;
  }
}

// Walks the faces of the planar graph (each directed edge once, the face on its left), from
// every node in order and its edges counter-clockwise; keeps the bounded ones.
void FaceAssembler::walk(Index g, Chunk& out, FaceSides* sides) {
  const int nl = int(gid_.size());
  seen_.assign(nbr_.size(), 0);
  for (int a0 = 0; a0 < nl; ++a0) {
    for (int s0 = first_[std::size_t(a0)]; s0 < first_[std::size_t(a0) + 1]; ++s0) {
      if (seen_[std::size_t(s0)]) continue;
      const std::size_t node_begin = out.nodes.size();
      const std::size_t run_begin = sides ? sides->runs.size() : 0;
      Index label = kInvalidIndex;
      double area2 = 0.0;
      bool outside = false;
      int a = a0, s = s0;
      for (int guard = 0; guard <= 2 * nl + 4; ++guard) {
        seen_[std::size_t(s)] = 1;
        out.nodes.push_back(a);
        const int b = nbr_[std::size_t(s)];
        const Index lab = left_[std::size_t(s)];
        if (lab == -2) outside = true;
        if (lab >= 0 && label < 0) label = lab;
        const Eigen::Vector2d &pa = p_[std::size_t(a)], &pb = p_[std::size_t(b)];
        area2 += pa.x() * pb.y() - pb.x() * pa.y();
        if (sides) {  // on a side of g (both ends on side k, going ccw): for labels
          for (int k = 0; k < 3; ++k) {
            const Eigen::Vector3d &ba = bary_[std::size_t(a)], &bb = bary_[std::size_t(b)];
            if (ba[(k + 2) % 3] == 0.0 && bb[(k + 2) % 3] == 0.0) {
              const double ta = ba[(k + 1) % 3], tb = bb[(k + 1) % 3];
              if (ta < tb) sides->runs.push_back({k, ta, tb});
            }
          }
        }
        s = next_[std::size_t(s)];
        a = b;
        if (s == s0) break;  // back at a0 → b0
      }
      if (outside || !(area2 > 0.0)) {
        out.nodes.resize(node_begin);
        if (sides) sides->runs.resize(run_begin);
        continue;
      }
      const std::size_t m = out.nodes.size() - node_begin;
      for (std::size_t i = node_begin; i < out.nodes.size(); ++i) {
        out.nodes[i] = gid_[std::size_t(out.nodes[i])];
      }
      out.polys.push_back({g, label, Index(node_begin)});
      out.n_out_faces += m == 3 ? 1 : m;
      out.n_extra += m == 3 ? 0 : 1;
      if (label < 0 && (out.unlabeled_faces.empty() || out.unlabeled_faces.back() != g)) {
        out.unlabeled_faces.push_back(g);
      }
      if (sides) sides->begin.push_back(Index(sides->runs.size()));
    }
  }
}

void FaceAssembler::assemble(Index g, Chunk& out, FaceSides* sides) {
  start_face(g);
  gather_segments(g);
  edges_.clear();
  edge_labels_.clear();
  edge_seen_.reset(2 * gid_.size() + inner_.size() + 3);
  label_sides(g);
  add_inner_edges();
  lay_out(g);
  build_adjacency();
  walk(g, out, sides);
}

// Clears the buffers for input face g (sized for its segments) and makes its corner nodes.
void FaceAssembler::start_face(Index g) {
  const IntrinsicTriangulation& in = *x_.in;
  for (int k = 0; k < 3; ++k) cv_[k] = in.tail(3 * g + k);
  const Index s_begin = (*x_.seg_begin)[g], s_end = (*x_.seg_begin)[g + 1];
  const std::size_t max_nodes = 2 * std::size_t(s_end - s_begin) + 3;
  gid_.clear();
  bary_.clear();
  next_in_bucket_.clear();
  for (auto& on : on_side_) on.clear();
  local_.reset(max_nodes);
  bucket_.reset(2 * max_nodes);
  for (int k = 0; k < 3; ++k) node(cv_[k], Eigen::Vector3d::Unit(k), 0);
}

// Makes the nodes of g's traced segments and keeps those not along a side of g (inner_, with
// their intrinsic halfedges in inner_h_).
void FaceAssembler::gather_segments(Index g) {
  const IntrinsicTriangulation& in = *x_.in;
  const Index s_begin = (*x_.seg_begin)[g], s_end = (*x_.seg_begin)[g + 1];
  inner_.clear();
  inner_h_.clear();
  SegmentRef prev{kInvalidIndex, kInvalidIndex};
  int prev_b = -1;
  const SegmentRef* segs = x_.segs->data();
  const EdgePath* edges = x_.edges->data();
  for (Index s = s_begin; s < s_end; ++s) {
    // the segments of g belong to edges all over memory: fetch ahead
    if (s + 16 < s_end) prefetch(&edges[segs[s + 16].e]);
    if (s + 8 < s_end) {
      const EdgePath& ahead = edges[segs[s + 8].e];
      prefetch(ahead.points + segs[s + 8].i);
      prefetch(ahead.points + segs[s + 8].i + 1);
      prefetch(x_.created->data() + 2 * std::size_t(ahead.base - x_.nvi + segs[s + 8].i));
    }
    if (s + 4 < s_end) {  // the sides to_face() looks at
      prefetch(in.twins().data() + 3 * edges[segs[s + 4].e].points[segs[s + 4].i + 1].face);
    }
    const SegmentRef sg = segs[s];
    const EdgePath& ep = edges[sg.e];
    const SurfacePoint* path = ep.points;
    const Index h = ep.h;
    const std::size_t n = std::size_t(ep.n), i = std::size_t(sg.i);
    const Index ia = i == 0 ? ep.tail : ep.base + Index(i - 1);
    const Index ib = i + 2 == n ? ep.head : ep.base + Index(i);
    Eigen::Vector3d bb;
    to_face(in, path[i + 1], g, bb);  // checked when the segments were gathered
    // path point i both ends the previous segment of g and starts this one: the same node
    const int a =
        i > 0 && prev.e == sg.e && prev.i == sg.i - 1 ? prev_b : node(ia, path[i].bary, 0);
    const int b = node(ib, bb, 1);
    prev = sg;
    prev_b = b;
    if (a == b) continue;
    bool along_side = false;
    for (int j = 0; j < 3; ++j) {
      if (bary_[std::size_t(a)][j] == 0.0 && bary_[std::size_t(b)][j] == 0.0) along_side = true;
    }
    if (along_side) continue;  // labels its side (side labels)
    inner_.emplace_back(a, b);
    inner_h_.push_back(h);
  }
}

// Adds the inner segments as edges labelled with the intrinsic faces on their two sides.
void FaceAssembler::add_inner_edges() {
  const IntrinsicTriangulation& tri = *x_.tri;
  // two segments with the same ends need both ends shared by two segments or more
  uses_.assign(gid_.size(), 0);
  for (const auto& [a, b] : inner_) {
    ++uses_[std::size_t(a)];
    ++uses_[std::size_t(b)];
  }
  for (std::size_t i = 0; i < inner_.size(); ++i) {
    const Index h = inner_h_[i];
    const auto [a, b] = inner_[i];
    add_edge(a, b, T::face(h), tri.twin(h) == kInvalidIndex ? -1 : T::face(tri.twin(h)),
             uses_[std::size_t(a)] > 1 && uses_[std::size_t(b)] > 1);
  }
}

// The nodes' 2D positions in g's layout (p_).
void FaceAssembler::lay_out(Index g) {
  Eigen::Vector2d corner[3];
  face_layout(*x_.in, g, corner);
  p_.resize(gid_.size());
  for (std::size_t i = 0; i < gid_.size(); ++i) {
    p_[i] = bary_[i][0] * corner[0] + bary_[i][1] * corner[1] + bary_[i][2] * corner[2];
  }
}

// ---- The phases of common_subdivision().

// Every intrinsic edge traced over the input.
struct Traces {
  std::vector<Index> traced;                     // per edge: the halfedge traced
  std::vector<std::vector<SurfacePoint>> paths;  // per edge: its path over the input
};

// Throws InvalidInput: the paths traced so far have `points` points, more than max_points.
void throw_over_budget(std::size_t points, double max_points, double budget) {
  std::ostringstream m;
  m << std::setprecision(3) << "the traced intrinsic edges cross the input " << double(points)
    << " times (so far), more than the memory budget of " << budget / 1e9 << " GB pays for ("
    << max_points << " at " << kSubdivisionBytesPerCrossing
    << " bytes each): refine less, or raise the budget (max_memory_bytes, `--memory-budget`)";
  throw InvalidInput(m.str());
}

// Traces every edge from the halfedge trace_edge() would use, counting path points against
// the budget; any failed trace (or the budget) ends the call, and the other threads stop.
Traces trace_edges(const SignpostTriangulation& st, double budget, std::size_t& crossings) {
  const IntrinsicTriangulation& tri = st.intrinsic();
  const Index n_in = st.n_input_vertices(), ne = tri.n_edges();
  Traces t{std::vector<Index>(ne), std::vector<std::vector<SurfacePoint>>(ne)};
  const double max_points = budget / kSubdivisionBytesPerCrossing - double(tri.n_vertices()) -
                            double(st.input().n_faces());
  std::atomic<std::size_t> points{0};
  FirstError failure;  // transport out of the OpenMP loop: any exception ends the call
#pragma omp parallel for schedule(dynamic, 256)
  for (Index e = 0; e < ne; ++e) {
    Index h = tri.edge_halfedge(e);
    if (tri.tail(h) >= n_in && tri.head(h) < n_in && tri.twin(h) != kInvalidIndex) h = tri.twin(h);
    t.traced[e] = h;
    if (failure.failed()) continue;  // the call fails: no more paths (their memory) needed
    try {
      t.paths[e] = st.trace_halfedge(h);
      const std::size_t n = t.paths[e].size() >= 2 ? t.paths[e].size() - 2 : 0;
      const std::size_t total = points.fetch_add(n) + n;
      if (double(total) > max_points) throw_over_budget(total, max_points, budget);
    } catch (...) {
      failure.record_current("edge " + std::to_string(e));
    }
  }
  failure.rethrow_if_any("common_subdivision");
  crossings = points.load();
  return t;
}

// A trace leaving (or reaching) a vertex that lies on an input side records a crossing at the
// vertex itself: drops it, so that the vertex is the path's end in the face the segment really
// runs in (else that face gets a second node at the vertex's place and overlapping pieces).
void drop_crossings_at_ends(const SignpostTriangulation& st,
                            std::vector<std::vector<SurfacePoint>>& paths) {
  const IntrinsicTriangulation& tri = st.intrinsic();
  const Index ne = tri.n_edges();
#pragma omp parallel for schedule(dynamic, 256)
  for (Index e = 0; e < ne; ++e) {
    auto& path = paths[e];
    const double tol = 1e-10 * tri.length(e);
    auto same_place = [&](const SurfacePoint& a, const SurfacePoint& b) {
      return (st.position(a) - st.position(b)).norm() <= tol;
    };
    while (path.size() > 2 && same_place(path[0], path[1])) path.erase(path.begin());
    while (path.size() > 2 && same_place(path[path.size() - 2], path.back())) path.pop_back();
  }
}

// Node ids: input vertices, inserted vertices, then one per interior path point; segments.
struct Numbering {
  std::vector<Index> offset;      // per edge, + 1: its first interior path point (node nvi + it)
  std::vector<Index> seg_offset;  // per edge, + 1: its first segment
  Index n_points = 0;             // path point nodes
  Index n_segs = 0;
};

// Numbers the interior path points and the segments edge by edge.
Numbering number_path_points(const std::vector<std::vector<SurfacePoint>>& paths) {
  const Index ne = Index(paths.size());
  Numbering num{std::vector<Index>(ne + 1, 0), std::vector<Index>(ne + 1, 0)};
  for (Index e = 0; e < ne; ++e) {
    const std::size_t n = paths[e].size();
    num.offset[e + 1] = num.offset[e] + Index(std::max<std::size_t>(n, 2) - 2);
    num.seg_offset[e + 1] = num.seg_offset[e] + Index(std::max<std::size_t>(n, 1) - 1);
  }
  num.n_points = num.offset[ne];
  num.n_segs = num.seg_offset[ne];
  return num;
}

// A side label for input face `target`, with the key that orders a face's labels: (face of the
// segment, edge, segment, side, that face first).
struct LabelRecord {
  Index target, g, e, i;
  int k, other;
  SideLabel label;
  bool operator<(const LabelRecord& r) const {
    return std::tie(g, e, i, k, other) < std::tie(r.g, r.e, r.i, r.k, r.other);
  }
};

// The coordinates of a node (id, b) in face g that are zero once snapped, as a bit mask (a
// corner id is its corner; others: below kSideTol).
int zero_mask(const IntrinsicTriangulation& in, Index id, Index g, const Eigen::Vector3d& b) {
  for (int k = 0; k < 3; ++k) {
    if (id == in.tail(3 * g + k)) return 7 & ~(1 << k);
  }
  return (b[0] < kSideTol ? 1 : 0) | (b[1] < kSideTol ? 2 : 0) | (b[2] < kSideTol ? 4 : 0);
}

// The barycentric coordinates of a node (id, b) in face g once snapped to a corner or sides.
Eigen::Vector3d snapped(const IntrinsicTriangulation& in, Index id, Index g, Eigen::Vector3d b) {
  for (int k = 0; k < 3; ++k) {
    if (id == in.tail(3 * g + k)) return Eigen::Vector3d(Eigen::Vector3d::Unit(k));
  }
  for (int k = 0; k < 3; ++k) {
    if (b[k] < kSideTol) b[k] = 0.0;
  }
  return Eigen::Vector3d(b / b.sum());
}

// Appends the side labels of segment i of edge e (traced from h, in face g, from snapped ba to
// snapped bs) for each side of g it runs along: for g and for the face across that side.
void add_side_labels(const IntrinsicTriangulation& tri, const IntrinsicTriangulation& in, Index h,
                     Index e, Index i, Index g, const Eigen::Vector3d& ba,
                     const Eigen::Vector3d& bs, std::vector<LabelRecord>& out) {
  for (int k = 0; k < 3; ++k) {
    if (ba[(k + 2) % 3] != 0.0 || bs[(k + 2) % 3] != 0.0) continue;
    const double ta = ba[(k + 1) % 3], tb = bs[(k + 1) % 3];
    if (ta == tb) continue;
    const Index tw_h = tri.twin(h);
    const Index left_face = T::face(h);
    const Index right_face = tw_h == kInvalidIndex ? kInvalidIndex : T::face(tw_h);
    // g's interior is left of its side run corner k → k+1 (t increasing)
    out.push_back({g,
                   g,
                   e,
                   i,
                   k,
                   0,
                   {k, std::min(ta, tb), std::max(ta, tb), ta < tb ? left_face : right_face}});
    const Index tw = in.twin(3 * g + k);
    if (tw != kInvalidIndex) {
      out.push_back({T::face(tw),
                     g,
                     e,
                     i,
                     k,
                     1,
                     {int(T::side(tw)), 1.0 - std::max(ta, tb), 1.0 - std::min(ta, tb),
                      ta < tb ? right_face : left_face}});
    }
  }
}

// The side label records of traced edge e (collect_label_records()), appended to `mine`.
void label_records_of_edge(const SignpostTriangulation& st, const Traces& traces,
                           const Numbering& num, Index e, std::vector<Index>& seg_face,
                           std::vector<LabelRecord>& mine, bool& my_jumps) {
  const IntrinsicTriangulation& tri = st.intrinsic();
  const IntrinsicTriangulation& in = st.input();
  const Index nvi = tri.n_vertices();
  const auto& path = traces.paths[e];
  const Index h = traces.traced[e];
  const std::size_t n = path.size();
  for (std::size_t i = 0; i + 1 < n; ++i) {
    const Index g = path[i].face;
    seg_face[std::size_t(num.seg_offset[e]) + i] = g;
    Eigen::Vector3d bb;
    if (!to_face(in, path[i + 1], g, bb)) {
      my_jumps = true;
      continue;
    }
    const Index ia = i == 0 ? tri.tail(h) : nvi + num.offset[e] + Index(i - 1);
    const Index ib = i + 2 == n ? tri.head(h) : nvi + num.offset[e] + Index(i);
    if ((zero_mask(in, ia, g, path[i].bary) & zero_mask(in, ib, g, bb)) == 0) continue;
    add_side_labels(tri, in, h, e, Index(i), g, snapped(in, ia, g, path[i].bary),
                    snapped(in, ib, g, bb), mine);
  }
}

// Per segment its input face (seg_face); intrinsic edges that run along an input side label
// that side on both of its faces (the trace records such a segment in one of the two faces
// only): their records, unordered. @throws Error when a path jumps between faces
std::vector<LabelRecord> collect_label_records(const SignpostTriangulation& st,
                                               const Traces& traces, const Numbering& num,
                                               bool parallel, std::vector<Index>& seg_face) {
  const Index ne = st.intrinsic().n_edges();
  std::vector<LabelRecord> records;
  bool jumps = false;
  FirstError failure;  // std::bad_alloc may not leave the region
#pragma omp parallel if (parallel)
  {
    std::vector<LabelRecord> mine;
    bool my_jumps = false;
#pragma omp for schedule(dynamic, 1024) nowait
    for (Index e = 0; e < ne; ++e) {
      if (failure.failed()) continue;
      try {
        label_records_of_edge(st, traces, num, e, seg_face, mine, my_jumps);
      } catch (...) {
        failure.record_current("edge " + std::to_string(e));
      }
    }
#pragma omp critical(ifem_common_subdivision_records)
    {
      try {
        records.insert(records.end(), mine.begin(), mine.end());
      } catch (...) {
        failure.record_current("merging the side labels");
      }
      jumps = jumps || my_jumps;
    }
  }
  failure.rethrow_if_any("common_subdivision");
  if (jumps) throw Error("common_subdivision: traced path jumps between faces");
  return records;
}

// The side labels grouped by input face (label_begin: per face, + 1), each face's in the
// order of its records' key.
void group_labels(const std::vector<LabelRecord>& records, Index nf,
                  std::vector<Index>& label_begin, std::vector<SideLabel>& labels) {
  label_begin.assign(std::size_t(nf) + 1, 0);
  for (const LabelRecord& r : records) ++label_begin[std::size_t(r.target) + 1];
  for (Index g = 0; g < nf; ++g) label_begin[g + 1] += label_begin[g];
  labels.resize(records.size());
  std::vector<LabelRecord> by_face(records.size());
  std::vector<Index> fill(label_begin.begin(), label_begin.end() - 1);
  for (const LabelRecord& r : records) by_face[std::size_t(fill[r.target]++)] = r;
  for (Index g = 0; g < nf; ++g) {
    const auto first = by_face.begin() + label_begin[g];
    const auto last = by_face.begin() + label_begin[g + 1];
    std::sort(first, last);
    for (auto it = first; it != last; ++it) labels[std::size_t(it - by_face.begin())] = it->label;
  }
}

// The segments grouped by input face (seg_begin: per face, + 1), in the order of (edge,
// segment).
void group_segments(const std::vector<Index>& seg_face, const std::vector<Index>& seg_offset,
                    Index nf, std::vector<Index>& seg_begin, std::vector<SegmentRef>& segs) {
  const Index ne = Index(seg_offset.size()) - 1;
  seg_begin.assign(std::size_t(nf) + 1, 0);
  for (const Index g : seg_face) ++seg_begin[std::size_t(g) + 1];
  for (Index g = 0; g < nf; ++g) seg_begin[g + 1] += seg_begin[g];
  segs.resize(seg_face.size());
  std::vector<Index> fill(seg_begin.begin(), seg_begin.end() - 1);
  for (Index e = 0; e < ne; ++e) {
    for (Index s = seg_offset[e]; s < seg_offset[e + 1]; ++s) {
      segs[std::size_t(fill[seg_face[std::size_t(s)]]++)] = {e, s - seg_offset[e]};
    }
  }
}

// Each traced edge as the per-face assembly reads it.
std::vector<EdgePath> make_edge_paths(const IntrinsicTriangulation& tri, const Traces& traces,
                                      const Numbering& num) {
  const Index nvi = tri.n_vertices(), ne = tri.n_edges();
  std::vector<EdgePath> edge_paths(std::size_t(ne), EdgePath{});
  for (Index e = 0; e < ne; ++e) {
    const Index h = traces.traced[e];
    const std::vector<SurfacePoint>& path = traces.paths[e];
    edge_paths[e] = {path.data(), Index(path.size()), nvi + num.offset[e],
                     tri.tail(h), tri.head(h),        h};
  }
  return edge_paths;
}

// The input faces of chunk c assembled into `out`.
void assemble_chunk(const Inputs& inputs, Index nf, Index c, FaceAssembler& assembler, Chunk& out) {
  const std::vector<Index>& seg_begin = *inputs.seg_begin;
  const Index g0 = c * kChunkFaces, g1 = std::min(nf, g0 + kChunkFaces);
  out.face_poly_begin.reserve(std::size_t(g1 - g0) + 1);
  // typically a polygon per segment and face, with 2 nodes per segment and 3 per face
  const std::size_t n_seg = std::size_t(seg_begin[g1] - seg_begin[g0]);
  out.polys.reserve(n_seg / 2 + std::size_t(g1 - g0) + 16);
  out.nodes.reserve(2 * n_seg + 3 * std::size_t(g1 - g0) + 64);
  for (Index g = g0; g < g1; ++g) {
    out.face_poly_begin.push_back(Index(out.polys.size()));
    assembler.assemble(g, out, nullptr);
  }
  out.face_poly_begin.push_back(Index(out.polys.size()));
}

// Per input face its planar graph and bounded faces, in chunks of kChunkFaces faces.
std::vector<Chunk> assemble_faces(const Inputs& inputs, Index nf, bool parallel) {
  const Index n_chunks = (nf + kChunkFaces - 1) / kChunkFaces;
  std::vector<Chunk> chunks(std::size_t(n_chunks), Chunk{});
  FirstError failure;  // std::bad_alloc may not leave the region
#pragma omp parallel if (parallel)
  {
    FaceAssembler assembler(inputs);
#pragma omp for schedule(dynamic, 1)
    for (Index c = 0; c < n_chunks; ++c) {
      if (failure.failed()) continue;
      try {
        assemble_chunk(inputs, nf, c, assembler, chunks[std::size_t(c)]);
      } catch (...) {
        failure.record_current("input faces from " + std::to_string(c * kChunkFaces));
      }
    }
  }
  failure.rethrow_if_any("common_subdivision");
  return chunks;
}

// The polygons of input face g: (chunk, first polygon, end) in that chunk.
std::tuple<Index, Index, Index> face_polys(const std::vector<Chunk>& chunks, Index g) {
  const Chunk& c = chunks[std::size_t(g / kChunkFaces)];
  const Index r = g % kChunkFaces;
  return std::make_tuple(g / kChunkFaces, c.face_poly_begin[std::size_t(r)],
                         c.face_poly_begin[std::size_t(r) + 1]);
}

// The polygon sides of the faces in `faces` and of their neighbours (assembled again); the
// other faces' entries stay empty.
std::vector<FaceSides> sides_near(const Inputs& inputs, Index nf, const std::vector<Chunk>& chunks,
                                  const std::vector<Index>& faces) {
  const IntrinsicTriangulation& in = *inputs.in;
  std::vector<FaceSides> sides(static_cast<std::size_t>(nf));
  std::vector<char> has_sides(std::size_t(nf), 0);
  FaceAssembler assembler(inputs);
  Chunk scratch;
  auto need = [&](Index g) {
    if (has_sides[std::size_t(g)]) return;
    has_sides[std::size_t(g)] = 1;
    scratch.polys.clear();
    scratch.nodes.clear();
    scratch.unlabeled_faces.clear();
    sides[std::size_t(g)].begin.assign(1, 0);
    assembler.assemble(g, scratch, &sides[std::size_t(g)]);
    const auto [c, p0, p1] = face_polys(chunks, g);
    if (Index(scratch.polys.size()) != p1 - p0) {
      throw Error("common_subdivision: face " + std::to_string(g) + " assembled differently");
    }
  };
  for (const Index g : faces) {
    need(g);
    for (int k = 0; k < 3; ++k) {
      if (in.twin(3 * g + k) != kInvalidIndex) need(T::face(in.twin(3 * g + k)));
    }
  }
  return sides;
}

// The label across side run `run` of a polygon of face g: that of the last labelled polygon of
// the neighbouring face whose side run holds the run's midpoint, or -1.
Index label_across(const IntrinsicTriangulation& in, const std::vector<Chunk>& chunks,
                   const std::vector<FaceSides>& sides, Index g, const SideRun& run) {
  const Index tw = in.twin(3 * g + run.k);
  if (tw == kInvalidIndex) return kInvalidIndex;
  const double t = 1.0 - 0.5 * (run.t0 + run.t1);
  const int k2 = int(T::side(tw));
  const Index g2 = T::face(tw);
  const auto [c2, q0, q1] = face_polys(chunks, g2);
  const FaceSides& fs2 = sides[std::size_t(g2)];
  Index label = kInvalidIndex;
  for (Index q = q0; q < q1; ++q) {
    const Index lab_q = chunks[std::size_t(c2)].polys[std::size_t(q)].label;
    if (lab_q < 0) continue;
    const Index r0 = fs2.begin[std::size_t(q - q0)];
    for (Index r3 = r0; r3 < fs2.begin[std::size_t(q - q0) + 1]; ++r3) {
      const SideRun& run3 = fs2.runs[std::size_t(r3)];
      if (run3.k == k2 && run3.t0 <= t && t <= run3.t1) label = lab_q;
    }
  }
  return label;
}

// Labels across input sides, for polygons with no traced segment on their boundary: repeated
// until no polygon gains one.
void label_across_sides(const Inputs& inputs, Index nf, std::vector<Chunk>& chunks) {
  const IntrinsicTriangulation& in = *inputs.in;
  std::vector<Index> unlabeled_faces;
  for (const Chunk& c : chunks) {
    unlabeled_faces.insert(unlabeled_faces.end(), c.unlabeled_faces.begin(),
                           c.unlabeled_faces.end());
  }
  if (unlabeled_faces.empty()) return;
  const std::vector<FaceSides> sides = sides_near(inputs, nf, chunks, unlabeled_faces);
  for (bool progress = true; progress;) {
    progress = false;
    for (const Index g : unlabeled_faces) {
      const auto [c, p0, p1] = face_polys(chunks, g);
      const FaceSides& fs = sides[std::size_t(g)];
      for (Index pi = p0; pi < p1; ++pi) {
        Index& label = chunks[std::size_t(c)].polys[std::size_t(pi)].label;
        if (label >= 0) continue;
        const Index r_end = fs.begin[std::size_t(pi - p0) + 1];
        for (Index ri = fs.begin[std::size_t(pi - p0)]; ri < r_end; ++ri) {
          const Index found = label_across(in, chunks, sides, g, fs.runs[std::size_t(ri)]);
          if (found >= 0) {
            label = found;
            break;
          }
        }
        if (label >= 0) progress = true;
      }
    }
  }
}

// Output node ids: intrinsic vertices keep theirs, then the path points some face made a node,
// in order; n_out: their number.
std::vector<Index> output_ids(Index nvi, Index n_points, const std::vector<unsigned char>& created,
                              Index& n_out) {
  std::vector<Index> id(std::size_t(nvi) + std::size_t(n_points), kInvalidIndex);
  for (Index v = 0; v < nvi; ++v) id[v] = v;
  n_out = nvi;
  for (Index q = 0; q < n_points; ++q) {
    if (created[2 * std::size_t(q)] || created[2 * std::size_t(q) + 1]) {
      id[std::size_t(nvi + q)] = n_out++;
    }
  }
  return id;
}

// Positions of the vertices (rows 0 .. nvi - 1) and of the path point nodes: a path point's
// is the one in the first face that made it a node (the face of the segment it starts, or of
// the one it ends, whichever is lower).
void place_nodes(const SignpostTriangulation& st, const Traces& traces, const Numbering& num,
                 const std::vector<unsigned char>& created, const std::vector<Index>& id,
                 bool parallel, Positions& positions) {
  const IntrinsicTriangulation& in = st.input();
  const Index n_in = st.n_input_vertices(), nvi = st.intrinsic().n_vertices();
  const Index ne = Index(traces.paths.size());
  for (Index v = 0; v < n_in; ++v) positions.row(v) = st.input_positions().row(v);
  for (Index v = n_in; v < nvi; ++v) {
    positions.row(v) = st.position(st.vertex_location(v)).transpose();
  }
#pragma omp parallel for schedule(dynamic, 1024) if (parallel)
  for (Index e = 0; e < ne; ++e) {
    const auto& path = traces.paths[e];
    for (std::size_t i = 1; i + 1 < path.size(); ++i) {
      const std::size_t q = std::size_t(num.offset[e]) + i - 1;
      const bool as_start = created[2 * q], as_end = created[2 * q + 1];
      if (!as_start && !as_end) continue;
      const Index g_start = path[i].face, g_end = path[i - 1].face;
      const bool use_start = as_start && (!as_end || g_start < g_end);
      const Index g = use_start ? g_start : g_end;
      Eigen::Vector3d b;
      if (use_start) {
        b = path[i].bary;
      } else {
        to_face(in, path[i], g, b);
      }
      b = snap_to_sides(b);
      Eigen::Vector3d x = Eigen::Vector3d::Zero();
      for (int k = 0; k < 3; ++k) {
        x += b[k] * st.input_positions().row(in.tail(3 * g + k)).transpose();
      }
      positions.row(id[std::size_t(nvi) + q]) = x.transpose();
    }
  }
}

// Fans the polygons of the chunks into cs.faces (already sized): a triangle as it is, a larger
// polygon around its centroid (a new vertex from n_out + its chunk's extra_base on), with
// face_base: per chunk, + 1, its first output face.
void emit_polygons(const SignpostTriangulation& st, const std::vector<Chunk>& chunks,
                   const std::vector<Index>& id, Index n_out,
                   const std::vector<std::size_t>& face_base,
                   const std::vector<std::size_t>& extra_base, bool parallel,
                   CommonSubdivision& cs) {
  const Index n_chunks = Index(chunks.size());
#pragma omp parallel for schedule(dynamic, 1) if (parallel)
  for (Index c = 0; c < n_chunks; ++c) {
    const Chunk& chunk = chunks[std::size_t(c)];
    std::size_t fo = face_base[c];
    Index ci = n_out + Index(extra_base[c]);
    for (std::size_t j = 0; j < chunk.polys.size(); ++j) {
      const PolyRec& poly = chunk.polys[j];
      const Index* nodes = chunk.nodes.data() + poly.node_begin;
      const std::size_t m = std::size_t(j + 1 < chunk.polys.size() ? chunk.polys[j + 1].node_begin
                                                                   : Index(chunk.nodes.size())) -
                            std::size_t(poly.node_begin);
      const Index fi = st.input_face_origin().empty() ? poly.input_face
                                                      : st.input_face_origin()[poly.input_face];
      auto emit = [&](Index a, Index b, Index c3) {
        cs.faces[fo] = {a, b, c3};
        cs.intrinsic_face[fo] = poly.label;
        cs.input_face[fo] = fi;
        ++fo;
      };
      if (m == 3) {
        emit(id[nodes[0]], id[nodes[1]], id[nodes[2]]);
        continue;
      }
      // a fan around the centroid: no sliver triangles from collinear nodes on the sides
      Eigen::Vector3d centroid = Eigen::Vector3d::Zero();
      for (std::size_t i = 0; i < m; ++i) centroid += cs.positions.row(id[nodes[i]]).transpose();
      cs.positions.row(ci) = (centroid / double(m)).transpose();
      for (std::size_t i = 0; i < m; ++i) emit(ci, id[nodes[i]], id[nodes[(i + 1) % m]]);
      ++ci;
    }
  }
}

// The output mesh: compact nodes (input vertices keep their ids), fanned polygons.
CommonSubdivision make_output(const SignpostTriangulation& st, const Traces& traces,
                              const Numbering& num, const std::vector<unsigned char>& created,
                              const std::vector<Chunk>& chunks, bool parallel) {
  const Index nvi = st.intrinsic().n_vertices();
  const Index n_chunks = Index(chunks.size());
  Index n_out = 0;
  const std::vector<Index> id = output_ids(nvi, num.n_points, created, n_out);
  std::vector<std::size_t> face_base(std::size_t(n_chunks) + 1, 0), extra_base(face_base);
  for (Index c = 0; c < n_chunks; ++c) {
    face_base[c + 1] = face_base[c] + chunks[std::size_t(c)].n_out_faces;
    extra_base[c + 1] = extra_base[c] + chunks[std::size_t(c)].n_extra;
  }
  CommonSubdivision cs;
  cs.positions.resize(n_out + Index(extra_base[n_chunks]), 3);
  place_nodes(st, traces, num, created, id, parallel, cs.positions);
  // sequential: an allocation failure (std::bad_alloc) may not leave an OpenMP region
  cs.faces.resize(face_base[n_chunks]);
  cs.intrinsic_face.resize(face_base[n_chunks]);
  cs.input_face.resize(face_base[n_chunks]);
  emit_polygons(st, chunks, id, n_out, face_base, extra_base, parallel, cs);
  return cs;
}

}  // namespace

CommonSubdivision common_subdivision(const SignpostTriangulation& st, double max_memory_bytes) {
  if (!(max_memory_bytes >= 0.0)) {
    throw InvalidInput("common_subdivision: max_memory_bytes must be ≥ 0 (0: automatic)");
  }
  const IntrinsicTriangulation& tri = st.intrinsic();
  const IntrinsicTriangulation& in = st.input();
  const Index nf = in.n_faces();
  // ---- trace every edge
  std::size_t crossings = 0;
  Traces traces = trace_edges(
      st, max_memory_bytes > 0.0 ? max_memory_bytes : default_memory_budget(), crossings);
  drop_crossings_at_ends(st, traces.paths);
  // ---- node ids and segments
  const Numbering num = number_path_points(traces.paths);
  const bool parallel = num.n_segs >= kParallelMin;
  // ---- per segment its input face; side labels grouped by face
  std::vector<Index> seg_face(num.n_segs);
  std::vector<Index> label_begin;
  std::vector<SideLabel> labels;
  group_labels(collect_label_records(st, traces, num, parallel, seg_face), nf, label_begin, labels);
  // ---- segments grouped by input face
  std::vector<Index> seg_begin;
  std::vector<SegmentRef> segs;
  group_segments(seg_face, num.seg_offset, nf, seg_begin, segs);
  std::vector<Index>().swap(seg_face);
  const std::vector<EdgePath> edge_paths = make_edge_paths(tri, traces, num);
  // ---- per input face: planar graph, its bounded faces; labels across input sides
  std::vector<unsigned char> created(2 * std::size_t(num.n_points), 0);
  const Inputs inputs{&tri,  &in,          tri.n_vertices(), &edge_paths, &seg_begin,
                      &segs, &label_begin, &labels,          &created};
  std::vector<Chunk> chunks = assemble_faces(inputs, nf, parallel);
  label_across_sides(inputs, nf, chunks);
  // ---- output
  CommonSubdivision cs = make_output(st, traces, num, created, chunks, parallel);
  cs.crossings = crossings;
  return cs;
}

void write_common_subdivision_ply(const std::string& path, const CommonSubdivision& cs,
                                  bool binary) {
  if (cs.positions.rows() > INT32_MAX || cs.faces.size() > std::size_t(INT32_MAX)) {
    throw IoError(path + ": too many vertices for 32-bit ids");
  }
  std::FILE* f = io::detail::open_temporary(path, binary);
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
  io::detail::close_and_rename(f, true, path);
}

}  // namespace ifem::intrinsic
