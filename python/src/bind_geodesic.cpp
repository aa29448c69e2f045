// Geodesic curves by FlipOut: the Python arguments of the geodesic recipe
// (solvers/recipes/geodesic.h, the one `ifem geodesic` runs) turned into its curves and its
// results into dicts. Points are vertex ids or face points (face, b0, b1, b2); the Python layer
// (python/ifem/_geodesic.py) turns the dicts into result objects.
#include <pybind11/stl.h>

#include <climits>
#include <cmath>
#include <string>
#include <utility>
#include <vector>

#include "arrays.h"
#include "bindings.h"
#include "intrinsic/core/errors.h"
#include "solvers/recipes/geodesic.h"
#include "solvers/recipes/text_formats.h"

namespace ifem::python {

namespace {

using recipes::GivenCurve;
using recipes::GivenPoint;
using Point = GivenPoint;
using CurveSpec = GivenCurve;

constexpr int kMaxBezierRounds = 16;  // as the CLI's --bezier

std::string repr_of(const py::handle& h) { return py::repr(h).cast<std::string>(); }

// An integer from a Python or numpy integer (not a bool); false for anything else.
bool integer_of(const py::handle& h, long long& out) {
  if (PyBool_Check(h.ptr()) || !PyIndex_Check(h.ptr())) return false;
  PyObject* i = PyNumber_Index(h.ptr());
  if (i == nullptr) {
    PyErr_Clear();  // e.g. a 1-D numpy array: it has __index__ but refuses it
    return false;
  }
  int overflow = 0;
  out = PyLong_AsLongLongAndOverflow(i, &overflow);
  Py_DECREF(i);
  if (overflow != 0) out = overflow > 0 ? LLONG_MAX : LLONG_MIN;
  return true;
}

// A face id of a face point: an integer, or a real with an integer value (rows of a float array).
bool face_of(const py::handle& h, long long& out) {
  if (integer_of(h, out)) return true;
  if (!PyFloat_Check(h.ptr())) return false;
  const double x = PyFloat_AsDouble(h.ptr());
  if (!std::isfinite(x) || x != std::floor(x) || std::abs(x) > 1e15) return false;
  out = static_cast<long long>(x);
  return true;
}

std::string range(Index n) { return "[0, " + std::to_string(n) + ")"; }

// (face, b0, b1, b2) into p: face a row of F, coordinates ≥ 0 summing to 1 (normalized).
void face_point(const py::sequence& s, Index nf, Point& p) {
  long long face = 0;
  if (!face_of(s[0], face)) {
    throw InvalidInput(p.token +
                       ": the face of a face point (face, b0, b1, b2) must be an integer, "
                       "got " +
                       repr_of(s[0]));
  }
  if (face < 0 || face >= nf) {
    throw InvalidInput(p.token + ": face " + std::to_string(face) + " out of range " + range(nf) +
                       " (F has " + std::to_string(nf) + " rows)");
  }
  double sum = 0.0;
  for (int k = 0; k < 3; ++k) {
    const py::object b = s[static_cast<std::size_t>(k + 1)];
    double x = 0.0;
    try {
      x = b.cast<double>();
    } catch (const py::cast_error&) {
      throw InvalidInput(p.token + ": barycentric coordinate b" + std::to_string(k) +
                         " must be a number, got " + repr_of(b));
    }
    if (!std::isfinite(x) || x < 0.0) {
      throw InvalidInput(p.token + ": barycentric coordinate b" + std::to_string(k) + " = " +
                         repr_of(b) + " must be finite and ≥ 0");
    }
    p.bary[static_cast<std::size_t>(k)] = x;
    sum += x;
  }
  if (std::abs(sum - 1.0) > 1e-9) {
    throw InvalidInput(p.token + ": barycentric coordinates (b0, b1, b2) must sum to 1, got " +
                       std::to_string(sum));
  }
  for (double& b : p.bary) b /= sum;
  p.face = static_cast<Index>(face);
}

// One point: a vertex id, or a face point (face, b0, b1, b2).
Point point_from(const py::handle& item, Index nv, Index nf, const std::string& name) {
  Point p;
  p.token = name;
  long long id = 0;
  if (integer_of(item, id)) {
    if (id < 0 || id >= nv) {
      throw InvalidInput(name + " = " + std::to_string(id) + ": vertex out of range " + range(nv) +
                         " (V has " + std::to_string(nv) + " rows)");
    }
    p.vertex = static_cast<Index>(id);
    return p;
  }
  if (py::isinstance<py::str>(item) || py::isinstance<py::bytes>(item) ||
      !PySequence_Check(item.ptr()) || PySequence_Size(item.ptr()) != 4) {
    PyErr_Clear();
    throw InvalidInput(name +
                       " must be a vertex id (an integer) or a face point (face, b0, b1, "
                       "b2), got " +
                       repr_of(item));
  }
  face_point(py::reinterpret_borrow<py::sequence>(item), nf, p);
  return p;
}

// The points of one curve: ≥ 2 of them, no two consecutive ones the same (a loop's last and
// first included).
CurveSpec curve_from(const py::handle& points, bool closed, bool pin, Index nv, Index nf,
                     const std::string& name) {
  if (points.is_none() || py::isinstance<py::str>(points) || !PySequence_Check(points.ptr())) {
    throw InvalidInput(name +
                       " must be a sequence of points (vertex ids or (face, b0, b1, b2)), "
                       "got " +
                       repr_of(points));
  }
  const py::sequence seq = py::reinterpret_borrow<py::sequence>(points);
  CurveSpec c;
  c.origin = name;
  c.closed = closed;
  c.pin = !closed || pin;
  for (std::size_t k = 0; k < seq.size(); ++k) {
    c.points.push_back(point_from(seq[k], nv, nf, name + "[" + std::to_string(k) + "]"));
  }
  if (c.points.size() < 2) {
    throw InvalidInput(name + " needs at least 2 points, got " + std::to_string(c.points.size()));
  }
  const std::size_t n = c.points.size();
  for (std::size_t k = 0; k < (closed ? n : n - 1); ++k) {
    const Point& a = c.points[k];
    const Point& b = c.points[(k + 1) % n];
    if (a.same_as(b)) {
      throw InvalidInput(
          a.token + " and " + b.token + " are the same point (consecutive points must differ" +
          (closed ? "; a loop closes by itself: do not repeat its first point)" : ")"));
    }
  }
  return c;
}

// The input, refused when it has no faces (the recipe would say so too, in the CLI's words).
io::SurfaceInput triangle_mesh(const py::handle& V, const py::handle& F) {
  io::SurfaceInput in = surface_input(V, F);
  if (!in.has_faces()) {
    throw InvalidInput("F has no faces: geodesic curves need a triangle mesh (not a point cloud)");
  }
  return in;
}

Positions to_positions(const std::vector<Eigen::Vector3d>& line) {
  Positions p(static_cast<Eigen::Index>(line.size()), 3);
  for (std::size_t i = 0; i < line.size(); ++i) p.row(Eigen::Index(i)) = line[i].transpose();
  return p;
}

double checked_mollify(double mollify) {
  if (!(mollify >= 0.0 && mollify <= 1.0)) {
    throw InvalidInput("mollify must be in [0, 1] (relative to the mean edge length), got " +
                       std::to_string(mollify));
  }
  return mollify;
}

py::dict report_dict(const intrinsic::FlipOutReport& r) {
  py::dict d;
  d["converged"] = r.stopped_by == intrinsic::FlipOutStop::kConverged;
  d["stopped_by"] = intrinsic::to_string(r.stopped_by);
  d["iterations"] = r.iterations;
  d["flips"] = r.flips;
  d["blocked_joints"] = r.blocked_joints;
  d["initial_length"] = r.initial_length;
  d["final_length"] = r.final_length;
  return d;
}

// (curves, report): per curve a dict of polyline, points, lengths, closed, collapsed.
py::tuple run_result(const recipes::GeodesicCurves& run) {
  py::list curves;
  for (const recipes::GeodesicCurve& c : run.curves) {
    py::dict d;
    d["polyline"] = to_numpy(c.polyline.empty() ? Positions(0, 3) : to_positions(c.polyline));
    d["points"] = to_numpy(to_positions(c.points));
    d["initial_length"] = c.initial_length;
    d["length"] = c.length;
    d["closed"] = c.closed;
    d["collapsed"] = c.collapsed;
    d["start_won"] = run.start_won;  // one curve when set (a path between two points)
    curves.append(d);
  }
  py::dict report = report_dict(run.report);
  report["bezier_control_points"] = run.bezier_control_points;
  report["bezier_midpoints"] = run.bezier_midpoints;
  return py::make_tuple(curves, report);
}

recipes::GeodesicOptions options_of(double mollify) {
  recipes::GeodesicOptions o;
  o.mollify_relative_epsilon = checked_mollify(mollify);
  return o;
}

// The start paths' name as the library's enum (the CLI's --start).
intrinsic::StartPath start_of(const std::string& s) {
  try {
    return intrinsic::start_path_from(s);
  } catch (const InvalidInput& e) {
    throw InvalidInput(std::string("start = ") + e.what());
  }
}

// curves: a list of (points, closed, pin), each named by the matching entry of `names`.
py::tuple geodesic_curves(const py::handle& V, const py::handle& F, const py::list& curves,
                          const std::vector<std::string>& names, double mollify,
                          Index max_iterations, bool accept_partial, const std::string& start) {
  const io::SurfaceInput in = triangle_mesh(V, F);
  const Index nv = static_cast<Index>(in.positions.rows());
  const Index nf = static_cast<Index>(in.triangles.size());
  if (curves.empty()) throw InvalidInput("curves is empty: give at least one curve");
  std::vector<CurveSpec> specs;
  for (std::size_t c = 0; c < curves.size(); ++c) {
    const py::tuple t = curves[c].cast<py::tuple>();
    specs.push_back(curve_from(t[0], t[1].cast<bool>(), t[2].cast<bool>(), nv, nf, names.at(c)));
  }
  recipes::GeodesicOptions o = options_of(mollify);
  o.flipout.max_iterations = max_iterations;
  o.accept_partial = accept_partial;
  o.start = start_of(start);
  recipes::GeodesicCurves run;
  {
    const py::gil_scoped_release release;
    run = recipes::geodesic(in, specs, o);
  }
  return run_result(run);
}

// One geodesic Bézier curve with the given control points (the CLI's --path ... --bezier R).
py::tuple bezier_curve(const py::handle& V, const py::handle& F, const py::handle& control,
                       int rounds, double mollify, double memory_budget_bytes) {
  const io::SurfaceInput in = triangle_mesh(V, F);
  const Index nv = static_cast<Index>(in.positions.rows());
  const CurveSpec spec = curve_from(control, false, true, nv,
                                    static_cast<Index>(in.triangles.size()), "control_points");
  if (rounds < 0 || rounds > kMaxBezierRounds) {
    throw InvalidInput("rounds must be in [0, " + std::to_string(kMaxBezierRounds) +
                       "] (de Casteljau subdivisions; 0: the geodesic control polygon), got " +
                       std::to_string(rounds));
  }
  recipes::GeodesicOptions o = options_of(mollify);
  o.bezier_rounds = rounds;
  o.max_memory_bytes = memory_budget_bytes;
  recipes::GeodesicCurves run;
  {
    const py::gil_scoped_release release;
    run = recipes::geodesic(in, {spec}, o);
  }
  return run_result(run);
}

// Lengths of single-source geodesics from `source` (the CLI's --all-from), and with
// `return_paths` every geodesic as a polyline (the source's: one point; unreached: none).
py::tuple single_source(const py::handle& V, const py::handle& F, const py::handle& source,
                        bool return_paths, double mollify, const py::handle& progress,
                        bool single_source_flipout) {
  const io::SurfaceInput in = triangle_mesh(V, F);
  const Index nv = static_cast<Index>(in.positions.rows());
  long long s = 0;
  if (!integer_of(source, s)) {
    throw InvalidInput("source must be a vertex id (an integer), got " + repr_of(source));
  }
  if (s < 0 || s >= nv) {
    throw InvalidInput("source = " + std::to_string(s) + ": vertex out of range " + range(nv));
  }
  recipes::GeodesicOptions o = options_of(mollify);
  o.trace_paths = return_paths;
  o.single_source_flipout = single_source_flipout;
  o.on_progress = progress_callback(progress);
  recipes::SingleSourceResult g;
  {
    const py::gil_scoped_release release;
    g = recipes::geodesic(in, static_cast<Index>(s), o);
  }
  py::dict info;
  info["flips"] = g.flips;
  info["iterations"] = g.iterations;
  info["blocked"] = g.blocked;
  info["exact"] = g.exact;
  info["windows"] = g.windows;
  info["tufted_cover"] = g.tufted_cover;
  py::object paths = py::none();
  if (return_paths) {
    py::list l;
    for (const auto& p : g.paths) l.append(to_numpy(p.empty() ? Positions(0, 3) : to_positions(p)));
    paths = l;
  }
  return py::make_tuple(to_numpy(Eigen::VectorXd(g.length)), paths, info);
}

// A network file (the CLI's --network; the library's reader, errors at FILE:line) as a list of
// dicts {'points': [...], 'loop': bool}, face points as (F, b0, b1, b2).
py::list read_network(const std::string& path) {
  std::vector<GivenCurve> curves;
  {
    const py::gil_scoped_release release;
    curves = recipes::read_network_file(path, false);
  }
  py::list out;
  for (const GivenCurve& c : curves) {
    py::list points;
    for (const GivenPoint& p : c.points) {
      if (p.vertex != kInvalidIndex) {
        points.append(p.vertex);
      } else {
        points.append(py::make_tuple(p.face, p.bary[0], p.bary[1], p.bary[2]));
      }
    }
    py::dict d;
    d["points"] = points;
    d["loop"] = c.closed;
    out.append(d);
  }
  return out;
}

}  // namespace

void bind_geodesic(py::module_& m) {
  m.def("geodesic_curves", &geodesic_curves, py::arg("V"), py::arg("F"), py::arg("curves"),
        py::arg("names"), py::arg("mollify"), py::arg("max_iterations"), py::arg("accept_partial"),
        py::arg("start") = "best");
  m.def("bezier_curve", &bezier_curve, py::arg("V"), py::arg("F"), py::arg("control_points"),
        py::arg("rounds"), py::arg("mollify"), py::arg("memory_budget_bytes"));
  m.def("single_source_geodesics", &single_source, py::arg("V"), py::arg("F"), py::arg("source"),
        py::arg("return_paths"), py::arg("mollify"), py::arg("progress") = py::none(),
        py::arg("single_source_flipout") = false);
  m.def("read_network", &read_network, py::arg("path"));
}

}  // namespace ifem::python
