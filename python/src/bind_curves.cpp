// Boundary-value problems with data on curves, as `ifem poisson --curves` and `ifem distance
// --curves` compute them (solvers/recipes/curves.h, examples/cli/cli_curves.cpp): curves through
// input vertices become edges of a constrained intrinsic Delaunay triangulation, then Poisson takes
// its Dirichlet data on them or the heat method measures the distance to them.
//
// A curve crosses the boundary as a tuple (the Python layer's ifem.Curve flattens to it):
//   (vertices: int64 1-D, shape: 'path' | 'loop' | 'bezier', rounds: int, values: float 1-D,
//    slit: bool, right_values: float 1-D, origin: str)
// where origin names the curve in messages ("curves[2]", or "file:line" for a curves file).
#include <pybind11/stl.h>

#include <cmath>
#include <cstdint>
#include <limits>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "arrays.h"
#include "bindings.h"
#include "intrinsic/core/errors.h"
#include "solvers/recipes/curves.h"

namespace ifem::python {

namespace {

using solvers::CurveCondition;
using Shape = intrinsic::CurveShape;

const char* shape_name(Shape s) {
  switch (s) {
    case Shape::kLoop:
      return "loop";
    case Shape::kBezier:
      return "bezier";
    case Shape::kPath:
      break;
  }
  return "path";
}

Shape shape_of(const std::string& name, const std::string& origin) {
  if (name == "path") return Shape::kPath;
  if (name == "loop") return Shape::kLoop;
  if (name == "bezier") return Shape::kBezier;
  throw InvalidInput(origin + ": shape must be 'path', 'loop' or 'bezier', got '" + name + "'");
}

// Vertex ids as given (the range is checked against the mesh later, by validate_curves).
std::vector<Index> ids_of(const py::handle& a, const std::string& origin) {
  const auto ids = py::array_t<std::int64_t, py::array::c_style | py::array::forcecast>::ensure(a);
  if (!ids || ids.ndim() != 1) {
    throw InvalidInput(origin + ": vertices must be a 1-D array of vertex ids");
  }
  std::vector<Index> out(static_cast<std::size_t>(ids.size()));
  for (std::size_t i = 0; i < out.size(); ++i) {
    const std::int64_t v = ids.data()[i];
    if (v < std::numeric_limits<Index>::min() || v > std::numeric_limits<Index>::max()) {
      throw InvalidInput(origin + ": vertex " + std::to_string(v) +
                         " is beyond any vertex id (ids are 32-bit)");
    }
    out[i] = static_cast<Index>(v);
  }
  return out;
}

std::vector<double> reals_of(const py::handle& a, const std::string& origin, const char* what) {
  const auto d = py::array_t<double, py::array::c_style | py::array::forcecast>::ensure(a);
  if (!d || d.ndim() != 1) throw InvalidInput(origin + ": " + what + " must be a 1-D array");
  return std::vector<double>(d.data(), d.data() + d.size());
}

CurveCondition condition_from(const py::handle& spec) {
  const py::tuple t = spec.cast<py::tuple>();
  if (t.size() != 7) throw InvalidInput("a curve spec must have 7 fields");
  CurveCondition c;
  c.origin = t[6].cast<std::string>();
  c.vertices = ids_of(t[0], c.origin);
  c.shape = shape_of(t[1].cast<std::string>(), c.origin);
  c.bezier_rounds = t[2].cast<int>();
  c.values = reals_of(t[3], c.origin, "values");
  c.slit = t[4].cast<bool>();
  c.right_values = reals_of(t[5], c.origin, "right values");
  return c;
}

std::vector<CurveCondition> conditions_from(const py::list& specs) {
  if (specs.empty()) throw InvalidInput("curves is empty: give at least one curve");
  std::vector<CurveCondition> curves;
  for (const py::handle spec : specs) curves.push_back(condition_from(spec));
  return curves;
}

py::tuple spec_of(const CurveCondition& c) {
  std::vector<Index> v = c.vertices;
  return py::make_tuple(to_numpy(std::move(v)), shape_name(c.shape), c.bezier_rounds,
                        to_numpy(Eigen::VectorXd(Eigen::Map<const Eigen::VectorXd>(
                            c.values.data(), Eigen::Index(c.values.size())))),
                        c.slit,
                        to_numpy(Eigen::VectorXd(Eigen::Map<const Eigen::VectorXd>(
                            c.right_values.data(), Eigen::Index(c.right_values.size())))),
                        c.origin);
}

// The checks that need no mesh (ids ≥ 0 and in Index's range are the caller's): ≥ 2 vertices,
// no repeats in a row, value counts, finite values, rounds.
void check_curve(const py::handle& spec) {
  solvers::validate_curves({condition_from(spec)}, std::numeric_limits<Index>::max(), false);
}

py::list read_curves_file(const std::string& path) {
  std::vector<CurveCondition> curves;
  {
    const py::gil_scoped_release release;
    curves = solvers::read_curves_file(path);
  }
  py::list out;
  for (const CurveCondition& c : curves) out.append(spec_of(c));
  return out;
}

// The library's curves-file writer (solvers::write_curves_file), so Python writes what the CLI
// and read_curves_file read.
std::string curve_line(const py::handle& spec) { return solvers::curve_line(condition_from(spec)); }

void write_curves_file(const std::string& path, const py::list& specs) {
  std::vector<CurveCondition> curves;
  for (const py::handle spec : specs) curves.push_back(condition_from(spec));
  const py::gil_scoped_release release;
  solvers::write_curves_file(path, curves);
}

// refine: None, or (min_angle, resolution, max_area, max_insertions[, conform[, correspondence]])
// with Python's
// names in the messages.
std::optional<solvers::SurfaceRefineOptions> refine_from(const py::handle& refine) {
  if (refine.is_none()) return std::nullopt;
  const py::tuple t = refine.cast<py::tuple>();
  solvers::SurfaceRefineOptions r;
  r.min_angle_degrees = t[0].cast<double>();
  r.resolution = t[1].cast<double>();
  r.max_area = t[2].cast<double>();
  r.max_insertions = t[3].cast<Index>();
  if (t.size() > 4) r.conform = t[4].cast<bool>();
  if (t.size() > 5) r.correspondence = intrinsic::parse_correspondence(t[5].cast<std::string>());
  r.need_signposts = true;
  if (!(r.min_angle_degrees > 0.0 && r.min_angle_degrees <= 30.0)) {
    throw InvalidInput("min_angle must be in (0, 30] degrees, got " +
                       std::to_string(r.min_angle_degrees));
  }
  if (!(r.resolution >= 0.0 && std::isfinite(r.resolution))) {
    throw InvalidInput(
        "resolution must be finite and ≥ 0 (× the mean edge length; 0: no size "
        "bound), got " +
        std::to_string(r.resolution));
  }
  if (!(r.max_area >= 0.0 && std::isfinite(r.max_area))) {
    throw InvalidInput("max_area must be finite and ≥ 0 (0: none), got " +
                       std::to_string(r.max_area));
  }
  if (r.max_insertions < -1) {
    throw InvalidInput("max_insertions must be ≥ 0 (or None for the default), got " +
                       std::to_string(r.max_insertions));
  }
  r.validate();
  return r;
}

// FlipOut's cap on the curves (−1: the library's default) and whether curves left at it are
// accepted (CurveSurfaceOptions::flipout.max_iterations, accept_partial).
struct CurveFlipOut {
  Index max_iterations = -1;
  bool accept_partial = false;
};

// The input with its curves inserted (and refined when asked), GIL released.
solvers::CurveSurface prepare_curves(io::SurfaceInput in, const py::list& specs,
                                     const py::handle& refine, double mollify, bool need_values,
                                     const CurveFlipOut& flipout) {
  std::vector<CurveCondition> curves = conditions_from(specs);
  if (!(mollify >= 0.0 && mollify <= 1.0)) {
    throw InvalidInput("mollify must be in [0, 1] (relative to the mean edge length), got " +
                       std::to_string(mollify));
  }
  solvers::validate_curves(curves, static_cast<Index>(in.positions.rows()), need_values);
  solvers::CurveSurfaceOptions opt;
  opt.mollify_relative_epsilon = mollify;
  opt.refine = refine_from(refine);
  if (flipout.max_iterations < -1) {
    throw InvalidInput("max_iterations must be ≥ 0 (or None for the default), got " +
                       std::to_string(flipout.max_iterations));
  }
  opt.flipout.max_iterations = flipout.max_iterations;
  opt.accept_partial = flipout.accept_partial;
  const py::gil_scoped_release release;
  return solvers::prepare_curve_surface(std::move(in), std::move(curves), opt);
}

// What inserting the curves did, for the `info` dicts.
py::dict curves_info(const solvers::CurveSurface& s) {
  const intrinsic::FlipOutReport& fo = s.network.flipout;
  py::dict d;
  d["flipout"] =
      py::dict(py::arg("converged") = fo.stopped_by == intrinsic::FlipOutStop::kConverged,
               py::arg("stopped_by") = intrinsic::to_string(fo.stopped_by),
               py::arg("iterations") = fo.iterations, py::arg("flips") = fo.flips,
               py::arg("blocked_joints") = fo.blocked_joints);
  d["bezier_midpoints"] = s.network.bezier_midpoints;
  d["curve_lengths"] = s.network.length;
  d["constrained_flips"] = s.constrained_flips.flips;
  d["non_delaunay_curve_edges"] = s.constrained_flips.unflippable;
  d["negative_weights_on_curves"] = s.signs.negative_constrained;
  d["negative_weights_elsewhere"] = s.signs.negative_unconstrained;
  d["min_weight"] = s.signs.min_weight;
  d["vertices"] = s.surface.tri.n_vertices();
  d["refined"] = s.surface.refined;
  if (s.surface.refined) {
    const intrinsic::RefineReport& r = s.surface.refine_report;
    d["refine"] = solvers::describe(r);
    d["conforming_splits"] = r.conforming_splits;
    d["negative_barrier_weights"] = r.negative_barrier_weights;
    d["min_relative_barrier_weight"] = r.min_relative_barrier_weight;
  }
  d["mollify_delta"] = s.surface.mollify.delta;
  return d;
}

py::object polylines_of(const solvers::CurveSurface& s, bool want) {
  if (!want) return py::none();
  std::vector<std::vector<Eigen::Vector3d>> lines;
  {
    const py::gil_scoped_release release;
    lines = solvers::curve_polylines(s);
  }
  py::list out;
  for (const std::vector<Eigen::Vector3d>& line : lines) {
    Positions p(static_cast<Eigen::Index>(line.size()), 3);
    for (std::size_t i = 0; i < line.size(); ++i) p.row(Eigen::Index(i)) = line[i].transpose();
    out.append(to_numpy(std::move(p)));
  }
  return out;
}

// (u, polylines or None, info)
py::tuple curve_poisson(const py::handle& V, const py::handle& F, const py::list& specs,
                        const py::handle& rhs, const py::handle& dirichlet_vertices,
                        const py::handle& dirichlet_values, double screening,
                        const py::handle& refine, double mollify, bool want_polylines,
                        Index max_iterations, bool accept_partial) {
  io::SurfaceInput in = surface_input(V, F);
  const Index nv = static_cast<Index>(in.positions.rows());
  Eigen::VectorXd f;
  if (!rhs.is_none()) f = values_from(rhs, nv, "rhs");
  std::vector<Index> dv;
  Eigen::VectorXd dval;
  if (!dirichlet_vertices.is_none()) {
    dv = indices_from(dirichlet_vertices, nv, "dirichlet vertices", true);
    dval = values_from(dirichlet_values, static_cast<Eigen::Index>(dv.size()), "dirichlet values");
  }
  if (!(screening >= 0.0 && std::isfinite(screening))) {
    throw InvalidInput("screening must be finite and ≥ 0, got " + std::to_string(screening));
  }
  const solvers::CurveSurface s =
      prepare_curves(std::move(in), specs, refine, mollify, true, {max_iterations, accept_partial});
  solvers::PoissonOptions opt;
  opt.screening = screening;
  solvers::CurvePoissonResult r;
  {
    const py::gil_scoped_release release;
    r = solvers::curve_poisson(s, f, dv, dval, opt);
  }
  py::dict info = curves_info(s);
  info["dirichlet_vertices"] = r.dirichlet_vertices;
  info["conflicting_vertices"] = r.conflicting_vertices;
  info["slit_copies"] = r.slit_copies;
  py::object lines = polylines_of(s, want_polylines);
  return py::make_tuple(to_numpy(std::move(r.u)), lines, info);
}

// (d, polylines or None, info); time_factor / correction_steps: None for the library's choice.
py::tuple curve_distance(const py::handle& V, const py::handle& F, const py::list& specs,
                         const py::handle& refine, std::optional<double> time_factor,
                         std::optional<int> correction_steps, double mollify, bool want_polylines,
                         Index max_iterations, bool accept_partial, bool path_bounds) {
  if (time_factor && !(*time_factor > 0.0 && std::isfinite(*time_factor))) {
    throw InvalidInput("time_factor must be finite and > 0, got " + std::to_string(*time_factor));
  }
  if (correction_steps && *correction_steps < 0) {
    throw InvalidInput("correction_steps must be ≥ 0, got " + std::to_string(*correction_steps));
  }
  const solvers::CurveSurface s = prepare_curves(surface_input(V, F), specs, refine, mollify, false,
                                                 {max_iterations, accept_partial});
  solvers::DistanceOptions settings;
  settings.time_factor = time_factor;
  settings.correction_steps = correction_steps;
  settings.path_bounds = path_bounds;
  solvers::HeatDistanceReport report;
  Eigen::VectorXd d;
  {
    const py::gil_scoped_release release;
    d = solvers::curve_distance(s, settings, &report);
  }
  py::dict info = curves_info(s);
  info["stages"] = report.stages;
  py::object lines = polylines_of(s, want_polylines);
  return py::make_tuple(to_numpy(std::move(d)), lines, info);
}

}  // namespace

solvers::CurveSurface prepare_with_curves(io::SurfaceInput input, const py::list& specs,
                                          const py::handle& refine, double mollify,
                                          bool need_values, Index max_iterations,
                                          bool accept_partial) {
  return prepare_curves(std::move(input), specs, refine, mollify, need_values,
                        {max_iterations, accept_partial});
}

py::dict curve_surface_info(const solvers::CurveSurface& s) { return curves_info(s); }

void bind_curves(py::module_& m) {
  m.def("check_curve", &check_curve, py::arg("spec"));
  m.def("read_curves_file", &read_curves_file, py::arg("path"));
  m.def("curve_line", &curve_line, py::arg("spec"));
  m.def("write_curves_file", &write_curves_file, py::arg("path"), py::arg("specs"));
  m.def("curve_poisson", &curve_poisson, py::arg("V"), py::arg("F"), py::arg("curves"),
        py::arg("rhs"), py::arg("dirichlet_vertices"), py::arg("dirichlet_values"),
        py::arg("screening"), py::arg("refine"), py::arg("mollify"), py::arg("polylines"),
        py::arg("max_iterations"), py::arg("accept_partial"));
  m.def("curve_distance", &curve_distance, py::arg("V"), py::arg("F"), py::arg("curves"),
        py::arg("refine"), py::arg("time_factor"), py::arg("correction_steps"), py::arg("mollify"),
        py::arg("polylines"), py::arg("max_iterations"), py::arg("accept_partial"),
        py::arg("path_bounds") = true);
}

}  // namespace ifem::python
