// Intrinsic Delaunay refinement (`ifem refine`): a handle on the refined triangulation (signposts
// or integer coordinates) with its common subdivision, vertex positions on the input, operators,
// data transfer from the input's vertices, and save / load ("ifem-signpost 1" or "ifem-integer 1").
#include <pybind11/stl.h>

#include <cmath>
#include <memory>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "arrays.h"
#include "bindings.h"
#include "fem/attribute_transfer.h"
#include "fem/operators.h"
#include "intrinsic/core/errors.h"
#include "intrinsic/core/geometry.h"
#include "intrinsic/core/timer.h"
#include "intrinsic/refine/common_subdivision.h"

namespace ifem::python {

namespace {

// ---- arguments ------------------------------------------------------------------------------

void require(bool ok, const std::string& what) {
  if (!ok) throw InvalidInput(what);
}

std::string number(double x) { return py::str(py::float_(x)).cast<std::string>(); }

void require_size(double x, const char* name) {
  require(std::isfinite(x) && x >= 0.0,
          std::string(name) + " must be finite and ≥ 0 (0 = off), got " + number(x));
}

// The library's settings from the Python arguments, each checked under its Python name.
solvers::SurfaceRefineOptions refine_settings(double min_angle, double resolution, double max_area,
                                              const std::optional<long long>& max_insertions,
                                              long long relax, double max_edge,
                                              const std::optional<double>& memory_budget,
                                              const std::string& correspondence) {
  require(min_angle > 0.0 && min_angle <= 30.0,
          "min_angle must be in (0, 30] degrees (Chew's algorithm terminates up to 30°), got " +
              number(min_angle));
  require_size(resolution, "resolution");
  require_size(max_area, "max_area");
  require_size(max_edge, "max_edge");
  require(!max_insertions || (*max_insertions >= 0 && *max_insertions <= (1LL << 30)),
          "max_insertions must be None or in [0, 2^30], got " +
              std::to_string(max_insertions.value_or(0)));
  require(relax >= 0 && relax <= 1000000,
          "relax must be in [0, 10^6] passes, got " + std::to_string(relax));
  require(max_edge == 0.0 || relax > 0, "max_edge splits long edges during relaxation: set relax");
  require(!memory_budget || *memory_budget > 0.0,
          "memory_budget must be None or > 0 gigabytes, got " + number(memory_budget.value_or(0)));
  solvers::SurfaceRefineOptions r;
  r.min_angle_degrees = min_angle;
  r.resolution = resolution;
  r.max_area = max_area;
  r.max_insertions = max_insertions ? static_cast<Index>(*max_insertions) : Index(-1);
  r.relax_iterations = static_cast<int>(relax);
  r.relax_max_edge = max_edge;
  r.need_signposts = true;
  r.max_memory_bytes = memory_budget ? *memory_budget * 1e9 : 0.0;
  r.correspondence = intrinsic::parse_correspondence(correspondence);
  r.validate();
  return r;
}

// ---- refining -------------------------------------------------------------------------------

// Smallest corner angle of the input triangles as given, degrees (the CLI's "input" angle).
double input_min_angle(const io::SurfaceInput& in) {
  const auto t = intrinsic::IntrinsicTriangulation::from_positions(in.triangles, in.positions);
  double m = intrinsic::kPi;
  for (Index f = 0; f < t.n_faces(); ++f) m = std::min(m, intrinsic::min_corner_angle(t, f));
  return m * 180.0 / intrinsic::kPi;
}

// Called while handling an InvalidInput from prepare_surface(): when it was the refusal of an
// input that cannot have signposts, throws it again as the exception class of the cause (the
// same message), found by preparing the input without refinement (cheap; only on this failure
// path). Returns otherwise, for the caller to rethrow the original.
void throw_as_cause(const io::SurfaceInput& in, const solvers::PrepareOptions& o,
                    const InvalidInput& refusal) {
  solvers::PrepareOptions plain = o;
  plain.refine.reset();
  intrinsic::PathReason reason = intrinsic::PathReason::kEdgeManifoldOrientable;
  try {
    const solvers::PreparedSurface s = solvers::prepare_surface(in, plain);
    if (s.supports_signposts()) return;
    reason = s.reason;
  } catch (const Error&) {
    return;  // not a path refusal: the original error stands
  }
  if (reason == intrinsic::PathReason::kNonOrientable) throw NonOrientableInput(refusal.what());
  if (reason == intrinsic::PathReason::kNonmanifoldEdges) throw NonManifoldInput(refusal.what());
}

py::dict relax_dict(const intrinsic::RelaxReport& r) {
  py::dict d;
  d["passes"] = r.passes;
  d["moved"] = r.moved;
  d["rejected"] = r.rejected;
  d["splits"] = r.splits;
  d["hit_split_cap"] = r.hit_split_cap;
  d["flips"] = r.flips;
  d["max_displacement"] = r.max_displacement;
  d["max_edge_after"] = r.max_edge_after;
  d["min_angle_before"] = r.min_angle_before;
  d["min_angle_after"] = r.min_angle_after;
  d["mean_min_angle_before"] = r.mean_min_angle_before;
  d["mean_min_angle_after"] = r.mean_min_angle_after;
  return d;
}

// `seconds`: the whole of refine() (build, flips, signposts, refinement, relaxation).
py::dict report_dict(const solvers::PreparedSurface& s, double min_angle_input, double seconds) {
  const intrinsic::RefineReport& r = s.refine_report;
  py::dict d;
  d["vertices_before"] = r.vertices_before;
  d["vertices_after"] = r.vertices_after;
  d["insertions"] = r.insertions;
  d["face_insertions"] = r.face_insertions;
  d["edge_splits"] = r.edge_splits;
  d["boundary_splits"] = r.boundary_splits;
  d["failed_traces"] = r.failed_traces;
  d["flips"] = r.flips;
  d["hit_insertion_cap"] = r.hit_insertion_cap;
  d["needle_faces"] = r.needle_faces;
  d["bad_faces_left"] = r.bad_faces_left;
  d["scale_floor_faces"] = r.scale_floor_faces;
  d["min_angle_input"] = min_angle_input;
  d["min_angle_before"] = r.min_angle_before;
  d["min_angle_after"] = r.min_angle_after;
  d["min_angle_after_excluding_needles"] = r.min_angle_after_excluding_needles;
  d["target_edge_length"] = s.target_edge_length;
  d["input_mean_edge_length"] = s.input_mean_edge_length;
  d["mollify_delta"] = s.mollify.delta;
  d["seconds"] = seconds;
  d["relax"] = s.relax_report.passes > 0 ? py::object(relax_dict(s.relax_report)) : py::none();
  d["summary"] = solvers::describe(r);
  return d;
}

std::unique_ptr<Refined> refine(const py::handle& V, const py::handle& F, double min_angle,
                                double resolution, double max_area,
                                std::optional<long long> max_insertions, long long relax,
                                double max_edge, double mollify,
                                std::optional<double> memory_budget,
                                const std::string& correspondence, const py::handle& progress) {
  io::SurfaceInput in = surface_input(V, F);
  require(!in.triangles.empty(), "F has no faces: refinement needs a triangle mesh");
  require(std::isfinite(mollify) && mollify >= 0.0,
          "mollify must be finite and ≥ 0 (a margin relative to the mean edge length), got " +
              number(mollify));
  solvers::PrepareOptions o = prepare_options(mollify, "auto", true, 30);
  o.refine = refine_settings(min_angle, resolution, max_area, max_insertions, relax, max_edge,
                             memory_budget, correspondence);
  o.on_progress = progress_callback(progress);
  solvers::PreparedSurface s;
  double angle = 0.0, seconds = 0.0;
  {
    const py::gil_scoped_release release;
    const Stopwatch watch;
    try {
      s = solvers::prepare_surface(in, o);
    } catch (const InvalidInput& e) {
      throw_as_cause(in, o, e);
      throw;
    }
    seconds = watch.seconds();
    angle = input_min_angle(s.input);
  }
  intrinsic::SavedTriangulation kept;
  kept.signposts = std::move(s.signposts);
  kept.integer = std::move(s.integer);
  auto h = std::make_unique<Refined>(std::move(kept));
  h->report = report_dict(s, angle, seconds);
  h->memory_budget_bytes = o.refine->max_memory_bytes;
  return h;
}

// ---- what the handle gives ------------------------------------------------------------------

std::vector<Triangle> faces_of(const intrinsic::IntrinsicTriangulation& t) {
  std::vector<Triangle> faces(static_cast<std::size_t>(t.n_faces()));
  for (Index f = 0; f < t.n_faces(); ++f) {
    faces[static_cast<std::size_t>(f)] = {t.tail(3 * f), t.tail(3 * f + 1), t.tail(3 * f + 2)};
  }
  return faces;
}

// #F×3: column k of row f is the length of side F[f, k] → F[f, (k + 1) % 3].
Eigen::MatrixXd side_lengths(const intrinsic::IntrinsicTriangulation& t) {
  Eigen::MatrixXd l(t.n_faces(), 3);
  for (Index f = 0; f < t.n_faces(); ++f) {
    for (int k = 0; k < 3; ++k) l(f, k) = t.halfedge_length(3 * f + k);
  }
  return l;
}

py::tuple common_subdivision_of(const Refined& h) {
  intrinsic::CommonSubdivision cs;
  {
    const py::gil_scoped_release release;
    cs = h.st().common_subdivision(h.memory_budget_bytes);
  }
  return py::make_tuple(to_numpy(std::move(cs.positions)), to_numpy(std::move(cs.faces)),
                        to_numpy(std::move(cs.intrinsic_face)), to_numpy(std::move(cs.input_face)));
}

py::tuple laplacian_of(const Refined& h) {
  fem::SparseMatrix L;
  Eigen::VectorXd m;
  {
    const py::gil_scoped_release release;
    L = fem::cotan_laplacian(h.st().intrinsic());
    m = fem::lumped_mass(h.st().intrinsic());
  }
  return py::make_tuple(to_csc_parts(std::move(L)), to_numpy(std::move(m)));
}

py::array from_input(const Refined& h, const py::handle& x) {
  const Eigen::VectorXd values = values_from(x, h.st().n_input_vertices(), "x");
  Eigen::VectorXd out;
  {
    const py::gil_scoped_release release;
    out = h.st().input_to_intrinsic(values);
  }
  return to_numpy(std::move(out));
}

// transfer(h, x, method, back): fem::transfer on the handle's correspondence, GIL released.
py::array transfer(const Refined& h, const py::handle& x, const std::string& method, bool back) {
  const fem::TransferMethod m = fem::parse_transfer_method(method);
  const Index n = back ? h.st().intrinsic().n_vertices() : h.st().n_input_vertices();
  const Eigen::VectorXd values = values_from(x, n, "x");
  Eigen::VectorXd out;
  {
    const py::gil_scoped_release release;
    out = fem::transfer(h.st(), values, m, back);
  }
  return to_numpy(std::move(out));
}

void save(const Refined& h, const std::string& path) {
  const py::gil_scoped_release release;
  h.st().save(path);
}

std::unique_ptr<Refined> load(const std::string& path) {
  std::optional<intrinsic::SavedTriangulation> st;
  {
    const py::gil_scoped_release release;
    st.emplace(intrinsic::load_triangulation(path));
  }
  return std::make_unique<Refined>(std::move(*st));
}

}  // namespace

void bind_refine(py::module_& m) {
  py::class_<Refined>(m, "Refined")
      .def_property_readonly("n_input_vertices",
                             [](const Refined& h) { return h.st().n_input_vertices(); })
      .def_property_readonly("n_vertices",
                             [](const Refined& h) { return h.st().intrinsic().n_vertices(); })
      .def_property_readonly("n_faces",
                             [](const Refined& h) { return h.st().intrinsic().n_faces(); })
      .def_property_readonly("report",
                             [](const Refined& h) -> py::object {
                               return h.report ? py::object(*h.report) : py::none();
                             })
      .def("positions", [](const Refined& h) { return to_numpy(h.st().vertex_positions()); })
      .def("faces", [](const Refined& h) { return to_numpy(faces_of(h.st().intrinsic())); })
      .def("edge_lengths",
           [](const Refined& h) { return to_numpy(side_lengths(h.st().intrinsic())); })
      .def("common_subdivision", &common_subdivision_of)
      .def("laplacian", &laplacian_of)
      .def("from_input", &from_input, py::arg("x"))
      .def("save", &save, py::arg("path"))
      .def_property_readonly("correspondence", [](const Refined& h) {
        return std::string(intrinsic::to_string(h.st().kind()));
      });
  m.def("refine", &refine, py::arg("V"), py::arg("F"), py::arg("min_angle"), py::arg("resolution"),
        py::arg("max_area"), py::arg("max_insertions"), py::arg("relax"), py::arg("max_edge"),
        py::arg("mollify"), py::arg("memory_budget"), py::arg("correspondence") = "integer",
        py::arg("progress") = py::none());
  m.def("load_refined", &load, py::arg("path"));
  m.def("transfer", &transfer, py::arg("refined"), py::arg("x"), py::arg("method"),
        py::arg("back"));
}

}  // namespace ifem::python
