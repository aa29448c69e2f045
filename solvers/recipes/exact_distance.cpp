#include "solvers/recipes/exact_distance.h"

#include <string>
#include <utility>

#include "intrinsic/core/errors.h"

namespace ifem::solvers {

Eigen::VectorXd exact_distance(const PreparedSurface& s, const std::vector<Index>& sources,
                               const intrinsic::ExactDistanceOptions& options,
                               intrinsic::ExactDistance* full) {
  if (sources.empty()) throw InvalidInput("exact_distance: no source vertex given");
  const Index nv = s.n_input_vertices();
  for (std::size_t k = 0; k < sources.size(); ++k) {
    const Index v = sources[k];
    if (v < 0 || v >= nv) {
      throw InvalidInput("exact_distance: source " + std::to_string(v) + " (position " +
                         std::to_string(k) + ") is not an input vertex id in [0, " +
                         std::to_string(nv) + ")");
    }
    if (s.tri.vertex_halfedge(v) == kInvalidIndex) {
      throw InvalidInput("exact_distance: source " + std::to_string(v) +
                         " is used by no face (nothing to measure from)");
    }
  }
  intrinsic::ExactDistance d = intrinsic::exact_distance(s.tri, sources, options);
  Eigen::VectorXd out = on_input_vertices(s, d.distance);
  if (full != nullptr) *full = std::move(d);
  return out;
}

std::vector<std::vector<Eigen::Vector3d>> exact_paths_3d(const PreparedSurface& s,
                                                         const intrinsic::ExactDistance& full,
                                                         const std::vector<Index>& from) {
  if (s.refined || s.flips.flips > 0) {
    throw InvalidInput(
        "exact paths are placed on the input's own faces: prepare the surface without intrinsic "
        "Delaunay flips and without refinement");
  }
  const Index nv = s.n_input_vertices();
  const auto& x = s.input.positions;
  std::vector<std::vector<Eigen::Vector3d>> out;
  out.reserve(from.size());
  for (const Index v : from) {
    if (v < 0 || v >= nv) {
      throw InvalidInput("exact paths: vertex " + std::to_string(v) +
                         " is not an input vertex id in [0, " + std::to_string(nv) + ")");
    }
    out.push_back(path_points_3d(s.tri, full.path_to_source(v),
                                 [&](Index u) -> Eigen::Vector3d { return x.row(u).transpose(); }));
  }
  return out;
}

}  // namespace ifem::solvers
