#include "solvers/recipes/trace_geodesic.h"

#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <fstream>

#include "intrinsic/core/errors.h"
#include "intrinsic/core/geometry.h"
#include "intrinsic/geodesic/input_surface.h"
#include "intrinsic/io/tokens.h"
#include "intrinsic/refine/signpost.h"
#include "solvers/recipes/geodesic.h"

namespace ifem::recipes {

using intrinsic::IntrinsicTriangulation;
using intrinsic::SurfacePoint;
using T = IntrinsicTriangulation;

namespace {

constexpr double kTwoPi = 6.283185307179586;
// a weight this close to 1 makes a point that vertex (a face point's start, the end's report)
constexpr double kAtVertex = 1e-12;
// a direction whose tangent part is at most this fraction of it is along the normal
constexpr double kAlongNormal = 1e-9;

std::string vec_text(const Eigen::Vector3d& d) {
  char buf[96];
  std::snprintf(buf, sizeof buf, "(%.6g, %.6g, %.6g)", d[0], d[1], d[2]);
  return buf;
}

// The counter-clockwise angle in [0, 2π) from a to b, both in the plane normal to unit n.
double turn(const Eigen::Vector3d& a, const Eigen::Vector3d& b, const Eigen::Vector3d& n) {
  double t = std::atan2(a.cross(b).dot(n), a.dot(b));
  if (t < 0.0) t += kTwoPi;
  return t;
}

// The part of d in the plane normal to unit n, refused when d is zero / along n.
Eigen::Vector3d tangent_part(const Eigen::Vector3d& d, const Eigen::Vector3d& n,
                             const std::string& where) {
  const Eigen::Vector3d t = d - d.dot(n) * n;
  if (!(t.norm() > kAlongNormal * d.norm())) {
    throw InvalidInput("direction " + vec_text(d) + " is along the surface normal at " + where +
                       ": no tangent direction to trace");
  }
  return t;
}

// The fan of outgoing halfedges at v, counter-clockwise, from its first (a boundary side when
// v is on the boundary).
std::vector<Index> vertex_fan(const IntrinsicTriangulation& tri, Index v) {
  const Index h0 = tri.vertex_halfedge(v);
  Index h = h0;
  for (Index guard = 0; guard < tri.n_halfedges(); ++guard) {
    const Index tw = tri.twin(h);
    if (tw == kInvalidIndex || T::next(tw) == h0) break;
    h = T::next(tw);
  }
  std::vector<Index> fan;
  const Index first = h;
  for (Index guard = 0; guard < tri.n_halfedges(); ++guard) {
    fan.push_back(h);
    const Index n = tri.twin(T::prev(h));
    if (n == kInvalidIndex || n == first) break;
    h = n;
  }
  return fan;
}

}  // namespace

struct GeodesicTracer::Start {
  SurfacePoint point;
  Eigen::Vector2d direction;  // unit, in point.face's layout
  int corner = -1;            // trace_straight's start_corner
};

std::string InputSurfacePoint::token() const {
  char buf[128];
  std::snprintf(buf, sizeof buf, "face:%d:%.17g:%.17g", static_cast<int>(face), bary[1], bary[2]);
  return buf;
}

GeodesicTracer::GeodesicTracer(const io::SurfaceInput& input) {
  if (!input.has_faces()) {
    throw InvalidInput("trace needs a triangle mesh (the input has no faces: a point cloud)");
  }
  input_.positions = input.positions;
  input_.triangles = input.triangles;
  input_.n_non_triangles = input.n_non_triangles;
  intrinsic::BuildReport report;
  try {
    tri_ = IntrinsicTriangulation::from_positions(input.triangles, input.positions, &report);
  } catch (const NonManifoldInput& e) {
    throw intrinsic::manifold_only(e,
                                   "trace needs an edge-manifold, orientable surface (a ray has "
                                   "no single way on across an edge of 3+ faces)");
  }
  face_origin_ = report.face_origin;
  given_face_.assign(input.triangles.size(), kInvalidIndex);
  bool area = false;
  for (Index f = 0; f < tri_.n_faces(); ++f) {
    given_face_[face_origin_[f]] = f;
    area = area || intrinsic::face_area(tri_, f) > 0.0;
  }
  if (!area) throw InvalidInput("trace: no face of the input has area");
  out_degree_.assign(tri_.n_vertices(), 0);
  for (const Index v : tri_.tails()) ++out_degree_[v];
  const Eigen::Vector3d lo = input.positions.colwise().minCoeff();
  const Eigen::Vector3d hi = input.positions.colwise().maxCoeff();
  merge_distance_ = 1e-14 * (hi - lo).norm();
}

Eigen::Vector3d GeodesicTracer::position(Index f, const Eigen::Vector3d& bary) const {
  Eigen::Vector3d x = Eigen::Vector3d::Zero();
  for (int k = 0; k < 3; ++k) x += bary[k] * input_.positions.row(tri_.tail(3 * f + k)).transpose();
  return x;
}

// A layout vector w of face f as a 3D vector on its triangle (the affine map of the layout).
Eigen::Vector3d GeodesicTracer::to_3d(Index f, const Eigen::Vector2d& w) const {
  Eigen::Vector2d p[3];
  intrinsic::face_layout(tri_, f, p);
  const double b = w.y() / p[2].y();
  const double a = (w.x() - b * p[2].x()) / p[1].x();
  const Eigen::Vector3d x0 = input_.positions.row(tri_.tail(3 * f)).transpose();
  return a * (input_.positions.row(tri_.tail(3 * f + 1)).transpose() - x0) +
         b * (input_.positions.row(tri_.tail(3 * f + 2)).transpose() - x0);
}

InputSurfacePoint GeodesicTracer::on_input(Index f, const Eigen::Vector3d& bary) const {
  InputSurfacePoint p;
  p.face = face_origin_[f];
  const Triangle& given = input_.triangles[p.face];
  for (int k = 0; k < 3; ++k) {
    const Index v = tri_.tail(3 * f + k);
    for (int j = 0; j < 3; ++j) {
      if (given[j] == v) p.bary[j] = bary[k];
    }
    if (bary[k] >= 1.0 - kAtVertex) p.vertex = v;
  }
  p.position = position(f, bary);
  return p;
}

GeodesicTracer::Start GeodesicTracer::face_start(const GivenPoint& p,
                                                 const Eigen::Vector3d& d) const {
  const Index g = given_face_[p.face];
  const std::string where = "face " + std::to_string(p.face);
  if (g == kInvalidIndex) throw InvalidInput(p.token + ": " + where + " repeats a vertex");
  Start s;
  s.point.face = g;
  const Triangle& given = input_.triangles[p.face];
  for (int k = 0; k < 3; ++k) {
    for (int j = 0; j < 3; ++j) {
      if (given[j] == tri_.tail(3 * g + k)) s.point.bary[k] = p.bary[j];
    }
  }
  s.point.bary /= s.point.bary.sum();
  const Eigen::Vector3d x0 = input_.positions.row(tri_.tail(3 * g)).transpose();
  const Eigen::Vector3d e1 = input_.positions.row(tri_.tail(3 * g + 1)).transpose() - x0;
  const Eigen::Vector3d e2 = input_.positions.row(tri_.tail(3 * g + 2)).transpose() - x0;
  const Eigen::Vector3d n = e1.cross(e2);
  if (!(n.norm() > 0.0) || !(intrinsic::face_area(tri_, g) > 0.0)) {
    throw InvalidInput(p.token + ": " + where + " has no area (no tangent plane)");
  }
  const Eigen::Vector3d t = tangent_part(d, n.normalized(), where);
  // t = a·e1 + b·e2 (t lies in their plane), then the same combination of the layout's sides
  const double g11 = e1.dot(e1), g12 = e1.dot(e2), g22 = e2.dot(e2);
  const double r1 = e1.dot(t), r2 = e2.dot(t), det = g11 * g22 - g12 * g12;
  const Eigen::Vector2d ab((g22 * r1 - g12 * r2) / det, (g11 * r2 - g12 * r1) / det);
  Eigen::Vector2d lay[3];
  intrinsic::face_layout(tri_, g, lay);
  s.direction = (ab[0] * lay[1] + ab[1] * lay[2]).normalized();
  return s;
}

// Long function: the vertex rule of the header (normal, projected wedges, the uniform fallback
// and the boundary range) reads best in one place.
GeodesicTracer::Start GeodesicTracer::vertex_start(Index v, const Eigen::Vector3d& d) const {
  const std::string where = "vertex " + std::to_string(v);
  if (tri_.vertex_halfedge(v) == kInvalidIndex) {
    throw InvalidInput(where + " is on no face: no direction to leave it in");
  }
  const std::vector<Index> fan = vertex_fan(tri_, v);
  if (static_cast<Index>(fan.size()) != out_degree_[v]) {
    throw InvalidInput(where +
                       " is pinched (its faces form several fans): no single tangent "
                       "plane; start from a face point (face:F:u:v) next to it");
  }
  const bool boundary = tri_.twin(fan.front()) == kInvalidIndex;
  const Eigen::Vector3d xv = input_.positions.row(v).transpose();
  auto at = [&](Index u) -> Eigen::Vector3d { return input_.positions.row(u).transpose() - xv; };
  // the fan's edges E_0..E_m (interior: E_m is E_0 again) and corners; angle-weighted normal
  const std::size_t m = fan.size();
  std::vector<Eigen::Vector3d> edge(m + 1);
  std::vector<double> corner(m);
  Eigen::Vector3d n = Eigen::Vector3d::Zero();
  double theta_v = 0.0;
  for (std::size_t i = 0; i < m; ++i) {
    edge[i] = at(tri_.head(fan[i]));
    edge[i + 1] = at(tri_.tail(T::prev(fan[i])));
    corner[i] = intrinsic::corner_angle(tri_, fan[i]);
    theta_v += corner[i];
    const Eigen::Vector3d fn = edge[i].cross(edge[i + 1]);
    if (fn.norm() > 0.0) n += corner[i] * fn.normalized();
  }
  if (!(n.norm() > 0.0)) throw InvalidInput(where + " has no normal (its faces have no area)");
  n.normalize();
  const Eigen::Vector3d t = tangent_part(d, n, where);
  auto flat = [&](const Eigen::Vector3d& x) -> Eigen::Vector3d { return x - x.dot(n) * n; };
  // turns between consecutive projected edges; valid when they go round v in order
  std::vector<double> step(m);
  double total = 0.0;
  bool ordered = true;
  for (std::size_t i = 0; i < m; ++i) {
    double a = turn(flat(edge[i]), flat(edge[i + 1]), n);
    if (!boundary && m == 1) a = kTwoPi;
    step[i] = a;
    total += a;
    ordered = ordered && a > 0.0 && a < M_PI + 1e-12;
  }
  ordered = ordered && (boundary ? total < kTwoPi : std::abs(total - kTwoPi) < 1e-9);
  double theta = turn(flat(edge[0]), t, n);
  double range = boundary ? (ordered ? total : turn(flat(edge[0]), flat(edge[m]), n)) : kTwoPi;
  if (!(range > 0.0)) range = kTwoPi;
  if (boundary && theta > range + 1e-12) {
    if (theta < kTwoPi - 1e-12) {
      throw InvalidInput("direction " + vec_text(d) + " points off the surface at boundary " +
                         where + " (its faces span " + std::to_string(range * 180.0 / M_PI) +
                         "° of the tangent plane from the first boundary edge)");
    }
    theta = 0.0;
  }
  theta = std::min(theta, range);
  // the wedge i and the angle alpha into its corner
  std::size_t i = 0;
  double alpha = 0.0;
  if (ordered) {
    while (i + 1 < m && theta >= step[i]) theta -= step[i++];
    alpha = corner[i] * std::clamp(theta / step[i], 0.0, 1.0);
  } else {
    double phi = theta * theta_v / range;
    while (i + 1 < m && phi >= corner[i]) phi -= corner[i++];
    alpha = std::clamp(phi, 0.0, corner[i]);
  }
  Start s;
  const Index h = fan[i];
  const int side = static_cast<int>(T::side(h));
  s.point.face = T::face(h);
  s.point.bary[side] = 1.0;
  s.corner = side;
  Eigen::Vector2d p[3];
  intrinsic::face_layout(tri_, s.point.face, p);
  const Eigen::Vector2d e = (p[(side + 1) % 3] - p[side]).normalized();
  s.direction = std::cos(alpha) * e + std::sin(alpha) * Eigen::Vector2d(-e.y(), e.x());
  return s;
}

GeodesicRay GeodesicTracer::trace(const GivenPoint& start, const Eigen::Vector3d& direction,
                                  double length, const TraceGeodesicOptions& options) const {
  const std::string problem = point_problem(start, input_);
  if (!problem.empty()) throw InvalidInput("start " + problem);
  if (!direction.allFinite() || !(direction.norm() > 0.0)) {
    throw InvalidInput("direction " + vec_text(direction) + " must be finite and nonzero");
  }
  if (!std::isfinite(length) || length < 0.0) {
    throw InvalidInput("length " + std::to_string(length) + " must be finite and ≥ 0");
  }
  Start s;
  Index at_vertex = start.vertex;
  if (at_vertex == kInvalidIndex) {
    for (int k = 0; k < 3; ++k) {
      if (start.bary[k] >= 1.0 - kAtVertex) at_vertex = input_.triangles[start.face][k];
    }
  }
  s = at_vertex != kInvalidIndex ? vertex_start(at_vertex, direction)
                                 : face_start(start, direction);
  intrinsic::TraceOptions o;
  o.start_corner = s.corner;
  o.slide_on_boundary = options.slide_on_boundary;
  o.record_path = true;
  const intrinsic::TraceResult r = intrinsic::trace_straight(tri_, s.point, s.direction, length, o);
  GeodesicRay ray;
  for (const SurfacePoint& q : r.path) {
    const Eigen::Vector3d x = position(q.face, q.bary);
    if (!x.allFinite()) {
      throw TraceError("trace: the ray crossed a face without area near input face " +
                       std::to_string(face_origin_[q.face]));
    }
    if (!ray.polyline.empty() && (x - ray.polyline.back()).norm() <= merge_distance_) continue;
    if (!ray.polyline.empty()) ray.length += (x - ray.polyline.back()).norm();
    ray.polyline.push_back(x);
  }
  ray.end = on_input(r.end.face, r.end.bary);
  ray.start_direction = to_3d(s.point.face, s.direction).normalized();
  ray.end_direction = to_3d(r.end.face, r.direction).normalized();
  ray.hit_boundary = r.hit_boundary;
  ray.slides = r.slides;
  return ray;
}

namespace {

// "" when x, y, z are three finite numbers, not all zero (into d), else what is wrong.
std::string direction_problem(const std::vector<std::string>& xyz, const std::string& text,
                              Eigen::Vector3d& d) {
  const std::string expected =
      io::quoted_excerpt(text) + " is not a direction: expected X,Y,Z (three finite numbers)";
  if (xyz.size() != 3) return expected;
  for (int k = 0; k < 3; ++k) {
    if (!io::parse_whole_real(xyz[k], d[k]) || !std::isfinite(d[k])) return expected;
  }
  if (!(d.norm() > 0.0)) return io::quoted_excerpt(text) + ": the zero direction points nowhere";
  return "";
}

}  // namespace

std::string parse_direction(const std::string& text, Eigen::Vector3d& d) {
  return direction_problem(split_fields(text, ','), text, d);
}

std::vector<Eigen::Vector3d> read_directions_file(const std::string& path) {
  std::ifstream in(path);
  if (!in) throw IoError(path + ": cannot open");
  std::vector<Eigen::Vector3d> out;
  std::string text;
  for (long n = 1; std::getline(in, text); ++n) {
    const std::string body = text.substr(0, text.find('#'));
    const std::vector<std::string> tokens = io::line_tokens(body);
    if (tokens.empty()) continue;
    Eigen::Vector3d d;
    const std::string problem = direction_problem(tokens, body, d);
    if (!problem.empty()) throw IoError(path + ":" + std::to_string(n) + ": " + problem);
    out.push_back(d);
  }
  if (out.empty()) throw IoError(path + ": no direction (expected 'X Y Z' lines)");
  return out;
}

GeodesicRay trace_geodesic(const io::SurfaceInput& input, const GivenPoint& start,
                           const Eigen::Vector3d& direction, double length,
                           const TraceGeodesicOptions& options) {
  return GeodesicTracer(input).trace(start, direction, length, options);
}

}  // namespace ifem::recipes
