// The refinement cross-check (crosscheck.h).
#include "intrinsic/integer/crosscheck.h"

#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <exception>
#include <limits>
#include <vector>

#include "intrinsic/core/timer.h"
#include "intrinsic/integer/correspondence.h"

namespace ifem::intrinsic {

namespace {

double triangle_area_3d(const Positions& x, Index a, Index b, Index c) {
  const Eigen::Vector3d pa = x.row(a), pb = x.row(b), pc = x.row(c);
  return 0.5 * (pb - pa).cross(pc - pa).norm();
}

// RefineRun::area_partition_error of cs over the input of view c.
double area_partition_error(const CorrespondenceView& c, const CommonSubdivision& cs,
                            const std::vector<Index>& origin) {
  const IntrinsicTriangulation& input = c.input();
  const Positions& x = c.input_positions();
  Index n_given = 0;
  for (const Index g : origin) n_given = std::max(n_given, g + 1);
  std::vector<double> want(static_cast<std::size_t>(n_given), 0.0), got = want;
  double total = 0.0;
  for (Index f = 0; f < input.n_faces(); ++f) {
    const double a =
        triangle_area_3d(x, input.tail(3 * f), input.tail(3 * f + 1), input.tail(3 * f + 2));
    want[static_cast<std::size_t>(origin[f])] += a;
    total += a;
  }
  for (std::size_t i = 0; i < cs.faces.size(); ++i) {
    const Triangle& t = cs.faces[i];
    const auto g = static_cast<std::size_t>(cs.input_face[i]);
    if (g >= got.size()) return std::numeric_limits<double>::infinity();
    got[g] += triangle_area_3d(cs.positions, t[0], t[1], t[2]);
  }
  double worst = 0.0;
  for (std::size_t g = 0; g < got.size(); ++g) worst = std::max(worst, std::abs(got[g] - want[g]));
  const double mean = input.n_faces() > 0 ? total / double(input.n_faces()) : 0.0;
  return mean > 0.0 ? worst / mean : worst;
}

// Refines `out` (a copy of the input triangulation) and builds its common subdivision; `first`
// receives the subdivision's first #V positions (the intrinsic vertices' locations).
template <class Tri>
RefineRun run_refine(Tri& out, const RefineOptions& options, const std::vector<Index>& origin,
                     Positions& first) {
  RefineRun r;
  try {
    Stopwatch watch;
    r.report = delaunay_refine(out, options);
    r.seconds = watch.restart();
    const CorrespondenceView view(out);
    const CommonSubdivision cs = view.common_subdivision();
    r.subdivision_seconds = watch.restart();
    r.subdivision_vertices = static_cast<Index>(cs.positions.rows());
    r.subdivision_faces = static_cast<Index>(cs.faces.size());
    r.area_partition_error = area_partition_error(view, cs, origin);
    first =
        cs.positions.topRows(std::min<Index>(cs.positions.rows(), out.intrinsic().n_vertices()));
    r.ok = true;
  } catch (const std::exception& e) {
    r.error = e.what();
  }
  return r;
}

double mean_edge_length(const IntrinsicTriangulation& tri) {
  double sum = 0.0;
  for (Index e = 0; e < tri.n_edges(); ++e) sum += tri.length(e);
  return tri.n_edges() > 0 ? sum / double(tri.n_edges()) : 0.0;
}

}  // namespace

bool RefineCrosscheck::agree() const {
  return same_insertions && max_length_difference <= 1e-9 * mean_length &&
         max_vertex_distance <= 1e-6 * mean_length;
}

RefineCrosscheck crosscheck_refine(const SignpostTriangulation& s0,
                                   const NormalCoordinateTriangulation& n0,
                                   const RefineOptions& options, SignpostTriangulation* s_out,
                                   NormalCoordinateTriangulation* n_out) {
  SignpostTriangulation st = s0;
  NormalCoordinateTriangulation nc = n0;
  Positions xs, xn;
  RefineCrosscheck c;
  c.signposts = run_refine(st, options, n0.input_face_origin(), xs);
  c.integer = run_refine(nc, options, n0.input_face_origin(), xn);
  if (c.signposts.ok && c.integer.ok) {
    const RefineReport &a = c.signposts.report, &b = c.integer.report;
    c.same_insertions = a.insertions == b.insertions && a.face_insertions == b.face_insertions &&
                        a.edge_splits == b.edge_splits && a.boundary_splits == b.boundary_splits &&
                        a.constrained_splits == b.constrained_splits;
    const auto& la = st.intrinsic().lengths();
    const auto& lb = nc.intrinsic().lengths();
    const double inf = std::numeric_limits<double>::infinity();
    c.max_length_difference = la.size() == lb.size() ? 0.0 : inf;
    for (std::size_t e = 0; e < la.size() && e < lb.size(); ++e) {
      c.max_length_difference = std::max(c.max_length_difference, std::abs(la[e] - lb[e]));
    }
    c.max_vertex_distance =
        xs.rows() == xn.rows() && xs.rows() > 0 ? (xs - xn).rowwise().norm().maxCoeff() : inf;
    c.mean_length = mean_edge_length(nc.intrinsic());
  }
  if (s_out != nullptr) *s_out = std::move(st);
  if (n_out != nullptr) *n_out = std::move(nc);
  return c;
}

}  // namespace ifem::intrinsic
