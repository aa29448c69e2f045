// Signed distance to curves and oriented points (signed_distance.h).
#include "solvers/recipes/signed_distance.h"

#include <algorithm>
#include <cmath>
#include <complex>
#include <string>

#include "fem/connection.h"
#include "intrinsic/core/errors.h"
#include "intrinsic/core/geometry.h"
#include "intrinsic/geodesic/curve_network.h"

namespace ifem::solvers {
namespace {

using Complex = std::complex<double>;

SignedHeatOptions heat_options(const PreparedSurface& s, const SignedDistanceOptions& options) {
  options.validate();
  SignedHeatOptions o;
  o.time_factor = options.time_factor;
  o.level_set = options.level_set;
  o.mean_edge_length = distance_options(s).mean_edge_length;  // 0 on point clouds: tri's mean
  return o;
}

// The curves on a copy of the constrained triangulation, each curve edge split into pieces of
// at most `target` (a long curve edge leaves its normals at two far-apart vertices and slivers
// beside it; with pieces of about h the diffusion sees the curve as the paper's source), then
// flipped to the constrained Delaunay triangulation again. from[e]: the vertex curve edge e
// starts at (the curve runs from[e] → the other end), kInvalidIndex on other edges.
struct SplitCurves {
  intrinsic::IntrinsicTriangulation tri;
  std::vector<Index> from;
};

SplitCurves split_curves(const CurveSurface& s, double target) {
  SplitCurves out{s.surface.tri, std::vector<Index>(s.surface.tri.n_edges(), kInvalidIndex)};
  intrinsic::IntrinsicTriangulation& tri = out.tri;
  std::vector<Index>& from = out.from;
  std::vector<Index> curve_edges;
  for (Index c = 0; c < s.network.n_curves(); ++c) {
    const intrinsic::CurveChain ch = intrinsic::curve_chain(tri, s.network, c);
    for (std::size_t i = 0; i < ch.edges.size(); ++i) {
      from[ch.edges[i]] = ch.vertices[i];
      curve_edges.push_back(ch.edges[i]);
    }
  }
  for (const Index e : curve_edges) {
    Index cur = e;
    for (int p = int(std::ceil(tri.length(e) / target - 1e-9)); p >= 2; --p) {
      if (!tri.can_split_edge(cur)) break;
      const Index h = tri.edge_halfedge(cur);
      const Index a = tri.tail(h), start = from[cur];
      const Index ne = tri.n_edges();  // the new edge m–head(h)
      const Index m = tri.split_edge(cur, 1.0 / p);
      from.resize(std::size_t(tri.n_edges()), kInvalidIndex);
      // cur is now a–m, ne is m–b: the curve runs a → m → b, or b → m → a
      from[cur] = start == a ? a : m;
      from[ne] = start == a ? m : start;
      cur = ne;
    }
  }
  tri.flip_to_delaunay([&](Index e) { return from[e] == kInvalidIndex && tri.flip_edge(e); });
  return out;
}

// The curves' integrated normals (right-hand side of the direction of travel: the direction
// turned by −π/2 in the counter-clockwise angular coordinates), their vertices and the length
// each vertex stands for.
SignedHeatSources curve_sources(const SplitCurves& c) {
  const intrinsic::IntrinsicTriangulation& tri = c.tri;
  const fem::TangentFrames frames = fem::tangent_frames(tri);
  constexpr double kPi = intrinsic::kPi;
  SignedHeatSources src;
  src.normals = Eigen::VectorXcd::Zero(tri.n_vertices());
  std::vector<double> share(tri.n_vertices(), -1.0);
  auto add = [&](Index v, double direction, double half_length) {
    src.normals[v] += std::polar(half_length, direction - 0.5 * kPi);
    share[v] = std::max(share[v], 0.0) + half_length;
  };
  for (Index e = 0; e < tri.n_edges(); ++e) {
    if (c.from[e] == kInvalidIndex) continue;
    const Index g = tri.edge_halfedge(e);
    const double half = 0.5 * tri.length(e);
    // θ_g at tail(g) towards head(g); θ_g + arg r_g at head(g) pointing away from tail(g)
    const double at_tail = frames.halfedge_angle[g];
    const double at_head = at_tail + std::arg(frames.transport[g]);
    if (tri.tail(g) == c.from[e]) {  // the curve runs along g
      add(tri.tail(g), at_tail, half);
      add(tri.head(g), at_head, half);
    } else {  // against g: travelling head → tail
      add(tri.head(g), at_head + kPi, half);
      add(tri.tail(g), at_tail + kPi, half);
    }
  }
  for (Index v = 0; v < tri.n_vertices(); ++v) {
    if (share[v] < 0.0) continue;
    src.zero_set.push_back(v);
    src.zero_weights.push_back(share[v]);
  }
  if (src.zero_set.empty()) throw InvalidInput("signed_distance: no curve");
  return src;
}

}  // namespace

void SignedDistanceOptions::validate() const {
  if (!(time_factor > 0.0) || !std::isfinite(time_factor)) {
    throw InvalidInput("SignedDistanceOptions: time_factor must be > 0 and finite, got " +
                       std::to_string(time_factor));
  }
}

Eigen::VectorXd signed_distance(const CurveSurface& s, const SignedDistanceOptions& options,
                                SignedDistanceReport* report) {
  SignedHeatOptions o = heat_options(s.surface, options);
  if (!(o.mean_edge_length > 0.0)) o.mean_edge_length = intrinsic::mean_edge_length(s.surface.tri);
  const SplitCurves split = split_curves(s, o.mean_edge_length);
  const Eigen::VectorXd d = signed_heat_distance(split.tri, curve_sources(split), o, report);
  return d.head(s.n_input_vertices());
}

Eigen::VectorXd signed_distance(const PreparedSurface& s, const std::vector<InputDirection>& points,
                                const SignedDistanceOptions& options,
                                SignedDistanceReport* report) {
  const SignedHeatOptions o = heat_options(s, options);
  if (points.empty()) throw InvalidInput("signed_distance: no oriented point");
  const Index nv = s.n_input_vertices();
  if (s.tri.n_vertices() != nv) {
    throw InvalidInput(
        "signed_distance: oriented points use frames from the input's positions, so every "
        "vertex must be an input vertex: do not refine");
  }
  const TangentBasis3d basis = frame_basis_3d(s.input, s.tri);
  const double h =
      o.mean_edge_length > 0.0 ? o.mean_edge_length : intrinsic::mean_edge_length(s.tri);
  SignedHeatSources src;
  src.normals = Eigen::VectorXcd::Zero(nv);
  for (std::size_t k = 0; k < points.size(); ++k) {
    const InputDirection& p = points[k];
    const std::string name = p.origin.empty() ? "point " + std::to_string(k) : p.origin;
    if (p.vertex < 0 || p.vertex >= nv || s.tri.vertex_halfedge(p.vertex) == kInvalidIndex) {
      throw InvalidInput("signed_distance: " + name + ": vertex " + std::to_string(p.vertex) +
                         " is out of range [0, " + std::to_string(nv) + ") or used by no face");
    }
    const double len = p.direction.norm();
    if (!(len > 0.0) || !std::isfinite(len)) {
      throw InvalidInput("signed_distance: " + name + ": the normal is zero or not finite");
    }
    const Complex z(p.direction.dot(basis.e1.row(p.vertex)),
                    p.direction.dot(basis.e2.row(p.vertex)));
    if (std::abs(z) < 1e-3 * len) {
      throw InvalidInput("signed_distance: " + name +
                         ": the normal is normal to the surface (it must point along it, to the "
                         "positive side)");
    }
    if (src.normals[p.vertex] != Complex(0.0)) {
      throw InvalidInput("signed_distance: " + name + ": vertex " + std::to_string(p.vertex) +
                         " is given twice");
    }
    src.normals[p.vertex] = z * (h / std::abs(z));
    src.zero_set.push_back(p.vertex);
  }
  return on_input_vertices(s,
                           signed_heat_distance(s.tri, s.input.positions, basis, src, o, report));
}

}  // namespace ifem::solvers
