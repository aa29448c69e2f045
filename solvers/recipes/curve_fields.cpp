// Direction fields aligned to curves (curve_fields.h).
#include "solvers/recipes/curve_fields.h"

#include <complex>
#include <string>

#include "intrinsic/core/errors.h"
#include "intrinsic/core/geometry.h"

namespace ifem::solvers {

std::vector<DirectionConstraint> curve_constraints(const intrinsic::IntrinsicTriangulation& tri,
                                                   const intrinsic::CurveNetwork& network,
                                                   const fem::TangentFrames& frames) {
  const Index nh = tri.n_halfedges();
  if (frames.halfedge_angle.size() != nh || frames.transport.size() != nh ||
      static_cast<Index>(network.edges.size()) != tri.n_edges()) {
    throw InvalidInput(
        "curve_constraints: the frames or the curve network are not the "
        "triangulation's (" +
        std::to_string(frames.halfedge_angle.size()) + " halfedge angles, " +
        std::to_string(network.edges.size()) + " curve edges for " + std::to_string(nh) +
        " halfedges, " + std::to_string(tri.n_edges()) + " edges)");
  }
  constexpr double kPi = intrinsic::kPi;
  std::vector<DirectionConstraint> out;
  for (Index c = 0; c < network.n_curves(); ++c) {
    const intrinsic::CurveChain ch = intrinsic::curve_chain(tri, network, c);
    for (std::size_t i = 0; i < ch.edges.size(); ++i) {
      const Index a = ch.vertices[i], b = ch.vertices[i + 1];  // the curve runs a → b
      const Index h = ch.left_halfedges[i];
      // θ_h + arg r_h: the direction at head(h) pointing away from tail(h) (fem/connection.h)
      if (h != kInvalidIndex) {  // h runs a → b
        out.push_back({a, frames.halfedge_angle[h]});
        out.push_back({b, frames.halfedge_angle[h] + std::arg(frames.transport[h])});
      } else {  // the curve runs against a boundary side: its only halfedge runs b → a
        const Index g = tri.edge_halfedge(ch.edges[i]);
        out.push_back({a, frames.halfedge_angle[g] + std::arg(frames.transport[g]) + kPi});
        out.push_back({b, frames.halfedge_angle[g] + kPi});
      }
    }
  }
  return out;
}

TangentFieldResult curve_direction_field(const CurveSurface& s, const FieldOptions& settings) {
  FieldOptions all = settings;
  const std::vector<DirectionConstraint> along =
      curve_constraints(s.surface.tri, s.network, fem::tangent_frames(s.surface.tri));
  all.intrinsic_constraints.insert(all.intrinsic_constraints.end(), along.begin(), along.end());
  return direction_field_on(s.surface, all);
}

}  // namespace ifem::solvers
