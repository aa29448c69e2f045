// One name per operation: the recipes under the names of the CLI's commands (the README's
// name table; python/tests/test_vocabulary.py checks that every operation there is declared
// here or in geodesic.h). Each takes a prepared surface (prepare_surface() / load_surface(),
// pipeline.h: the input on the right path) and returns results on the input's vertices, in the
// input's order:
//
//   ifem info       recipes::info()       what the input is made of and the path it took
//   ifem laplacian  recipes::laplacian()  cotan Laplacian L and lumped mass M of s.tri
//   ifem refine     recipes::refine()     prepare with intrinsic Delaunay refinement
//   ifem distance   recipes::distance()   geodesic distance by the heat method
//   ifem eigen      recipes::eigen()      smallest Laplace–Beltrami eigenpairs
//   ifem poisson    recipes::poisson()    (L + c·M) u = M f with Dirichlet values
//   ifem geodesic   recipes::geodesic()   FlipOut curves, single-source geodesics (geodesic.h)
//   ifem field      recipes::field()      smoothest / aligned n-direction field
//   ifem transport  recipes::transport()  parallel transport (vector heat method)
//   ifem logmap     recipes::logmap()     logarithmic map (affine + vector heat blend)
//   ifem view       recipes::view()       one offline HTML page of a scene (view_scene.h)
//   ifem render     recipes::render()     a picture of a mesh, a field and curves (render.h)
//   ifem trace      recipes::trace()      straight geodesics from a point (trace_geodesic.h)
//   ifem simplify   recipes::simplify()   intrinsic simplification, map to the input
//   ifem transfer   recipes::transfer()   per-vertex values onto the refinement or back
//
// These forward to the solvers:: functions that implement them (named after what they compute:
// geodesic_distance, eigenmodes, direction_field_on, ...); use those for the variants (several
// sources at once, a reused VectorHeatSolver, reports).
#pragma once

#include <Eigen/Core>
#include <string>
#include <utility>
#include <vector>

#include "fem/attribute_transfer.h"
#include "fem/operators.h"
#include "intrinsic/simplify/simplify.h"
#include "solvers/recipes/geodesic.h"
#include "solvers/recipes/pipeline.h"
#include "solvers/recipes/render.h"
#include "solvers/recipes/surface_summary.h"
#include "solvers/recipes/tangent_fields.h"
#include "solvers/recipes/trace_geodesic.h"
#include "solvers/recipes/view_scene.h"

namespace ifem::recipes {

using solvers::PreparedSurface;

/// `ifem info`: counts, topology, defects, the path taken (solvers::summarize_mesh).
inline solvers::MeshSummary info(const PreparedSurface& s) { return solvers::summarize_mesh(s); }

/// The operators of `ifem laplacian`, on every vertex of s.tri (#V ≥ #V_in: the input's first).
struct Laplacian {
  fem::SparseMatrix L;   ///< #V×#V cotan Laplacian, positive semi-definite, L·1 = 0
  Eigen::VectorXd mass;  ///< #V lumped (diagonal) mass
};

/// `ifem laplacian`: L and M of the prepared (intrinsic Delaunay) triangulation.
inline Laplacian laplacian(const PreparedSurface& s) {
  return {fem::cotan_laplacian(s.tri), fem::lumped_mass(s.tri)};
}

/// `ifem refine`: prepare_surface() with intrinsic Delaunay refinement.
/// @throws InvalidInput as prepare_surface() and SurfaceRefineOptions::validate()
inline PreparedSurface refine(io::SurfaceInput input,
                              const solvers::SurfaceRefineOptions& refinement,
                              solvers::PrepareOptions options = {}) {
  options.refine = refinement;
  return solvers::prepare_surface(std::move(input), options);
}

/// `ifem distance`: geodesic distance from input vertices, #V_in (solvers::geodesic_distance).
inline Eigen::VectorXd distance(const PreparedSurface& s, const std::vector<Index>& sources,
                                const solvers::DistanceOptions& options = {}) {
  return solvers::geodesic_distance(s, sources, options);
}

/// `ifem transfer`: per-vertex values carried from the input's vertices (#V_in) onto every
/// vertex of s.tri (#V, the input's first), or with back from s.tri's vertices onto the
/// input's (fem::transfer over s.correspondence()).
/// @throws InvalidInput if s was not refined with a correspondence (refine() first), and as
///         fem::transfer (sizes, non-finite values); SolverError as fem::transfer
inline Eigen::VectorXd transfer(const PreparedSurface& s, const Eigen::VectorXd& values,
                                fem::TransferMethod method, bool back = false) {
  const std::optional<intrinsic::CorrespondenceView> view = s.correspondence();
  if (!view) {
    throw InvalidInput(
        "transfer: the surface was not refined with a correspondence (signposts or integer "
        "coordinates): refine it first (recipes::refine, an edge-manifold orientable mesh)");
  }
  return fem::transfer(*view, values, method, back);
}

/// `ifem simplify`: the intrinsic simplification of s.tri (intrinsic::simplify); its
/// fine_in_coarse has one entry per vertex of s.tri (the input's first), fem::prolongation() of
/// it is P.
inline intrinsic::Simplification simplify(const PreparedSurface& s,
                                          const intrinsic::SimplifyOptions& options) {
  return intrinsic::simplify(s.tri, options);
}

/// `ifem eigen`: the k smallest eigenpairs, eigenvectors on the input (solvers::eigenmodes).
inline solvers::EigenPairs eigen(const PreparedSurface& s, Index k,
                                 const solvers::EigenOptions& options = {}) {
  return solvers::eigenmodes(s, k, options);
}

/// `ifem poisson`: (L + c·M) u = M f, u held at Dirichlet input vertices, #V_in
/// (solvers::poisson).
inline Eigen::VectorXd poisson(const PreparedSurface& s, const Eigen::VectorXd& f,
                               const std::vector<Index>& dirichlet_vertices,
                               const Eigen::VectorXd& dirichlet_values,
                               const solvers::PoissonOptions& options = {}) {
  return solvers::poisson(s, f, dirichlet_vertices, dirichlet_values, options);
}

/// `ifem field`: the smoothest (or aligned) n-direction field (solvers::direction_field_on).
inline solvers::TangentFieldResult field(const PreparedSurface& s,
                                         const solvers::FieldOptions& options = {}) {
  return solvers::direction_field_on(s, options);
}

/// `ifem transport`: a vector at input vertex `source` transported to every input vertex,
/// #V_in×3 (solvers::transport_on with a solver built for this one query).
inline Eigen::MatrixX3d transport(const PreparedSurface& s, Index source,
                                  const Eigen::Vector3d& vector) {
  return solvers::transport_on(s, solvers::vector_heat_solver(s), source, vector);
}

/// `ifem logmap`: the logarithmic map about input vertex `source`, #V_in×2
/// (solvers::log_map_on with a solver built for this one query).
inline Eigen::MatrixX2d logmap(const PreparedSurface& s, Index source) {
  return solvers::log_map_on(s, solvers::vector_heat_solver(s), source);
}

/// `ifem view`: writes the page of a scene (view_scene() and the add_*() of view_scene.h) to
/// `path`, with three.js from find_three_js(three_dir).
/// @throws IoError if three.js is not found or the page cannot be written
inline void view(const Scene& scene, const std::string& path, const std::string& three_dir = "") {
  write_view_page(path, scene, find_three_js(three_dir));
}

/// `ifem render`: a picture of a mesh, a per-vertex field and curves (solvers::render_scene;
/// write it with solvers::write_png). Needs no prepared surface: it draws the input as given.
inline solvers::Rendering render(const solvers::RenderScene& scene,
                                 const solvers::RenderOptions& options = {}) {
  return solvers::render_scene(scene, options);
}

/// `ifem trace`: the straight geodesic from `start` in `direction` for `length` over the input
/// as given (trace_geodesic(); many rays from one input: GeodesicTracer).
/// @throws InvalidInput, NonManifoldInput, TraceError as GeodesicTracer
inline GeodesicRay trace(const io::SurfaceInput& input, const GivenPoint& start,
                         const Eigen::Vector3d& direction, double length,
                         const TraceGeodesicOptions& options = {}) {
  return trace_geodesic(input, start, direction, length, options);
}

}  // namespace ifem::recipes
