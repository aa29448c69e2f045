#include "intrinsic/refine/signpost.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <limits>
#include <string>
#include <utility>

#include "intrinsic/core/first_error.h"
#include "intrinsic/core/geometry.h"
#include "intrinsic/io/detail.h"

namespace ifem::intrinsic {
namespace {

using T = IntrinsicTriangulation;

Index trace_cap(const IntrinsicTriangulation& tri) { return 4 * tri.n_faces() + 1000; }

// Clamps barycentric coordinates to ≥ 0 and rescales them to sum 1 (unless all are zero).
void clamp_normalize(Eigen::Vector3d& x) {
  x = x.cwiseMax(0.0);
  const double s = x.sum();
  if (s > 0.0) x /= s;
}

// Barycentric velocity of the unit direction d in a face laid out at p (Σ db = 0,
// Σ db_i p_i = d).
Eigen::Vector3d barycentric_velocity(const Eigen::Vector2d p[3], const Eigen::Vector2d& d) {
  const double db2 = d.y() / p[2].y();
  const double db1 = (d.x() - db2 * p[2].x()) / p[1].x();
  return Eigen::Vector3d(-db1 - db2, db1, db2);
}

// The coordinate k that a line from b with barycentric velocity db drives to zero first (it
// leaves the face through side k + 1), skipping k = excl and, when only ≥ 0, every k but only;
// -1 if none. t_exit: the distance to it (infinity if none).
int first_exit(const Eigen::Vector3d& b, const Eigen::Vector3d& db, int excl, int only,
               double& t_exit) {
  const double tol = 1e-12 * db.cwiseAbs().maxCoeff();
  int k_exit = -1;
  t_exit = std::numeric_limits<double>::infinity();
  for (int k = 0; k < 3; ++k) {
    if (k == excl || (only >= 0 && k != only) || !(db[k] < -tol)) continue;
    const double t = std::max(b[k], 0.0) / -db[k];
    if (t < t_exit) {
      t_exit = t;
      k_exit = k;
    }
  }
  return k_exit;
}

// Ends the trace at (f, b) heading d.
void finish_trace(TraceResult& r, Index f, const Eigen::Vector3d& b, const Eigen::Vector2d& d,
                  bool record_path) {
  r.end = {f, b};
  r.direction = d;
  if (record_path) r.path.push_back(r.end);
}

// Carries the line across side s of face f (unit vector e along it, crossed at b) into the
// face of its twin tw: f, b, d and p (the layout) become that face's, excl its side's
// opposite corner.
void unfold_across(const IntrinsicTriangulation& tri, Index tw, int s, const Eigen::Vector2d& e,
                   Index& f, Eigen::Vector3d& b, Eigen::Vector2d& d, Eigen::Vector2d p[3],
                   int& excl) {
  const int s1 = (s + 1) % 3;
  const double cs = d.dot(e), sn = cross2(e, d);
  const double u = b[s1] / (b[s] + b[s1]);
  const Index g = T::face(tw);
  const int s2 = T::side(tw);
  Eigen::Vector3d nb = Eigen::Vector3d::Zero();
  nb[s2] = u;
  nb[(s2 + 1) % 3] = 1.0 - u;
  face_layout(tri, g, p);
  const Eigen::Vector2d e2 = (p[(s2 + 1) % 3] - p[s2]).normalized();
  const Eigen::Vector2d e2perp(-e2.y(), e2.x());
  d = -(cs * e2 + sn * e2perp);
  f = g;
  b = nb;
  excl = (s2 + 2) % 3;
}

}  // namespace

TraceResult trace_straight(const IntrinsicTriangulation& tri, const SurfacePoint& start,
                           Eigen::Vector2d dir, double distance, int start_corner,
                           bool slide_on_boundary, bool record_path, Index max_steps,
                           const std::vector<char>* stop_edges) {
  TraceResult r;
  Index f = start.face;
  Eigen::Vector3d b = start.bary;
  Eigen::Vector2d d = dir.normalized();
  double rem = std::max(distance, 0.0);
  const double end_slack = 1e-10 * rem;
  // starting at a corner, the line may first leave only through the opposite side
  int only = start_corner;
  int excl = -1;
  if (record_path) r.path.push_back(start);
  Eigen::Vector2d p[3];
  face_layout(tri, f, p);
  for (Index step = 0;; ++step) {
    if (step > max_steps) {
      throw TraceError("trace: gave up after " + std::to_string(max_steps) +
                       " side crossings (degenerate geometry near face " + std::to_string(f) + ")");
    }
    const Eigen::Vector3d db = barycentric_velocity(p, d);
    double t_exit = 0.0;
    const int k_exit = first_exit(b, db, excl, only, t_exit);
    // ending within rounding of a side (typically at the far vertex): end, do not cross
    if (k_exit < 0 || rem <= t_exit + end_slack) {
      const double t_end = std::min(rem, t_exit);
      if (std::isfinite(t_end) && db.allFinite()) b += t_end * db;
      clamp_normalize(b);
      finish_trace(r, f, b, d, record_path);
      return r;
    }
    only = -1;
    b += t_exit * db;
    b[k_exit] = 0.0;
    clamp_normalize(b);
    rem -= t_exit;
    const int s = (k_exit + 1) % 3, s1 = (s + 1) % 3;
    const Index he = 3 * f + s;
    const Index tw = tri.twin(he);
    const Eigen::Vector2d e = (p[s1] - p[s]).normalized();
    if (tw != kInvalidIndex && is_flagged(stop_edges, tri.edge(he))) {
      r.hit_boundary = true;
      r.boundary_halfedge = he;
      finish_trace(r, f, b, d, record_path);
      return r;
    }
    if (tw == kInvalidIndex) {
      const double c = d.dot(e);
      // (meeting the side square on, at rounding level, is a stop: no side to slide towards)
      if (slide_on_boundary && std::abs(c) > 1e-12 && r.slides < max_steps) {
        // a line of the input surface cannot leave it: this is rounding, run along the side
        d = c > 0.0 ? e : Eigen::Vector2d(-e);
        ++r.slides;
        excl = k_exit;
        if (record_path) r.path.push_back({f, b});
        continue;
      }
      r.hit_boundary = true;
      r.boundary_halfedge = he;
      finish_trace(r, f, b, d, record_path);
      return r;
    }
    unfold_across(tri, tw, s, e, f, b, d, p, excl);
    if (record_path) r.path.push_back({f, b});
  }
}

// ---------------------------------------------------------------------------------------------

SignpostTriangulation::SignpostTriangulation(const std::vector<Triangle>& faces,
                                             const Positions& positions, double mollify_epsilon,
                                             BuildReport* report)
    : positions_(positions), faces_(faces), mollify_epsilon_(mollify_epsilon) {
  BuildReport build;
  input_ = IntrinsicTriangulation::from_positions(faces, positions, &build);
  face_origin_ = build.face_origin;
  if (report) *report = build;
  if (mollify_epsilon > 0.0) mollify_ = input_.mollify(mollify_epsilon);
  tri_ = input_;
  init_directions(input_, input_direction_, angle_sum_, boundary_);
  direction_ = input_direction_;
  input_corner_.resize(input_.n_halfedges());
  for (Index h = 0; h < input_.n_halfedges(); ++h) input_corner_[h] = corner_angle(input_, h);
  const Index nv = input_.n_vertices();
  location_.resize(nv);
  frame_.assign(nv, 0.0);
  for (Index v = 0; v < nv; ++v) {
    const Index h = input_.vertex_halfedge(v);
    if (h == kInvalidIndex) continue;
    location_[v].face = T::face(h);
    location_[v].bary[T::side(h)] = 1.0;
  }
}

void SignpostTriangulation::init_directions(const IntrinsicTriangulation& t,
                                            std::vector<double>& dir, std::vector<double>& sum,
                                            std::vector<char>& boundary) const {
  const Index nv = t.n_vertices(), nh = t.n_halfedges();
  dir.assign(nh, std::numeric_limits<double>::quiet_NaN());
  sum.assign(nv, 0.0);
  boundary.assign(nv, 0);
  auto walk_fan = [&](Index v, Index h0) {
    // rewind clockwise to the fan's first halfedge (an outgoing boundary side, if any)
    Index h = h0;
    for (Index guard = 0; guard < nh; ++guard) {
      const Index tw = t.twin(h);
      if (tw == kInvalidIndex) break;
      const Index back = T::next(tw);
      if (back == h0) break;
      h = back;
    }
    if (t.twin(h) == kInvalidIndex) boundary[v] = 1;
    const Index first = h;
    for (Index guard = 0; guard < nh; ++guard) {
      dir[h] = sum[v];
      sum[v] += corner_angle(t, h);
      const Index n = t.twin(T::prev(h));
      if (n == kInvalidIndex || n == first) break;
      h = n;
    }
  };
  for (Index v = 0; v < nv; ++v) {
    const Index h = t.vertex_halfedge(v);
    if (h != kInvalidIndex) walk_fan(v, h);
  }
  // pinched vertices (several fans): later fans continue the angle range
  for (Index h = 0; h < nh; ++h) {
    if (std::isnan(dir[h])) walk_fan(t.tail(h), h);
  }
}

double SignpostTriangulation::wrap(Index v, double a) const {
  const double theta = angle_sum_[v];
  if (boundary_[v]) return std::clamp(a, 0.0, theta);
  if (a >= theta) a -= theta;
  if (a < 0.0) a += theta;
  if (!(a >= 0.0 && a < theta)) a = std::fmod(std::fmod(a, theta) + theta, theta);
  return a;
}

void SignpostTriangulation::add_vertex_records() {
  angle_sum_.push_back(2.0 * kPi);
  boundary_.push_back(0);
  location_.push_back({});
  frame_.push_back(0.0);
  direction_.resize(tri_.n_halfedges(), 0.0);
}

Eigen::Vector3d SignpostTriangulation::position(const SurfacePoint& p) const {
  return point_position(input_, positions_, p);
}

Positions SignpostTriangulation::vertex_positions() const {
  Positions x(tri_.n_vertices(), 3);
  const Index n_in = n_input_vertices();
  for (Index v = 0; v < tri_.n_vertices(); ++v) {
    x.row(v) = v < n_in ? Eigen::Vector3d(positions_.row(v)) : position(location_[v]);
  }
  return x;
}

// ---------------------------------------------------------------------------------------------
// Flips

bool SignpostTriangulation::flip_edge(Index e) { return flip_edge(e, nullptr); }

bool SignpostTriangulation::flip_edge(Index e, double* corners) {
  const Index h = tri_.edge_halfedge(e);
  const Index t = tri_.twin(h);
  if (t == kInvalidIndex) return false;
  const Index h1 = T::next(h), h2 = T::prev(h), t1 = T::next(t), t2 = T::prev(t);
  const double dh1 = direction_[h1], dh2 = direction_[h2], dt1 = direction_[t1],
               dt2 = direction_[t2];
  if (recording_) {
    FlipRecord r;
    if (!tri_.flip_edge(e, &r.tri)) return false;
    const double d[6] = {direction_[h], direction_[t], dh1, dh2, dt1, dt2};
    std::copy(d, d + 6, r.direction);
    r.log_size = op_log_.size();
    journal_.push_back(r);
  } else if (!tri_.flip_edge(e)) {
    return false;
  }
  if (logging_) log(Operation::Kind::kFlip, e, Eigen::Vector3d::Zero(), 0.0);
  // slots keep their sides' signposts: h1 ← h2, h2 ← t1, t1 ← t2, t2 ← h1
  direction_[h1] = dh2;
  direction_[h2] = dt1;
  direction_[t1] = dt2;
  direction_[t2] = dh1;
  // h = d→c is t1 = d→b turned by face(t)'s corner at d; t = c→d is h1 = c→a turned likewise
  const double at_t1 = corner_angle(tri_, t1), at_h1 = corner_angle(tri_, h1);
  direction_[h] = wrap(tri_.tail(h), direction_[t1] + at_t1);
  direction_[t] = wrap(tri_.tail(t), direction_[h1] + at_h1);
  if (corners != nullptr) corners[0] = at_t1, corners[1] = at_h1;
  return true;
}

std::size_t SignpostTriangulation::flip_journal_mark() {
  recording_ = true;
  return journal_.size();
}

void SignpostTriangulation::undo_flips(std::size_t mark) {
  if (!recording_ || mark > journal_.size()) {
    throw InvalidInput("undo_flips: mark " + std::to_string(mark) + " but " +
                       (recording_ ? std::to_string(journal_.size()) + " flips recorded"
                                   : std::string("not recording flips")));
  }
  while (journal_.size() > mark) {
    const FlipRecord& r = journal_.back();
    tri_.undo_flip(r.tri);
    const Index h = r.tri.halfedge[0], t = r.tri.halfedge[1];  // save_diamond's order
    const Index slots[6] = {h, t, T::next(h), T::prev(h), T::next(t), T::prev(t)};
    for (int k = 0; k < 6; ++k) direction_[slots[k]] = r.direction[k];
    if (op_log_.size() > r.log_size) op_log_.resize(r.log_size);  // the undone flip leaves it
    journal_.pop_back();
  }
}

std::vector<Index> SignpostTriangulation::flips_since(std::size_t mark) const {
  if (!recording_ || mark > journal_.size()) {
    throw InvalidInput("flips_since: mark " + std::to_string(mark) + " but " +
                       (recording_ ? std::to_string(journal_.size()) + " flips recorded"
                                   : std::string("not recording flips")));
  }
  std::vector<Index> edges;
  for (std::size_t k = mark; k < journal_.size(); ++k) edges.push_back(journal_[k].tri.edge);
  return edges;
}

void SignpostTriangulation::end_flip_journal() {
  recording_ = false;
  journal_.clear();
  journal_.shrink_to_fit();
}

void SignpostTriangulation::start_operation_log() {
  logging_ = true;
  op_log_.clear();
}

void SignpostTriangulation::end_operation_log() {
  logging_ = false;
  op_log_.clear();
  op_log_.shrink_to_fit();
}

void SignpostTriangulation::log(Operation::Kind kind, Index index, const Eigen::Vector3d& bary,
                                double t) {
  Operation op;
  op.kind = kind;
  op.index = index;
  op.bary = bary;
  op.t = t;
  op_log_.push_back(op);
}

void SignpostTriangulation::check_not_recording(const char* what) const {
  if (recording_) {
    throw InvalidInput(std::string(what) +
                       ": the triangulation is recording flips (end_flip_journal() first)");
  }
}

FlipReport SignpostTriangulation::flip_to_delaunay_from(std::vector<Index> queue,
                                                        std::vector<Index>* touched) {
  return tri_.flip_to_delaunay_from(std::move(queue), touched,
                                    [this](Index e) { return flip_edge(e); });
}

FlipReport SignpostTriangulation::flip_to_delaunay() {
  return tri_.flip_to_delaunay([this](Index e) { return flip_edge(e); });
}

FlipReport SignpostTriangulation::flip_to_delaunay(const std::vector<char>& fixed_edges) {
  return tri_.flip_to_delaunay(
      [this, &fixed_edges](Index e) { return !is_flagged(&fixed_edges, e) && flip_edge(e); });
}

FlipReport SignpostTriangulation::flip_to_delaunay_from(std::vector<Index> queue,
                                                        std::vector<Index>* touched,
                                                        const std::vector<char>& fixed_edges) {
  return tri_.flip_to_delaunay_from(std::move(queue), touched, [this, &fixed_edges](Index e) {
    return !is_flagged(&fixed_edges, e) && flip_edge(e);
  });
}

// ---------------------------------------------------------------------------------------------
// Tracing over the input

Index SignpostTriangulation::input_wedge(Index v, double phi) const {
  const Index h0 = input_.vertex_halfedge(v);
  if (h0 == kInvalidIndex) {
    throw InvalidInput("trace: vertex " + std::to_string(v) + " has no faces");
  }
  Index h = h0, found = kInvalidIndex;
  for (Index guard = 0; guard < input_.n_halfedges(); ++guard) {
    const double a0 = input_direction_[h];
    if (phi >= a0 && phi < a0 + input_corner_[h]) {  // half-open: fans may share an end
      found = h;
      break;
    }
    const Index n = input_.twin(T::prev(h));
    if (n == kInvalidIndex || n == h0) {
      // the closed end of the last fan (phi = Θ_v on the boundary)
      const double a1 = a0 + input_corner_[h];
      if (n == kInvalidIndex && phi >= a0 && phi <= a1 + 1e-12 &&
          std::abs(a1 - angle_sum_[v]) <= 1e-12 * angle_sum_[v]) {
        found = h;
      }
      break;
    }
    h = n;
  }
  if (found == kInvalidIndex) {
    // pinched vertex (other fans), the end of a boundary fan, or rounding: the wedge that
    // contains phi (half-open), else the nearest one
    double best = std::numeric_limits<double>::infinity();
    for (Index x = 0; x < input_.n_halfedges(); ++x) {
      if (input_.tail(x) != v) continue;
      const double a0 = input_direction_[x], a1 = a0 + input_corner_[x];
      if (phi >= a0 && phi < a1) {
        found = x;
        break;
      }
      const double gap = phi < a0 ? a0 - phi : phi - a1;
      if (gap < best) {
        best = gap;
        found = x;
      }
    }
    if (found == kInvalidIndex) found = h0;
  }
  return found;
}

// The unit direction at the corner of input halfedge `wedge` (at its tail) turned by alpha
// (clamped to the corner) from the wedge's side, in its face's layout.
Eigen::Vector2d SignpostTriangulation::wedge_direction(Index wedge, double alpha) const {
  Eigen::Vector2d p[3];
  alpha = std::clamp(alpha, 0.0, input_corner_[wedge]);
  const int s = T::side(wedge);
  face_layout(input_, T::face(wedge), p);
  const Eigen::Vector2d e = (p[(s + 1) % 3] - p[s]).normalized();
  const Eigen::Vector2d eperp(-e.y(), e.x());
  return std::cos(alpha) * e + std::sin(alpha) * eperp;
}

TraceResult SignpostTriangulation::trace_from_vertex(Index v, double phi, double distance,
                                                     bool record) const {
  const Index cap = trace_cap(input_);
  if (v >= n_input_vertices()) {
    const SurfacePoint& s = location_[v];
    const double a = frame_[v] + phi;
    return trace_straight(input_, s, Eigen::Vector2d(std::cos(a), std::sin(a)), distance, -1, true,
                          record, cap);
  }
  // the wedge of the input fan at v that contains direction phi
  const Index found = input_wedge(v, phi);
  const int s = T::side(found);
  SurfacePoint start;
  start.face = T::face(found);
  start.bary[s] = 1.0;
  return trace_straight(input_, start, wedge_direction(found, phi - input_direction_[found]),
                        distance, s, true, record, cap);
}

Eigen::Vector3d SignpostTriangulation::halfedge_direction_3d(Index h) const {
  if (h < 0 || h >= tri_.n_halfedges()) {
    throw InvalidInput("halfedge_direction_3d: halfedge " + std::to_string(h) +
                       " out of range [0, " + std::to_string(tri_.n_halfedges()) + ")");
  }
  const Index v = tri_.tail(h);
  Index f = kInvalidIndex;
  Eigen::Vector2d d;
  if (v >= n_input_vertices()) {
    f = location_[v].face;
    const double a = frame_[v] + direction_[h];
    d = Eigen::Vector2d(std::cos(a), std::sin(a));
  } else {
    const Index wedge = input_wedge(v, direction_[h]);
    f = T::face(wedge);
    d = wedge_direction(wedge, direction_[h] - input_direction_[wedge]);
  }
  // the layout's direction as barycentric velocity, then through the 3D corners
  Eigen::Vector2d p[3];
  face_layout(input_, f, p);
  const Eigen::Vector3d db = barycentric_velocity(p, d);
  Eigen::Vector3d x = Eigen::Vector3d::Zero();
  for (int k = 0; k < 3; ++k) x += db[k] * positions_.row(input_.tail(3 * f + k)).transpose();
  return x.normalized();
}

void SignpostTriangulation::locate_from(Index h, Index v, double direction_v_to_u) {
  const TraceResult r =
      trace_from_vertex(tri_.tail(h), direction_[h], tri_.halfedge_length(h), false);
  location_[v] = r.end;
  frame_[v] = std::atan2(-r.direction.y(), -r.direction.x()) - direction_v_to_u;
}

SurfacePoint SignpostTriangulation::locate(Index f, const Eigen::Vector3d& bary) const {
  Eigen::Vector2d p[3];
  face_layout(tri_, f, p);
  const Eigen::Vector2d x = bary[0] * p[0] + bary[1] * p[1] + bary[2] * p[2];
  int k = 0;
  for (int j = 1; j < 3; ++j) {
    if ((x - p[j]).squaredNorm() < (x - p[k]).squaredNorm()) k = j;
  }
  const Index h = 3 * f + k;
  const Eigen::Vector2d w = x - p[k];
  const double dist = w.norm();
  if (!(dist > 0.0)) return location_[tri_.tail(h)];
  const Eigen::Vector2d e = p[(k + 1) % 3] - p[k];
  const double alpha = std::atan2(cross2(e, w), e.dot(w));
  const Index v = tri_.tail(h);
  return trace_from_vertex(v, wrap(v, direction_[h] + alpha), dist, false).end;
}

std::vector<SurfacePoint> SignpostTriangulation::trace_edge(Index e) const {
  Index h = tri_.edge_halfedge(e);
  const Index n_in = n_input_vertices();
  if (tri_.tail(h) >= n_in && tri_.head(h) < n_in && tri_.twin(h) != kInvalidIndex) {
    h = tri_.twin(h);
  }
  return trace_halfedge(h);
}

std::vector<SurfacePoint> SignpostTriangulation::trace_halfedge(Index h) const {
  return trace_from_vertex(tri_.tail(h), direction_[h], tri_.halfedge_length(h), true).path;
}

std::vector<std::vector<Eigen::Vector3d>> SignpostTriangulation::traced_edges_3d() const {
  std::vector<std::vector<Eigen::Vector3d>> out(tri_.n_edges());
  FirstError failure;  // transport out of the OpenMP loop: any exception ends the call
#pragma omp parallel for schedule(dynamic, 256)
  for (Index e = 0; e < tri_.n_edges(); ++e) {
    if (failure.failed()) continue;
    try {
      const std::vector<SurfacePoint> path = trace_edge(e);
      auto& line = out[e];
      line.reserve(path.size());
      for (const SurfacePoint& p : path) {
        const Eigen::Vector3d x = position(p);
        if (line.empty() || (x - line.back()).squaredNorm() > 0.0) line.push_back(x);
      }
    } catch (...) {
      failure.record_current("edge " + std::to_string(e));
    }
  }
  failure.rethrow_if_any("traced_edges_3d");
  return out;
}

// ---------------------------------------------------------------------------------------------
// Insertion

Index SignpostTriangulation::insert_vertex(Index f, const Eigen::Vector3d& bary) {
  check_not_recording("insert_vertex");
  const double d1 = direction_[3 * f + 1], d2 = direction_[3 * f + 2];
  const Index v = tri_.insert_vertex_in_face(f, bary);
  if (logging_) log(Operation::Kind::kInsertVertex, f, bary, 0.0);
  add_vertex_records();
  const Index f1 = tri_.n_faces() - 2, f2 = f1 + 1;
  const Index c0 = tri_.tail(3 * f), c1 = tri_.tail(3 * f1), c2 = tri_.tail(3 * f2);
  auto& dir = direction_;
  dir[3 * f1] = d1;
  dir[3 * f2] = d2;
  dir[3 * f + 2] = 0.0;  // v→c0
  dir[3 * f1 + 2] = corner_angle(tri_, 3 * f + 2);
  dir[3 * f2 + 2] = dir[3 * f1 + 2] + corner_angle(tri_, 3 * f1 + 2);
  dir[3 * f2 + 1] = wrap(c0, dir[3 * f] + corner_angle(tri_, 3 * f));
  dir[3 * f + 1] = wrap(c1, dir[3 * f1] + corner_angle(tri_, 3 * f1));
  dir[3 * f1 + 1] = wrap(c2, dir[3 * f2] + corner_angle(tri_, 3 * f2));
  // locate from the nearest corner (the shortest trace)
  const Index into[3] = {3 * f2 + 1, 3 * f + 1, 3 * f1 + 1};   // c_k → v
  const Index outof[3] = {3 * f + 2, 3 * f1 + 2, 3 * f2 + 2};  // v → c_k
  int k = 0;
  for (int j = 1; j < 3; ++j) {
    if (tri_.halfedge_length(outof[j]) < tri_.halfedge_length(outof[k])) k = j;
  }
  locate_from(into[k], v, dir[outof[k]]);
  return v;
}

Index SignpostTriangulation::split_edge(Index e, double t) {
  check_not_recording("split_edge");
  const Index h = tri_.edge_halfedge(e);
  const Index tw = tri_.twin(h);
  const bool interior = tw != kInvalidIndex;
  const Index h1 = T::next(h), h2 = T::prev(h);
  const Index t1 = interior ? T::next(tw) : kInvalidIndex;
  const Index t2 = interior ? T::prev(tw) : kInvalidIndex;
  const double dh1 = direction_[h1], dt1 = interior ? direction_[t1] : 0.0;
  const Index m = tri_.split_edge(e, t);
  if (logging_) log(Operation::Kind::kSplitEdge, e, Eigen::Vector3d::Zero(), t);
  add_vertex_records();
  const Index g1 = interior ? tri_.n_faces() - 2 : tri_.n_faces() - 1, g2 = g1 + 1;
  auto& dir = direction_;
  dir[3 * g1 + 1] = dh1;
  dir[3 * g1 + 2] = wrap(tri_.tail(h2), dir[h2] + corner_angle(tri_, h2));  // c→m
  dir[3 * g1] = 0.0;                                                        // m→b
  dir[h1] = corner_angle(tri_, 3 * g1);                                     // m→c
  const double to_a = dir[h1] + corner_angle(tri_, h1);                     // m→a
  if (interior) {
    dir[3 * g2 + 1] = dt1;
    dir[3 * g2 + 2] = wrap(tri_.tail(t2), dir[t2] + corner_angle(tri_, t2));  // d→m
    dir[3 * g2] = to_a;
    dir[t1] = to_a + corner_angle(tri_, 3 * g2);  // m→d
    if (t <= 0.5) {
      locate_from(h, m, to_a);
    } else {
      locate_from(tw, m, 0.0);
    }
  } else {
    angle_sum_[m] = kPi;
    boundary_[m] = 1;
    locate_from(h, m, kPi);
  }
  return m;
}

// ---------------------------------------------------------------------------------------------
// Moving inserted vertices inside their flat star

bool SignpostTriangulation::move_inserted_vertex(Index v, const Eigen::Vector2d& displacement,
                                                 double min_relative_height) {
  std::vector<Index> spokes;
  std::vector<Eigen::Vector2d> ring;
  const StarMove check = check_star_move(tri_, v, n_input_vertices(), displacement,
                                         min_relative_height, &spokes, &ring);
  if (check != StarMove::kMoves) return check == StarMove::kStays;
  const double dist = displacement.norm();
  const Eigen::Vector2d& p = displacement;
  const std::size_t n = ring.size();
  const double base = direction_[spokes[0]];  // the layout's angle 0, as a signpost at v
  const double theta = wrap(v, base + std::atan2(p.y(), p.x()));
  TraceResult r;
  try {
    r = trace_from_vertex(v, theta, dist, false);
  } catch (const TraceError&) {  // the move is refused, the vertex stays where it was
    return false;
  }
  if (r.hit_boundary || r.end.face == kInvalidIndex) return false;
  for (std::size_t i = 0; i < n; ++i) {
    tri_.set_length(tri_.edge(spokes[i]), (ring[i] - p).norm());
  }
  for (std::size_t i = 0; i < n; ++i) {
    const Eigen::Vector2d w = ring[i] - p;
    direction_[spokes[i]] = wrap(v, base + std::atan2(w.y(), w.x()));
    // at the ring vertex u: u→v follows the (unchanged) outer side u→ring[i+1] by the corner
    // angle of face(h_i) at u
    const Index out = T::next(spokes[i]);
    const Index tw = tri_.twin(spokes[i]);
    direction_[tw] = wrap(tri_.tail(tw), direction_[out] + corner_angle(tri_, out));
  }
  location_[v] = r.end;
  frame_[v] = std::atan2(r.direction.y(), r.direction.x()) - theta;
  return true;
}

// ---------------------------------------------------------------------------------------------
// Function transfer

Eigen::VectorXd SignpostTriangulation::input_to_intrinsic(const Eigen::VectorXd& x) const {
  const Index n_in = n_input_vertices();
  if (x.size() != n_in) {
    throw InvalidInput("input_to_intrinsic: " + std::to_string(x.size()) + " values for " +
                       std::to_string(n_in) + " input vertices");
  }
  Eigen::VectorXd out(tri_.n_vertices());
  out.head(n_in) = x;
  for (Index v = n_in; v < tri_.n_vertices(); ++v) out[v] = interpolate_at(input_, x, location_[v]);
  return out;
}

Eigen::VectorXd SignpostTriangulation::intrinsic_to_input(const Eigen::VectorXd& x) const {
  if (x.size() != tri_.n_vertices()) {
    throw InvalidInput("intrinsic_to_input: " + std::to_string(x.size()) + " values for " +
                       std::to_string(tri_.n_vertices()) + " intrinsic vertices");
  }
  return x.head(n_input_vertices());
}

// ---------------------------------------------------------------------------------------------
// Saving and restoring: the "ifem-signpost 1" text format. One record per line, fields
// separated by spaces, doubles printed with %.17g (exact round trip), ids 0-based, -1 = none:
//
//   ifem-signpost 1
//   mollify EPS                      relative mollification the input was built with
//   input_vertices NV                then NV lines "x y z"
//   input_faces NF                   then NF lines "a b c" (the faces as given, unrepaired)
//   intrinsic NVI NFI                intrinsic vertex and face counts (NVI ≥ NV)
//   halfedges                        then 3·NFI lines "tail twin length direction" for
//                                    halfedge 3f+s (corner s of face f): tail vertex, glued
//                                    halfedge (-1 on the boundary), edge length, signpost
//   vertices                         then NVI lines "angle_sum boundary face b0 b1 b2 frame":
//                                    total angle Θ_v, 1 on the boundary, location on the input
//                                    (input() face and barycentric coordinates), and for
//                                    inserted vertices the angle of direction 0 in that face
//   edges NE                         (optional) then NE lines "h": edge e is the edge of
//                                    halfedge h, which is its edge_halfedge(e) (without this
//                                    section edges are numbered in halfedge order)
//   end
//
// Input vertices are intrinsic vertices 0..NV-1. Lines starting with '#' are comments.

void SignpostTriangulation::save(const std::string& path) const {
  std::FILE* f = io::detail::open_temporary(path, false);
  std::fprintf(f, "ifem-signpost 1\n# intrinsic triangulation with signposts over its input\n");
  std::fprintf(f, "mollify %.17g\n", mollify_epsilon_);
  std::fprintf(f, "input_vertices %ld\n", long(positions_.rows()));
  for (Eigen::Index v = 0; v < positions_.rows(); ++v) {
    std::fprintf(f, "%.17g %.17g %.17g\n", positions_(v, 0), positions_(v, 1), positions_(v, 2));
  }
  std::fprintf(f, "input_faces %zu\n", faces_.size());
  for (const Triangle& t : faces_) std::fprintf(f, "%d %d %d\n", int(t[0]), int(t[1]), int(t[2]));
  std::fprintf(f, "intrinsic %d %d\nhalfedges\n", int(tri_.n_vertices()), int(tri_.n_faces()));
  for (Index h = 0; h < tri_.n_halfedges(); ++h) {
    std::fprintf(f, "%d %d %.17g %.17g\n", int(tri_.tail(h)), int(tri_.twin(h)),
                 tri_.halfedge_length(h), direction_[h]);
  }
  std::fprintf(f, "vertices\n");
  for (Index v = 0; v < tri_.n_vertices(); ++v) {
    const SurfacePoint& p = location_[v];
    std::fprintf(f, "%.17g %d %d %.17g %.17g %.17g %.17g\n", angle_sum_[v], int(boundary_[v]),
                 int(p.face), p.bary[0], p.bary[1], p.bary[2], frame_[v]);
  }
  std::fprintf(f, "edges %d\n", int(tri_.n_edges()));
  for (Index e = 0; e < tri_.n_edges(); ++e) std::fprintf(f, "%d\n", int(tri_.edge_halfedge(e)));
  std::fprintf(f, "end\n");
  io::detail::close_and_rename(f, true, path);
}

namespace {

// Record reader for load(), on the text cursor the mesh readers use: one record per line, blank
// lines and '#' comments skipped; errors are IoError naming the file and the line.
class RecordReader {
 public:
  explicit RecordReader(const std::string& path)
      : path_(path),
        bytes_(io::detail::read_file(path)),
        c_(path_, bytes_.data(), bytes_.data() + bytes_.size()) {}

  // Moves to the next record (a line with content); `what` names it when the file ends first.
  void next(const char* what) {
    if (started_) c_.next_line();
    started_ = true;
    if (!c_.next_content_line()) fail(std::string("unexpected end of file, expected ") + what);
  }
  // The next word of the current record (empty at its end).
  std::string word() { return std::string(c_.token()); }
  long integer(const std::string& what) { return long(c_.integer(what.c_str())); }
  double number(const std::string& what) { return c_.number(what.c_str()); }
  [[noreturn]] void fail(const std::string& msg) const { c_.fail(msg); }
  // Refuses a declared count of records that the rest of the file cannot hold (each record
  // takes at least min_bytes), before anything is allocated for them.
  void expect_records(long count, std::size_t min_bytes, const char* what) const {
    if (count > static_cast<long>(c_.remaining() / min_bytes + 1)) {
      fail(std::string("the file declares ") + std::to_string(count) + " " + what +
           " but is too short to hold them");
    }
  }
  // The next record is `word`, followed by one or two counts when a (and b) are given.
  void keyword(const char* word, long* a = nullptr, long* b = nullptr) {
    next(word);
    const std::string w = this->word();
    if (w != word) fail(std::string("expected '") + word + "', got '" + w + "'");
    if (a) *a = integer(std::string("the count of '") + word + "'");
    if (b) *b = integer(std::string("the second count of '") + word + "'");
  }
  // The next record is exactly the values x... (integers into long, numbers into double).
  template <class... X>
  void values(const char* what, X&... x) {
    next(what);
    (read(what, x), ...);
    if (!c_.at_line_end()) fail(std::string("expected ") + what + ", got more on the line");
  }

 private:
  void read(const char* what, long& x) { x = integer(what); }
  void read(const char* what, double& x) { x = number(what); }

  std::string path_;
  std::string bytes_;
  io::detail::TextCursor c_;
  bool started_ = false;
};

// The header ("ifem-signpost 1") and the mollification record; returns the mollification.
double read_header(RecordReader& r) {
  r.next("header");
  if (r.word() != "ifem-signpost") r.fail("not an ifem-signpost file");
  const long version = r.integer("the version");
  if (version != 1) r.fail("unsupported version " + std::to_string(version) + " (this reads 1)");
  r.next("mollify");
  if (r.word() != "mollify") r.fail("expected 'mollify EPS'");
  const double eps = r.number("EPS of 'mollify EPS'");
  if (!(eps >= 0)) r.fail("expected 'mollify EPS' with EPS >= 0");
  return eps;
}

// The input vertices and faces, as given.
void read_input(RecordReader& r, Positions& x, std::vector<Triangle>& faces) {
  long nv = 0, nf = 0;
  r.keyword("input_vertices", &nv);
  if (nv < 0 || nv > std::numeric_limits<Index>::max()) r.fail("bad vertex count");
  r.expect_records(nv, 6, "input vertices");  // "x y z\n"
  x.resize(nv, 3);
  for (long v = 0; v < nv; ++v) r.values("'x y z'", x(v, 0), x(v, 1), x(v, 2));
  r.keyword("input_faces", &nf);
  if (nf < 0 || nf > std::numeric_limits<Index>::max() / 3) r.fail("bad face count");
  r.expect_records(nf, 6, "input faces");  // "a b c\n"
  faces.resize(nf);
  for (long f = 0; f < nf; ++f) {
    long a, b, c;
    r.values("'a b c'", a, b, c);
    for (const long i : {a, b, c}) {
      if (i < 0 || i >= nv) r.fail("vertex id " + std::to_string(i) + " out of range");
    }
    faces[f] = {Index(a), Index(b), Index(c)};
  }
}

// The intrinsic triangulation's halfedge records.
struct GluingRecords {
  long nvi = 0;                   // intrinsic vertices
  std::vector<Index> tail, twin;  // per halfedge
  std::vector<double> len, dir;   // per halfedge: length, signpost
};

// The intrinsic counts (at least the nv input vertices) and the halfedge records.
GluingRecords read_halfedges(RecordReader& r, long nv) {
  GluingRecords gl;
  long nfi = 0;
  r.keyword("intrinsic", &gl.nvi, &nfi);
  if (gl.nvi < nv || nfi < 0 || nfi > std::numeric_limits<Index>::max() / 3 ||
      gl.nvi > std::numeric_limits<Index>::max()) {
    r.fail("bad intrinsic counts");
  }
  r.keyword("halfedges");
  const long nh = 3 * nfi;
  r.expect_records(nh, 8, "halfedges");  // "t w l d\n"
  gl.tail.resize(nh);
  gl.twin.resize(nh);
  gl.len.resize(nh);
  gl.dir.resize(nh);
  for (long h = 0; h < nh; ++h) {
    long t, tw;
    r.values("'tail twin length direction'", t, tw, gl.len[h], gl.dir[h]);
    if (t < 0 || t >= gl.nvi || tw < -1 || tw >= nh) r.fail("halfedge id out of range");
    gl.tail[h] = Index(t);
    gl.twin[h] = tw < 0 ? kInvalidIndex : Index(tw);
  }
  return gl;
}

// The per-vertex records of the intrinsic vertices.
struct VertexRecords {
  std::vector<double> angle_sum;
  std::vector<char> boundary;
  std::vector<SurfacePoint> location;  // on the input, face -1 for none
  std::vector<double> frame;
};

// The records of nvi intrinsic vertices, located in faces of an input with n_input_faces.
VertexRecords read_vertex_records(RecordReader& r, long nvi, Index n_input_faces) {
  VertexRecords vr;
  r.expect_records(nvi, 14, "intrinsic vertex records");  // "s b f b0 b1 b2 r\n"
  vr.angle_sum.resize(nvi);
  vr.boundary.resize(nvi);
  vr.location.resize(nvi);
  vr.frame.resize(nvi);
  for (long v = 0; v < nvi; ++v) {
    long b, f;
    SurfacePoint& p = vr.location[v];
    r.values("'angle_sum boundary face b0 b1 b2 frame'", vr.angle_sum[v], b, f, p.bary[0],
             p.bary[1], p.bary[2], vr.frame[v]);
    if (f < -1 || f >= n_input_faces) r.fail("location face out of range");
    vr.boundary[v] = char(b != 0);
    p.face = f < 0 ? kInvalidIndex : Index(f);
  }
  return vr;
}

// The optional edges section (edge e's halfedge, of nh) and 'end'; false without the section.
bool read_edges(RecordReader& r, long nh, std::vector<Index>& edge_halfedge) {
  r.next("'edges NE' or 'end'");
  const std::string word = r.word();
  if (word == "end") return false;
  if (word != "edges") r.fail("expected 'edges' or 'end', got '" + word + "'");
  const long ne = r.integer("the count of 'edges'");
  if (ne < 0 || ne > nh) r.fail("bad edge count");
  r.expect_records(ne, 2, "edges");  // "h\n"
  edge_halfedge.resize(ne);
  for (long e = 0; e < ne; ++e) {
    long h;
    r.values("'h'", h);
    if (h < 0 || h >= nh) r.fail("halfedge id out of range");
    edge_halfedge[e] = Index(h);
  }
  r.keyword("end");
  return true;
}

}  // namespace

SignpostTriangulation SignpostTriangulation::load(const std::string& path) {
  RecordReader r(path);
  const double eps = read_header(r);
  Positions x;
  std::vector<Triangle> faces;
  read_input(r, x, faces);
  GluingRecords gl = read_halfedges(r, long(x.rows()));
  r.keyword("vertices");
  SignpostTriangulation st(faces, x, eps);
  if (st.input_.n_vertices() != Index(x.rows())) r.fail("input vertex count mismatch");
  VertexRecords vr = read_vertex_records(r, gl.nvi, st.input_.n_faces());
  st.angle_sum_ = std::move(vr.angle_sum);
  st.boundary_ = std::move(vr.boundary);
  st.location_ = std::move(vr.location);
  st.frame_ = std::move(vr.frame);
  std::vector<Index> edge_halfedge;
  const bool has_edges = read_edges(r, long(gl.tail.size()), edge_halfedge);
  try {
    st.tri_ = IntrinsicTriangulation::from_gluing(std::move(gl.tail), std::move(gl.twin), gl.len,
                                                  Index(gl.nvi));
    if (has_edges) st.tri_.renumber_edges(edge_halfedge);
  } catch (const InvalidInput& e) {
    throw IoError(path + ": intrinsic triangulation: " + e.what());
  }
  st.direction_ = std::move(gl.dir);
  return st;
}

}  // namespace ifem::intrinsic
