// Heat distance (a stateful solver and a one-off), eigenpairs and Poisson, each as the CLI's
// `ifem distance` / `ifem eigen` / `ifem poisson` runs them (examples/cli/cli_distance.cpp,
// cli_eigen.cpp, cli_poisson.cpp): the same prepare_surface() options, the same refinement
// defaults (distance: resolution 0.4, no signposts needed; eigen: resolution 0; poisson:
// resolution 0, signposts needed), the same library calls, so results agree to round-off.
//
// Surface points as heat sources are given on the INPUT's faces; the solver works on the
// flipped (and maybe refined) intrinsic triangulation, so they are located on it by tracing from
// an input corner along the signposts (as intrinsic::insert_surface_point does, without
// inserting anything), or, refined with integer coordinates (the default), through the common
// subdivision (intrinsic::PointLocator). Both exist for edge-manifold, orientable meshes:
// refined ones carry theirs (PreparedSurface::signposts / integer); unrefined ones get a
// SignpostTriangulation of the same input flipped the same way, checked to be edge for edge the
// solver's triangulation.
#include <pybind11/stl.h>

#include <algorithm>
#include <atomic>
#include <cmath>
#include <limits>
#include <memory>
#include <mutex>
#include <optional>
#include <sstream>
#include <string>
#include <utility>
#include <vector>

#include "arrays.h"
#include "bindings.h"
#include "intrinsic/core/errors.h"
#include "intrinsic/core/geometry.h"
#include "intrinsic/core/timer.h"
#include "intrinsic/geodesic/flip_geodesic.h"
#include "intrinsic/geodesic/input_surface.h"
#include "intrinsic/integer/correspondence.h"
#include "intrinsic/refine/signpost.h"

namespace ifem::python {

namespace {

using intrinsic::SignpostTriangulation;
using intrinsic::SurfacePath;
using intrinsic::SurfacePoint;
using T = intrinsic::IntrinsicTriangulation;

std::string num(double x) {
  std::ostringstream s;
  s << x;
  return s.str();
}

// ---- options, checked under the Python names --------------------------------------------------

// The surface keyword arguments of every function here (the CLI's surface options).
struct SurfaceArgs {
  double mollify = intrinsic::kDefaultMollifyEpsilon;
  std::string path = "auto";
  int knn = 30;
  py::object normals = py::none();  ///< #V×3 point normals, or None (as the CLI: a file's normals)
  py::object progress = py::none();  ///< progress(fraction, stage), or None (progress_callback)
};

// `refine`: None (no refinement) or a dict of min_angle / resolution / max_area /
// max_insertions, each None for the CLI's default (resolution: `default_resolution`).
std::optional<solvers::SurfaceRefineOptions> refine_settings(const py::handle& refine,
                                                             double default_resolution,
                                                             bool need_signposts) {
  if (refine.is_none()) return std::nullopt;
  const py::dict d = py::reinterpret_borrow<py::dict>(refine);
  auto get = [&](const char* key) -> py::object {
    return d.contains(key) ? py::object(d[key]) : py::object(py::none());
  };
  solvers::SurfaceRefineOptions r;
  if (!get("min_angle").is_none()) r.min_angle_degrees = get("min_angle").cast<double>();
  r.resolution =
      get("resolution").is_none() ? default_resolution : get("resolution").cast<double>();
  if (!get("max_area").is_none()) r.max_area = get("max_area").cast<double>();
  if (!get("max_insertions").is_none()) r.max_insertions = get("max_insertions").cast<Index>();
  r.need_signposts = need_signposts;
  if (!get("correspondence").is_none()) {
    r.correspondence = intrinsic::parse_correspondence(get("correspondence").cast<std::string>());
  }
  if (!(r.min_angle_degrees > 0.0 && r.min_angle_degrees <= 30.0)) {
    throw InvalidInput("min_angle must be in (0, 30] degrees, got " + num(r.min_angle_degrees));
  }
  if (!(r.resolution >= 0.0 && std::isfinite(r.resolution))) {
    throw InvalidInput("resolution must be finite and ≥ 0 (× the mean edge length), got " +
                       num(r.resolution));
  }
  if (!(r.max_area >= 0.0 && std::isfinite(r.max_area))) {
    throw InvalidInput("max_area must be finite and ≥ 0 (0: no bound), got " + num(r.max_area));
  }
  if (!get("max_insertions").is_none() && r.max_insertions < 0) {
    throw InvalidInput("max_insertions must be ≥ 0, got " + std::to_string(r.max_insertions));
  }
  return r;
}

// The input as arrays, with the options whose range depends on it checked (as the CLI's option
// table does): mollify in [0, 1], knn in [2, #points) on the point-cloud path.
io::SurfaceInput checked_input(const py::handle& V, const py::handle& F, const SurfaceArgs& a) {
  if (!(a.mollify >= 0.0 && a.mollify <= 1.0)) {
    throw InvalidInput("mollify must be in [0, 1] (relative to the mean edge length), got " +
                       num(a.mollify));
  }
  io::SurfaceInput in = surface_input(V, F, a.normals);
  const Index n = static_cast<Index>(in.positions.rows());
  if ((!in.has_faces() || a.path == "pointcloud") && (a.knn < 2 || a.knn >= n)) {
    throw InvalidInput("knn must be in [2, number of points) = [2, " + std::to_string(n) +
                       ") on the point-cloud path, got " + std::to_string(a.knn));
  }
  return in;
}

// prepare_surface() as the CLI runs it (GIL released inside prepare()).
solvers::PreparedSurface prepare_checked(io::SurfaceInput in, const SurfaceArgs& a,
                                         std::optional<solvers::SurfaceRefineOptions> refine) {
  solvers::PrepareOptions o = prepare_options(a.mollify, a.path, true, a.knn);
  o.refine = std::move(refine);
  o.on_progress = progress_callback(a.progress);
  return prepare(std::move(in), o, a.path);
}

solvers::DistanceOptions distance_settings(std::optional<double> time_factor,
                                           std::optional<int> correction_steps,
                                           const std::string& precision, bool path_bounds = true,
                                           const std::string& solver = "direct") {
  using Precision = solvers::HeatDistanceOptions::Precision;
  if (precision != "mixed" && precision != "double") {
    throw InvalidInput("precision must be 'mixed' or 'double', got '" + precision + "'");
  }
  if (time_factor && !(*time_factor > 0.0 && std::isfinite(*time_factor))) {
    throw InvalidInput("time_factor must be finite and > 0 (t = time_factor·h²), got " +
                       num(*time_factor));
  }
  if (correction_steps && *correction_steps < 0) {
    throw InvalidInput("correction_steps must be ≥ 0, got " + std::to_string(*correction_steps));
  }
  solvers::DistanceOptions o;
  o.time_factor = time_factor;
  o.correction_steps = correction_steps;
  o.precision = precision == "double" ? Precision::kDouble : Precision::kMixed;
  o.path_bounds = path_bounds;
  o.solver.kind = solvers::parse_linear_solver(solver);
  return o;
}

// A per-input-vertex result checked as the pipeline checks it (NaN: degenerate operators).
void require_no_nan(const Eigen::MatrixXd& values, const char* what) {
  for (Eigen::Index j = 0; j < values.cols(); ++j) {
    for (Eigen::Index v = 0; v < values.rows(); ++v) {
      if (std::isnan(values(v, j))) {
        throw SolverError(std::string(what) + ": the value at vertex " + std::to_string(v) +
                          " is nan; the operators of this input are degenerate there");
      }
    }
  }
}

// ---- locating input surface points on the intrinsic triangulation ----------------------------
// (intrinsic::locate_input_point, flip_geodesic.h)

// points as (#P faces of F, #P×3 barycentric coordinates): faces in [0, #F), coordinates
// finite, ≥ 0 and summing to 1 (1e-9; normalized).
std::pair<std::vector<Index>, Eigen::MatrixX3d> checked_points(const py::handle& faces,
                                                               const py::handle& bary,
                                                               Index n_faces) {
  std::vector<Index> f = indices_from(faces, n_faces, "points (face column)");
  const Positions b = positions_from(bary, "points (barycentric columns)");
  if (b.rows() != static_cast<Eigen::Index>(f.size())) {
    throw InvalidInput("points: " + std::to_string(f.size()) + " faces for " +
                       std::to_string(b.rows()) + " coordinate rows");
  }
  Eigen::MatrixX3d out(b.rows(), 3);
  for (Eigen::Index i = 0; i < b.rows(); ++i) {
    const Eigen::Vector3d w = b.row(i).transpose();
    if (w.minCoeff() < -1e-12 || std::abs(w.sum() - 1.0) > 1e-9) {
      throw InvalidInput("points[" + std::to_string(i) +
                         "]: barycentric coordinates must be ≥ 0 and sum to 1, got (" + num(w[0]) +
                         ", " + num(w[1]) + ", " + num(w[2]) + ")");
    }
    out.row(i) = w.cwiseMax(0.0).transpose() / w.cwiseMax(0.0).sum();
  }
  return {std::move(f), std::move(out)};
}

// ---- the stateful heat-distance solver --------------------------------------------------------

class DistanceSolver {
 public:
  // mollify: the relative margin s was prepared with (the signposts are built with it too)
  DistanceSolver(solvers::PreparedSurface s, const solvers::DistanceOptions& settings,
                 double mollify)
      : s_(std::move(s)), solver_(s_, settings), mollify_(mollify) {}

  py::array distance(const py::handle& sources) const {
    return timed_query(
        sources, [this](const std::vector<Index>& ids) { return solver_.compute_distance(ids); });
  }

  py::array distances(const py::handle& sources, const py::handle& progress) const {
    const ProgressCallback on_progress = progress_callback(progress);
    return timed_query(sources, [&](const std::vector<Index>& ids) {
      return solver_.compute_distances(ids, nullptr, on_progress);
    });
  }

  py::array distance_from_points(const py::handle& faces, const py::handle& bary) {
    const std::string refusal = points_refusal();
    if (!refusal.empty()) throw InvalidInput(refusal);
    auto [f, b] = checked_points(faces, bary, static_cast<Index>(s_.input.triangles.size()));
    // with stray hubs cut loose (D-360, D-380) the points are located on the solver's surface
    // (the input without the hubs' faces), unless one lies on a cut face or that surface took
    // the tufted path (its hole's rim can choose it; no signposts there): then on s_ uncut
    const std::vector<Index>& kept = solver_.surface_face();
    const solvers::PreparedSurface& c = solver_.surface();
    const bool on_cut_surface = solver_.cut() && c.path == SurfacePath::kManifold && !c.refined &&
                                std::all_of(f.begin(), f.end(), [&](Index g) {
                                  return kept[std::size_t(g)] != kInvalidIndex;
                                });
    Eigen::VectorXd d;
    {
      const py::gil_scoped_release release;
      const Stopwatch watch;
      std::vector<SurfacePoint> pts(f.size());
      auto name = [](std::size_t i) { return "points[" + std::to_string(i) + "]"; };
      // the given faces' points on an input triangulation (`input`, whose face f comes from
      // given face origin[f] of `triangles`), then located on the intrinsic one: by tracing along
      // signposts, or through the common subdivision with integer coordinates (PointLocator,
      // built on the first points query)
      const auto given = [&](const T& input, const std::vector<Index>& origin,
                             const std::vector<Triangle>& triangles,
                             const std::vector<Index>& given_faces, const Eigen::MatrixX3d& w) {
        const std::vector<Index> face_map = intrinsic::given_face_map(origin, triangles.size());
        for (std::size_t i = 0; i < given_faces.size(); ++i) {
          pts[i] = intrinsic::given_face_point(input, triangles, face_map, given_faces[i], w.row(i),
                                               name(i));
        }
      };
      const auto traced = [&](const SignpostTriangulation& st) {
        for (SurfacePoint& p : pts) p = intrinsic::locate_input_point(st, p.face, p.bary);
      };
      if (on_cut_surface) {
        const SignpostTriangulation& st = cut_signposts();
        std::vector<Index> cut_faces(f.size());
        for (std::size_t i = 0; i < f.size(); ++i) cut_faces[i] = kept[std::size_t(f[i])];
        given(st.input(), st.input_face_origin(), solver_.surface().input.triangles, cut_faces, b);
        traced(st);
        d = solvers::on_input_vertices(s_, solver_.compute_distance_from_points(pts));
      } else {
        if (s_.integer) {
          given(s_.integer->input(), s_.integer->input_face_origin(), s_.input.triangles, f, b);
          pts = locator().input_to_intrinsic(pts);
        } else {
          const SignpostTriangulation& st = signposts();
          given(st.input(), st.input_face_origin(), s_.input.triangles, f, b);
          traced(st);
        }
        d = solvers::on_input_vertices(s_, solver_.compute_distance_from_points_uncut(pts));
      }
      last_query_seconds_ = watch.seconds();
    }
    require_no_nan(d, "heat distance");
    return to_numpy(std::move(d));
  }

  py::dict info() const {
    const solvers::HeatDistanceOptions& o = solver_.options();
    py::dict d = surface_info(s_);
    d["time_factor"] = o.time_factor;
    d["correction_steps"] = o.correction_steps;
    d["precision"] =
        o.precision == solvers::HeatDistanceOptions::Precision::kDouble ? "double" : "mixed";
    d["path_bounds"] = o.path_bounds;
    d["time_step"] = solver_.time_step();
    d["step_length"] = o.mean_edge_length;
    d["stray_hubs_cut"] = solver_.cut();
    return d;
  }

  Index n_input_vertices() const { return s_.n_input_vertices(); }
  // The library's own time of the latest query (GIL released: what the binding does not add).
  double last_query_seconds() const { return last_query_seconds_; }

 private:
  // A query from vertex ids (checked against the input), without the GIL, timed, restricted to
  // the input's vertices and checked for NaN: compute(ids) gives #V or #V×k values.
  template <class Compute>
  py::array timed_query(const py::handle& sources, Compute compute) const {
    const std::vector<Index> ids = indices_from(sources, s_.n_input_vertices(), "sources");
    decltype(compute(ids)) d;
    {
      const py::gil_scoped_release release;
      const Stopwatch watch;
      d = solvers::on_input_vertices(s_, compute(ids));
      last_query_seconds_ = watch.seconds();
    }
    require_no_nan(d, "heat distance");
    return to_numpy(std::move(d));
  }

  // The signposts that locate input points on s_.tri (built once, on the first points query).
  // Call after points_refusal() came back empty.
  const SignpostTriangulation& signposts() {
    if (s_.signposts) return *s_.signposts;
    std::call_once(once_, [this] { own_ = build_signposts(s_); });
    if (!own_) throw InvalidInput(mismatch_);
    return *own_;
  }

  // The signposts that locate points on the solver's surface when stray hubs were cut loose.
  const SignpostTriangulation& cut_signposts() {
    std::call_once(cut_once_, [this] { cut_own_ = build_signposts(solver_.surface()); });
    if (!cut_own_) throw InvalidInput(mismatch_);
    return *cut_own_;
  }

  // The point locator of an integer-refined surface (built once, on the first points query).
  const intrinsic::PointLocator& locator() {
    std::call_once(locator_once_,
                   [this] { locator_.emplace(intrinsic::CorrespondenceView(*s_.integer)); });
    return *locator_;
  }

  // Why surface points cannot be located on this surface; "" when they can.
  std::string points_refusal() const {
    if (s_.signposts || s_.integer || (s_.path == SurfacePath::kManifold && !s_.refined)) {
      return "";
    }
    return "points need signposts to be located on the solver's flipped triangulation (an "
           "edge-manifold, orientable mesh); this input took the " +
           std::string(intrinsic::to_string(s_.path)) + " path (" + s_.reason_detail +
           "): give vertex ids as sources instead";
  }

  // Signposts of p's input flipped as p.tri was, checked to be p.tri edge for edge.
  std::optional<SignpostTriangulation> build_signposts(const solvers::PreparedSurface& p) {
    SignpostTriangulation st(p.input.triangles, p.input.positions, mollify_);
    st.flip_to_delaunay();
    const T& a = st.intrinsic();
    const T& b = p.tri;
    if (a.tails() != b.tails() || a.twins() != b.twins() || a.edges() != b.edges() ||
        a.lengths() != b.lengths()) {
      mismatch_ =
          "points: the signpost triangulation of this input did not come out edge for edge as "
          "the solver's (mollify = 0 with degenerate triangles?); use refine=True, whose "
          "triangulation carries its signposts, or vertex ids as sources";
      return std::nullopt;
    }
    return st;
  }

  solvers::PreparedSurface s_;
  solvers::GeodesicDistanceSolver solver_;
  double mollify_;
  std::once_flag once_;
  std::optional<SignpostTriangulation> own_;
  std::once_flag cut_once_;
  std::optional<SignpostTriangulation> cut_own_;
  std::string mismatch_;  // why own_ or cut_own_ could not be built
  std::once_flag locator_once_;
  std::optional<intrinsic::PointLocator> locator_;
  mutable std::atomic<double> last_query_seconds_{0.0};
};

std::unique_ptr<DistanceSolver> make_distance_solver(const py::handle& V, const py::handle& F,
                                                     std::optional<double> time_factor,
                                                     std::optional<int> correction_steps,
                                                     const SurfaceArgs& a, const py::handle& refine,
                                                     const std::string& precision, bool path_bounds,
                                                     const std::string& solver) {
  const solvers::DistanceOptions settings =
      distance_settings(time_factor, correction_steps, precision, path_bounds, solver);
  std::optional<solvers::SurfaceRefineOptions> r =
      refine_settings(refine, solvers::RefinedDistanceOptions{}.resolution, false);
  solvers::PreparedSurface s = prepare_checked(checked_input(V, F, a), a, std::move(r));
  const py::gil_scoped_release release;
  return std::make_unique<DistanceSolver>(std::move(s), settings, a.mollify);
}

// ---- one-off functions ------------------------------------------------------------------------

// solvers::geodesic_distance(), the CLI's call, from vertex sources.
py::array heat_distance(const py::handle& V, const py::handle& F, const py::handle& sources,
                        std::optional<double> time_factor, std::optional<int> correction_steps,
                        const SurfaceArgs& a, const py::handle& refine,
                        const std::string& precision, bool path_bounds, const std::string& solver) {
  const solvers::DistanceOptions settings =
      distance_settings(time_factor, correction_steps, precision, path_bounds, solver);
  std::optional<solvers::SurfaceRefineOptions> r =
      refine_settings(refine, solvers::RefinedDistanceOptions{}.resolution, false);
  io::SurfaceInput in = checked_input(V, F, a);
  const std::vector<Index> ids =
      indices_from(sources, static_cast<Index>(in.positions.rows()), "sources");
  const solvers::PreparedSurface s = prepare_checked(std::move(in), a, std::move(r));
  Eigen::VectorXd d;
  {
    const py::gil_scoped_release release;
    d = solvers::geodesic_distance(s, ids, settings);
  }
  return to_numpy(std::move(d));
}

py::tuple eigen(const py::handle& V, const py::handle& F, Index k, const SurfaceArgs& a,
                const py::handle& refine, Index coarse, Index coarse_iterations) {
  std::optional<solvers::SurfaceRefineOptions> r = refine_settings(refine, 0.0, false);
  io::SurfaceInput in = checked_input(V, F, a);
  const Index n = static_cast<Index>(in.positions.rows());
  if (k < 1 || k >= n) {
    throw InvalidInput("k must be in [1, number of vertices) = [1, " + std::to_string(n) +
                       "), got " + std::to_string(k));
  }
  const solvers::PreparedSurface s = prepare_checked(std::move(in), a, std::move(r));
  solvers::EigenOptions eo;
  eo.on_progress = progress_callback(a.progress);
  eo.coarse = coarse;
  eo.coarse_iterations = coarse_iterations;
  solvers::EigenPairs ep;
  {
    const py::gil_scoped_release release;
    ep = solvers::eigenmodes(s, k, eo);
  }
  py::dict info = surface_info(s);
  info["eigen_coarse_vertices"] = ep.coarse_vertices;
  info["eigen_residuals"] = to_numpy(std::move(ep.residuals));
  return py::make_tuple(to_numpy(std::move(ep.values)), to_numpy(std::move(ep.vectors)), info);
}

// Dirichlet data: distinct ids in [0, n) and as many finite values.
std::pair<std::vector<Index>, Eigen::VectorXd> checked_dirichlet(const py::handle& ids,
                                                                 const py::handle& values,
                                                                 Index n) {
  std::vector<Index> dv = indices_from(ids, n, "dirichlet (vertex ids)", true);
  Eigen::VectorXd g = values_from(values, Eigen::Index(dv.size()), "dirichlet (values)");
  std::vector<Index> sorted = dv;
  std::sort(sorted.begin(), sorted.end());
  const auto twice = std::adjacent_find(sorted.begin(), sorted.end());
  if (twice != sorted.end()) {
    throw InvalidInput("dirichlet: vertex " + std::to_string(*twice) + " is given twice");
  }
  return {std::move(dv), std::move(g)};
}

py::tuple poisson(const py::handle& V, const py::handle& F, const py::handle& rhs,
                  const py::handle& dirichlet_ids, const py::handle& dirichlet_values,
                  double screening, const SurfaceArgs& a, const py::handle& refine,
                  const std::string& solver) {
  if (!(screening >= 0.0 && std::isfinite(screening))) {
    throw InvalidInput("screening must be finite and ≥ 0, got " + num(screening));
  }
  std::optional<solvers::SurfaceRefineOptions> r = refine_settings(refine, 0.0, true);
  io::SurfaceInput in = checked_input(V, F, a);
  const Index n = static_cast<Index>(in.positions.rows());
  const Eigen::VectorXd f = rhs.is_none() ? Eigen::VectorXd::Zero(n) : values_from(rhs, n, "rhs");
  auto [dv, g] = checked_dirichlet(dirichlet_ids, dirichlet_values, n);
  const solvers::PreparedSurface s = prepare_checked(std::move(in), a, std::move(r));
  solvers::PoissonOptions o;
  o.screening = screening;
  o.solver.kind = solvers::parse_linear_solver(solver);
  Eigen::VectorXd u;
  {
    const py::gil_scoped_release release;
    u = solvers::poisson(s, f, dv, g, o);
  }
  return py::make_tuple(to_numpy(std::move(u)), surface_info(s));
}

SurfaceArgs surface_args(double mollify, const std::string& path, int knn,
                         const py::handle& normals, const py::handle& progress) {
  return {mollify, path, knn, py::reinterpret_borrow<py::object>(normals),
          py::reinterpret_borrow<py::object>(progress)};
}

}  // namespace

void bind_solvers(py::module_& m) {
  using Opt = std::optional<double>;
  using Steps = std::optional<int>;
  py::class_<DistanceSolver>(m, "HeatDistanceSolver")
      .def(py::init([](const py::handle& V, const py::handle& F, Opt t, Steps c, double mollify,
                       const std::string& path, int knn, const py::handle& refine,
                       const std::string& precision, const py::handle& normals,
                       const py::handle& progress, bool path_bounds, const std::string& solver) {
             return make_distance_solver(V, F, t, c,
                                         surface_args(mollify, path, knn, normals, progress),
                                         refine, precision, path_bounds, solver);
           }),
           py::arg("V"), py::arg("F"), py::arg("time_factor"), py::arg("correction_steps"),
           py::arg("mollify"), py::arg("path"), py::arg("knn"), py::arg("refine"),
           py::arg("precision") = "double", py::arg("normals") = py::none(),
           py::arg("progress") = py::none(), py::arg("path_bounds") = true,
           py::arg("solver") = "direct")
      .def("compute_distance", &DistanceSolver::distance, py::arg("sources"))
      .def("compute_distances", &DistanceSolver::distances, py::arg("sources"),
           py::arg("progress") = py::none())
      .def("compute_distance_from_points", &DistanceSolver::distance_from_points, py::arg("faces"),
           py::arg("bary"))
      .def_property_readonly("info", &DistanceSolver::info)
      .def_property_readonly("n_input_vertices", &DistanceSolver::n_input_vertices)
      .def_property_readonly("last_query_seconds", &DistanceSolver::last_query_seconds);
  m.def(
      "heat_distance",
      [](const py::handle& V, const py::handle& F, const py::handle& sources, Opt t, Steps c,
         double mollify, const std::string& path, int knn, const py::handle& refine,
         const std::string& precision, const py::handle& normals, const py::handle& progress,
         bool path_bounds, const std::string& solver) {
        return heat_distance(V, F, sources, t, c,
                             surface_args(mollify, path, knn, normals, progress), refine, precision,
                             path_bounds, solver);
      },
      py::arg("V"), py::arg("F"), py::arg("sources"), py::arg("time_factor"),
      py::arg("correction_steps"), py::arg("mollify"), py::arg("path"), py::arg("knn"),
      py::arg("refine"), py::arg("precision") = "double", py::arg("normals") = py::none(),
      py::arg("progress") = py::none(), py::arg("path_bounds") = true,
      py::arg("solver") = "direct");
  m.def(
      "eigen",
      [](const py::handle& V, const py::handle& F, Index k, double mollify, const std::string& path,
         int knn, const py::handle& refine, const py::handle& normals, const py::handle& progress,
         Index coarse, Index coarse_iterations) {
        return eigen(V, F, k, surface_args(mollify, path, knn, normals, progress), refine, coarse,
                     coarse_iterations);
      },
      py::arg("V"), py::arg("F"), py::arg("k"), py::arg("mollify"), py::arg("path"), py::arg("knn"),
      py::arg("refine"), py::arg("normals") = py::none(), py::arg("progress") = py::none(),
      py::arg("coarse") = 0, py::arg("coarse_iterations") = 0);
  m.def(
      "poisson",
      [](const py::handle& V, const py::handle& F, const py::handle& rhs, const py::handle& ids,
         const py::handle& values, double screening, double mollify, const std::string& path,
         int knn, const py::handle& refine, const py::handle& normals, const py::handle& progress,
         const std::string& solver) {
        return poisson(V, F, rhs, ids, values, screening,
                       surface_args(mollify, path, knn, normals, progress), refine, solver);
      },
      py::arg("V"), py::arg("F"), py::arg("rhs"), py::arg("dirichlet_ids"),
      py::arg("dirichlet_values"), py::arg("screening"), py::arg("mollify"), py::arg("path"),
      py::arg("knn"), py::arg("refine"), py::arg("normals") = py::none(),
      py::arg("progress") = py::none(), py::arg("solver") = "direct");
}

}  // namespace ifem::python
