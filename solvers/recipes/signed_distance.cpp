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

using cd = std::complex<double>;

SignedHeatOptions heat_options(const PreparedSurface& s, const SignedDistanceOptions& options) {
  options.validate();
  SignedHeatOptions o;
  o.time_factor = options.time_factor;
  o.level_set = options.level_set;
  o.mean_edge_length = distance_options(s).mean_edge_length;  // 0 on point clouds: tri's mean
  return o;
}

// The curves' integrated normals (right-hand side of the direction of travel: the direction
// turned by −π/2 in the counter-clockwise angular coordinates), their vertices and the length
// each vertex stands for.
SignedHeatSources curve_sources(const CurveSurface& s) {
  const intrinsic::IntrinsicTriangulation& tri = s.surface.tri;
  const fem::TangentFrames frames = fem::tangent_frames(tri);
  constexpr double kPi = intrinsic::kPi;
  SignedHeatSources src;
  src.normals = Eigen::VectorXcd::Zero(tri.n_vertices());
  std::vector<double> share(tri.n_vertices(), -1.0);
  auto add = [&](Index v, double direction, double half_length) {
    src.normals[v] += std::polar(half_length, direction - 0.5 * kPi);
    share[v] = std::max(share[v], 0.0) + half_length;
  };
  for (Index c = 0; c < s.network.n_curves(); ++c) {
    const intrinsic::CurveChain ch = intrinsic::curve_chain(tri, s.network, c);
    for (std::size_t i = 0; i < ch.edges.size(); ++i) {
      const Index a = ch.vertices[i], b = ch.vertices[i + 1];  // the curve runs a → b
      const double half = 0.5 * tri.length(ch.edges[i]);
      const Index h = ch.left_halfedges[i];
      if (h != kInvalidIndex) {  // h runs a → b (fem/connection.h: θ_h + arg r_h at head(h))
        add(a, frames.halfedge_angle[h], half);
        add(b, frames.halfedge_angle[h] + std::arg(frames.transport[h]), half);
      } else {  // against a boundary side: its only halfedge runs b → a
        const Index g = tri.edge_halfedge(ch.edges[i]);
        add(a, frames.halfedge_angle[g] + std::arg(frames.transport[g]) + kPi, half);
        add(b, frames.halfedge_angle[g] + kPi, half);
      }
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
  const SignedHeatOptions o = heat_options(s.surface, options);
  const SignedHeatSources src = curve_sources(s);
  return on_input_vertices(s.surface, signed_heat_distance(s.surface.tri, src, o, report));
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
  const double h = o.mean_edge_length > 0.0 ? o.mean_edge_length : intrinsic::mean_edge_length(s.tri);
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
    const cd z(p.direction.dot(basis.e1.row(p.vertex)), p.direction.dot(basis.e2.row(p.vertex)));
    if (std::abs(z) < 1e-3 * len) {
      throw InvalidInput("signed_distance: " + name +
                         ": the normal is normal to the surface (it must point along it, to the "
                         "positive side)");
    }
    if (src.normals[p.vertex] != cd(0.0)) {
      throw InvalidInput("signed_distance: " + name + ": vertex " + std::to_string(p.vertex) +
                         " is given twice");
    }
    src.normals[p.vertex] = z * (h / std::abs(z));
    src.zero_set.push_back(p.vertex);
  }
  return on_input_vertices(
      s, signed_heat_distance(s.tri, s.input.positions, basis, src, o, report));
}

}  // namespace ifem::solvers
