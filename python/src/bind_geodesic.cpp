// Geodesic curves by FlipOut, as `ifem geodesic` computes them (examples/cli/cli_geodesic.cpp):
// paths, loops and networks through input vertices or points of faces, geodesic Bézier curves,
// single-source geodesics. Curves are traced over the input surface as polylines (the points
// the CLI writes to OBJ / PLY / txt). The Python layer (python/ifem/_geodesic.py) turns the
// dicts returned here into result objects.
#include <pybind11/stl.h>

#include <algorithm>
#include <array>
#include <climits>
#include <cmath>
#include <map>
#include <string>
#include <tuple>
#include <utility>
#include <vector>

#include "arrays.h"
#include "bindings.h"
#include "intrinsic/core/errors.h"
#include "intrinsic/core/geometry.h"
#include "intrinsic/geodesic/flip_geodesic.h"
#include "intrinsic/geodesic/input_surface.h"

namespace ifem::python {

namespace {

using intrinsic::EdgePath;
using intrinsic::FlipOutReport;
using intrinsic::SignpostTriangulation;

constexpr int kMaxBezierRounds = 16;  // as the CLI's --bezier

// A point as given: an input vertex, or a point of row `face` of F with barycentric
// coordinates `bary` for that row's corners in F's order.
struct Point {
  Index vertex = kInvalidIndex;
  Index face = kInvalidIndex;
  std::array<double, 3> bary{};
  std::string name;  // "points[2]", for messages
};

// One curve as given, and the name of the argument it came from.
struct CurveSpec {
  std::vector<Point> points;
  bool closed = false;
  bool pin = true;  // keep every given point on the curve (open paths always do)
  std::string name;
};

// A curve once shortened and traced.
struct CurveOut {
  Positions polyline;  // a loop repeats its first point at the end
  Positions points;    // the given points' positions on the surface
  double initial_length = 0.0, final_length = 0.0;
  bool closed = false, collapsed = false;
};

struct Run {
  std::vector<CurveOut> curves;
  FlipOutReport report;
  Index bezier_controls = 0, bezier_midpoints = 0;
};

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
    throw InvalidInput(p.name +
                       ": the face of a face point (face, b0, b1, b2) must be an integer, "
                       "got " +
                       repr_of(s[0]));
  }
  if (face < 0 || face >= nf) {
    throw InvalidInput(p.name + ": face " + std::to_string(face) + " out of range " + range(nf) +
                       " (F has " + std::to_string(nf) + " rows)");
  }
  double sum = 0.0;
  for (int k = 0; k < 3; ++k) {
    const py::object b = s[static_cast<std::size_t>(k + 1)];
    double x = 0.0;
    try {
      x = b.cast<double>();
    } catch (const py::cast_error&) {
      throw InvalidInput(p.name + ": barycentric coordinate b" + std::to_string(k) +
                         " must be a number, got " + repr_of(b));
    }
    if (!std::isfinite(x) || x < 0.0) {
      throw InvalidInput(p.name + ": barycentric coordinate b" + std::to_string(k) + " = " +
                         repr_of(b) + " must be finite and ≥ 0");
    }
    p.bary[static_cast<std::size_t>(k)] = x;
    sum += x;
  }
  if (std::abs(sum - 1.0) > 1e-9) {
    throw InvalidInput(p.name + ": barycentric coordinates (b0, b1, b2) must sum to 1, got " +
                       std::to_string(sum));
  }
  for (double& b : p.bary) b /= sum;
  p.face = static_cast<Index>(face);
}

// One point: a vertex id, or a face point (face, b0, b1, b2).
Point point_from(const py::handle& item, Index nv, Index nf, const std::string& name) {
  Point p;
  p.name = name;
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

bool same_point(const Point& a, const Point& b) {
  return a.vertex == b.vertex && a.face == b.face && a.bary == b.bary;
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
  c.name = name;
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
    if (same_point(a, b)) {
      throw InvalidInput(
          a.name + " and " + b.name + " are the same point (consecutive points must differ" +
          (closed ? "; a loop closes by itself: do not repeat its first point)" : ")"));
    }
  }
  return c;
}

// The signpost triangulation of the input (GIL released by the caller), refused as the CLI
// refuses it: no faces, no area, not edge-manifold and orientable.
SignpostTriangulation build_signposts(const io::SurfaceInput& in, double mollify) {
  if (!in.has_faces()) {
    throw InvalidInput("F has no faces: geodesic curves need a triangle mesh (not a point cloud)");
  }
  return intrinsic::flipout_surface(in, mollify);
}

// p (a face point) as a point of st.input().
intrinsic::SurfacePoint input_point(const SignpostTriangulation& st, const io::SurfaceInput& in,
                                    const std::vector<Index>& input_face, const Point& p) {
  const Eigen::Vector3d w(p.bary[0], p.bary[1], p.bary[2]);
  return intrinsic::given_face_point(st, in.triangles, input_face, p.face, w, p.name);
}

Positions to_positions(const std::vector<Eigen::Vector3d>& line) {
  Positions p(static_cast<Eigen::Index>(line.size()), 3);
  for (std::size_t i = 0; i < line.size(); ++i) p.row(Eigen::Index(i)) = line[i].transpose();
  return p;
}

// The intrinsic vertex ids of every curve's points (face points inserted, all before any path is
// built; the same face point twice is one vertex), and the points' positions into out.
std::vector<std::vector<Index>> insert_points(SignpostTriangulation& st, const io::SurfaceInput& in,
                                              const std::vector<CurveSpec>& curves, Run& out) {
  const std::vector<Index> input_face = intrinsic::given_face_map(st, in.triangles.size());
  std::map<std::tuple<Index, double, double, double>, Index> inserted;
  std::vector<std::vector<Index>> ids(curves.size());
  out.curves.resize(curves.size());
  for (std::size_t c = 0; c < curves.size(); ++c) {
    std::vector<Eigen::Vector3d> at;
    for (const Point& p : curves[c].points) {
      Index v = p.vertex;
      if (v == kInvalidIndex) {
        const auto key = std::make_tuple(p.face, p.bary[0], p.bary[1], p.bary[2]);
        auto it = inserted.find(key);
        if (it == inserted.end()) {
          const intrinsic::SurfacePoint sp = input_point(st, in, input_face, p);
          it = inserted.emplace(key, intrinsic::insert_surface_point(st, sp)).first;
        }
        v = it->second;
      }
      ids[c].push_back(v);
      at.push_back(st.position(st.vertex_location(v)));
    }
    out.curves[c].points = to_positions(at);
  }
  return ids;
}

// Lengths and traces of the shortened curves (tracing flips nothing: any order is fine).
void trace_curves(const SignpostTriangulation& st, const std::vector<EdgePath>& paths, Run& run) {
  std::vector<char> collapsed(paths.size(), 0);
  for (const Index c : run.report.collapsed_loops) collapsed[static_cast<std::size_t>(c)] = 1;
  for (std::size_t c = 0; c < paths.size(); ++c) {
    CurveOut& r = run.curves[c];
    r.closed = paths[c].closed;
    r.collapsed = collapsed[c] != 0;
    r.final_length = intrinsic::path_length(st.intrinsic(), paths[c]);
    r.polyline = paths[c].steps.empty() ? Positions(0, 3)
                                        : to_positions(intrinsic::path_polyline(st, paths[c]));
  }
}

// Paths and loops through the points, shortened together (the CLI's --path / --network).
void shorten_curves(SignpostTriangulation& st, const std::vector<CurveSpec>& specs,
                    const std::vector<std::vector<Index>>& ids, Run& run) {
  std::vector<intrinsic::CurveThrough> curves;
  for (std::size_t c = 0; c < specs.size(); ++c) {
    curves.push_back({ids[c], specs[c].closed, specs[c].pin, specs[c].name});
  }
  std::vector<EdgePath> paths;
  std::vector<double> initial;
  run.report = intrinsic::shorten_through(st, curves, &paths, &initial);
  for (std::size_t c = 0; c < specs.size(); ++c) run.curves[c].initial_length = initial[c];
  trace_curves(st, paths, run);
}

double checked_mollify(double mollify) {
  if (!(mollify >= 0.0 && mollify <= 1.0)) {
    throw InvalidInput("mollify must be in [0, 1] (relative to the mean edge length), got " +
                       std::to_string(mollify));
  }
  return mollify;
}

py::dict report_dict(const FlipOutReport& r) {
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
py::tuple run_result(Run&& run) {
  py::list curves;
  for (CurveOut& c : run.curves) {
    py::dict d;
    d["polyline"] = to_numpy(std::move(c.polyline));
    d["points"] = to_numpy(std::move(c.points));
    d["initial_length"] = c.initial_length;
    d["length"] = c.final_length;
    d["closed"] = c.closed;
    d["collapsed"] = c.collapsed;
    curves.append(d);
  }
  py::dict report = report_dict(run.report);
  report["bezier_control_points"] = run.bezier_controls;
  report["bezier_midpoints"] = run.bezier_midpoints;
  return py::make_tuple(curves, report);
}

// curves: a list of (points, closed, pin), each named by the matching entry of `names`.
py::tuple geodesic_curves(const py::handle& V, const py::handle& F, const py::list& curves,
                          const std::vector<std::string>& names, double mollify) {
  io::SurfaceInput in = surface_input(V, F);
  const Index nv = static_cast<Index>(in.positions.rows());
  const Index nf = static_cast<Index>(in.triangles.size());
  if (curves.empty()) throw InvalidInput("curves is empty: give at least one curve");
  std::vector<CurveSpec> specs;
  for (std::size_t c = 0; c < curves.size(); ++c) {
    const py::tuple t = curves[c].cast<py::tuple>();
    specs.push_back(curve_from(t[0], t[1].cast<bool>(), t[2].cast<bool>(), nv, nf, names.at(c)));
  }
  checked_mollify(mollify);
  Run run;
  {
    const py::gil_scoped_release release;
    SignpostTriangulation st = build_signposts(in, mollify);
    const std::vector<std::vector<Index>> ids = insert_points(st, in, specs, run);
    shorten_curves(st, specs, ids, run);
  }
  return run_result(std::move(run));
}

// One geodesic Bézier curve with the given control points (the CLI's --path ... --bezier R).
py::tuple bezier_curve(const py::handle& V, const py::handle& F, const py::handle& control,
                       int rounds, double mollify) {
  io::SurfaceInput in = surface_input(V, F);
  const Index nv = static_cast<Index>(in.positions.rows());
  const CurveSpec spec = curve_from(control, false, true, nv,
                                    static_cast<Index>(in.triangles.size()), "control_points");
  if (rounds < 0 || rounds > kMaxBezierRounds) {
    throw InvalidInput("rounds must be in [0, " + std::to_string(kMaxBezierRounds) +
                       "] (de Casteljau subdivisions; 0: the geodesic control polygon), got " +
                       std::to_string(rounds));
  }
  checked_mollify(mollify);
  Run run;
  {
    const py::gil_scoped_release release;
    SignpostTriangulation st = build_signposts(in, mollify);
    const std::vector<Index> ids = insert_points(st, in, {spec}, run)[0];
    intrinsic::BezierCurve b = intrinsic::bezier_curve(st, ids, rounds);
    run.report = b.report;
    run.curves[0].initial_length = b.report.initial_length;
    run.bezier_controls = static_cast<Index>(b.controls.size());
    run.bezier_midpoints = b.inserted_vertices;
    trace_curves(st, {b.path}, run);
  }
  return run_result(std::move(run));
}

// Lengths of single-source geodesics from `source` (the CLI's --all-from), and with
// `return_paths` every geodesic as a polyline (the source's: one point; unreached: none).
py::tuple single_source(const py::handle& V, const py::handle& F, const py::handle& source,
                        bool return_paths, double mollify) {
  io::SurfaceInput in = surface_input(V, F);
  const Index nv = static_cast<Index>(in.positions.rows());
  long long s = 0;
  if (!integer_of(source, s)) {
    throw InvalidInput("source must be a vertex id (an integer), got " + repr_of(source));
  }
  if (s < 0 || s >= nv) {
    throw InvalidInput("source = " + std::to_string(s) + ": vertex out of range " + range(nv));
  }
  checked_mollify(mollify);
  Eigen::VectorXd length;
  std::vector<Positions> lines;
  intrinsic::SingleSourceGeodesics g;
  {
    const py::gil_scoped_release release;
    SignpostTriangulation st = build_signposts(in, mollify);
    g = intrinsic::single_source_geodesics(st, static_cast<Index>(s));
    length = g.length.head(nv);
    for (Index v = 0; return_paths && v < nv; ++v) {
      const EdgePath& p = g.paths[static_cast<std::size_t>(v)];
      if (!p.steps.empty()) {
        lines.push_back(to_positions(intrinsic::path_polyline(st, p)));
      } else if (v == s) {
        lines.push_back(to_positions({st.position(st.vertex_location(v))}));
      } else {
        lines.emplace_back(0, 3);
      }
    }
  }
  py::dict info;
  info["flips"] = g.flips;
  info["iterations"] = g.iterations;
  info["blocked"] = g.blocked;
  py::object paths = py::none();
  if (return_paths) {
    py::list l;
    for (Positions& p : lines) l.append(to_numpy(std::move(p)));
    paths = l;
  }
  return py::make_tuple(to_numpy(std::move(length)), paths, info);
}

}  // namespace

void bind_geodesic(py::module_& m) {
  m.def("geodesic_curves", &geodesic_curves, py::arg("V"), py::arg("F"), py::arg("curves"),
        py::arg("names"), py::arg("mollify"));
  m.def("bezier_curve", &bezier_curve, py::arg("V"), py::arg("F"), py::arg("control_points"),
        py::arg("rounds"), py::arg("mollify"));
  m.def("single_source_geodesics", &single_source, py::arg("V"), py::arg("F"), py::arg("source"),
        py::arg("return_paths"), py::arg("mollify"));
}

}  // namespace ifem::python
