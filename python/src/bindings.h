// The pieces of the extension module ifem._ifem, one function per area (bind_*.cpp), called by
// module.cpp. Conventions for every binding:
//  - arrays are checked and converted (arrays.h) while the GIL is held; the computation itself
//    runs with the GIL released (py::gil_scoped_release), so other Python threads go on;
//  - results go to numpy without copies (arrays.h to_numpy / to_csc_parts);
//  - ifem's exceptions become ifem.InvalidInput / NonManifoldInput / IoError / SolverError / ...
//    (python/ifem/_errors.py) with the same messages (module.cpp).
#pragma once

#include <pybind11/pybind11.h>

#include <optional>
#include <utility>

#include "intrinsic/integer/correspondence.h"
#include "intrinsic/refine/signpost.h"
#include "solvers/recipes/curves.h"
#include "solvers/recipes/pipeline.h"

namespace ifem::python {

namespace py = pybind11;

void bind_mesh(py::module_& m);       // read_mesh, write_ply
void bind_operators(py::module_& m);  // laplacian, point_cloud_laplacian
void bind_solvers(py::module_& m);    // heat distance, eigenpairs, Poisson
void bind_refine(py::module_& m);     // refinement handle, common subdivision, save / load
void bind_geodesic(py::module_& m);   // FlipOut paths, loops, networks, Bézier curves
void bind_curves(py::module_& m);     // boundary-value problems with data on curves
void bind_fields(py::module_& m);     // tangent fields: smoothest direction fields
void bind_view(py::module_& m);       // `ifem view`'s page
void bind_render(py::module_& m);     // headless pictures (PNG)
void bind_isolines(py::module_& m);   // level sets of a per-vertex field as polylines
void bind_signed(py::module_& m);     // signed distance (signed heat method)
void bind_exact(py::module_& m);      // exact geodesic distance
void bind_trace(py::module_& m);      // straight geodesics from a point (exponential map)
void bind_simplify(py::module_& m);   // intrinsic simplification and its prolongation

/// The refined triangulation (ifem.refine's handle, bind_refine.cpp) and what refining it
/// reported (no report after load()); bind_view.cpp traces its edges.
struct Refined {
  explicit Refined(intrinsic::SavedTriangulation&& s) : saved(std::move(s)) {}
  intrinsic::SavedTriangulation saved;  ///< signposts or integer coordinates
  intrinsic::CorrespondenceView st() const { return saved.view(); }
  std::optional<py::dict> report;    // built while the GIL is held
  double memory_budget_bytes = 0.0;  // for the common subdivision; 0: the library's default
};

/// The library's ProgressCallback for a Python `progress` argument: None gives an empty one (no
/// reports, no cost); a callable is called as progress(fraction, stage) with the GIL taken for
/// the call. The callable is held by pointer, without a reference: the caller's argument keeps
/// it alive during the call, and copies of the callback made with the GIL released touch no
/// reference count. An exception it raises ends the computation and reaches the caller.
/// @throws InvalidInput if `progress` is neither None nor callable
ProgressCallback progress_callback(const py::handle& progress);

/// PrepareOptions from the keyword arguments every surface function shares (Python names):
/// mollify (relative margin ≥ 0), path ('auto' | 'manifold' | 'tufted' | 'pointcloud'),
/// intrinsic_delaunay (bool), k (neighbours on the point-cloud path).
/// @throws InvalidInput on an unknown path name
solvers::PrepareOptions prepare_options(double mollify, const std::string& path,
                                        bool intrinsic_delaunay, int k);

/// prepare_surface() on arrays with the GIL released; with path 'manifold', a surface that had
/// to take another path is refused (NonManifoldInput, with the reason).
solvers::PreparedSurface prepare(io::SurfaceInput input, const solvers::PrepareOptions& options,
                                 const std::string& path);

/// What preparing chose and did (path and why, flips, mollification, repairs, vertex counts,
/// refinement), for the `info` dicts of the Python functions.
py::dict surface_info(const solvers::PreparedSurface& s);

/// solvers::prepare_curve_surface() of an input and curve specs (ifem.Curve's tuples, see
/// bind_curves.cpp), with the GIL released; refine: None or (min_angle, resolution, max_area,
/// max_insertions). `need_values`: every curve must carry values (Poisson). max_iterations:
/// FlipOut's cap on the curves (−1: the library's default); accept_partial: curves left at it
/// are accepted (CurveSurfaceOptions).
/// @throws InvalidInput naming the curve, as validate_curves(), and on bad options
solvers::CurveSurface prepare_with_curves(io::SurfaceInput input, const py::list& specs,
                                          const py::handle& refine, double mollify,
                                          bool need_values, Index max_iterations = -1,
                                          bool accept_partial = false);

/// What inserting curves did (FlipOut, flips, weights' signs, refinement), for `info` dicts.
py::dict curve_surface_info(const solvers::CurveSurface& s);

}  // namespace ifem::python
