#include "solvers/recipes/pipeline.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstddef>
#include <limits>
#include <mutex>
#include <optional>
#include <sstream>
#include <string_view>
#include <utility>

#include "intrinsic/core/errors.h"
#include "intrinsic/core/geometry.h"
#include "intrinsic/core/timer.h"
#include "intrinsic/core/triangle_formulas.h"
#include "intrinsic/surface/face_analysis.h"

namespace ifem::solvers {
namespace {

using intrinsic::PathReason;
using intrinsic::SurfacePath;

// Sends a progress line to the caller's sink, if any; holds the caller's fraction callback.
class Progress {
 public:
  Progress(const std::function<void(const std::string&)>& sink, const ProgressCallback& fraction)
      : sink_(sink), fraction_(fraction) {}
  void operator()(const std::string& line) const {
    if (sink_) sink_(line);
  }
  const ProgressCallback& fraction() const { return fraction_; }

 private:
  const std::function<void(const std::string&)>& sink_;
  const ProgressCallback& fraction_;
};

std::string fmt(double x) {
  std::ostringstream s;
  s << x;
  return s.str();
}

void require(bool ok, const std::string& what) {
  if (!ok) throw InvalidInput(what);
}

// ---- point clouds ---------------------------------------------------------------------------

void prepare_point_cloud(const PrepareOptions& opt, PreparedSurface& s, const Progress& progress) {
  pointcloud::PointCloudOptions pc;
  pc.k = opt.knn;
  pc.mollify_relative_epsilon = opt.mollify_relative_epsilon;
  pc.intrinsic_delaunay = opt.intrinsic_delaunay;
  pc.self_edges = opt.self_edges;
  const Index nv = s.n_input_vertices();
  const bool with_normals = s.input.normals.rows() == nv && nv > 0;
  s.tri = pointcloud::pointcloud_triangulation(s.input.positions, pc,
                                               with_normals ? &s.input.normals : nullptr, &s.cloud);
  s.path = SurfacePath::kPointCloud;
  s.reason = s.input.has_faces() ? PathReason::kPointCloudRequested : PathReason::kNoFaces;
  s.reason_detail = std::string(intrinsic::to_string(s.reason)) +
                    ", k = " + std::to_string(s.cloud.k) +
                    (s.cloud.normals_from_input ? ", file normals" : ", PCA normals");
  s.mollify = s.cloud.mollify;
  s.flips = s.cloud.flips;
  s.build.unreferenced_vertices = s.cloud.isolated_points;
  s.seconds_build = s.cloud.seconds_knn + s.cloud.seconds_local + s.cloud.seconds_cover;
  s.seconds_flip = s.cloud.seconds_idt;
  std::ostringstream m;
  m << "point cloud: " << nv << " points, k = " << s.cloud.k << ", " << s.cloud.local_triangles
    << " local triangles, " << s.cloud.isolated_points << " isolated points; kNN "
    << s.cloud.seconds_knn << " s, local Delaunay " << s.cloud.seconds_local << " s, tufted cover "
    << s.cloud.seconds_cover << " s, intrinsic Delaunay " << s.cloud.seconds_idt << " s ("
    << s.flips.flips << " flips)";
  progress(m.str());
}

// ---- meshes ---------------------------------------------------------------------------------

void prepare_mesh(const PrepareOptions& opt, PreparedSurface& s, const Progress& progress) {
  intrinsic::SurfaceOptions so;
  so.mollify_relative_epsilon = opt.mollify_relative_epsilon;
  so.intrinsic_delaunay = opt.intrinsic_delaunay;
  so.force_tufted = opt.force_tufted;
  intrinsic::SurfaceTriangulation st =
      intrinsic::build_surface(s.input.triangles, s.input.positions, so);
  s.tri = std::move(st.tri);
  s.path = st.path;
  s.reason = st.reason;
  s.reason_detail = std::move(st.reason_detail);
  s.stats = st.stats;
  s.build = std::move(st.build);
  s.tufted = std::move(st.tufted);
  s.mollify = st.mollify;
  s.flips = st.flips;
  if (s.path == SurfacePath::kTufted) s.boundary_vertex = std::move(st.boundary_vertex);
  s.seconds_build = st.seconds_build;
  s.seconds_flip = st.seconds_flip;
  progress("path: " + std::string(intrinsic::to_string(s.path)) + " (" + s.reason_detail + ")");
  if (s.build.dropped_faces) {
    progress("dropped " + std::to_string(s.build.dropped_faces) + " faces that repeat a vertex");
  }
  if (s.build.reoriented_faces) {
    progress("reoriented " + std::to_string(s.build.reoriented_faces) +
             " faces for a consistent orientation");
  }
  if (s.mollify.delta > 0) {
    progress("mollified " + std::to_string(s.mollify.faces_below_margin) +
             " faces: every edge length + " + fmt(s.mollify.delta));
  }
  if (opt.intrinsic_delaunay) {
    progress("intrinsic Delaunay: " + std::to_string(s.flips.flips) + " flips");
  }
}

// ---- refinement -----------------------------------------------------------------------------

using solvers::describe;  // the RefineReport one (public), beside this overload

std::string describe(const intrinsic::RelaxReport& r) {
  std::ostringstream m;
  m << "relaxed: " << r.passes << " ODT passes, " << r.moved << " moves (" << r.rejected
    << " rejected, longest " << r.max_displacement << "), ";
  if (r.splits > 0) {
    m << r.splits << " long edges split (longest now " << r.max_edge_after << ")"
      << (r.hit_split_cap ? " STOPPED at the split cap" : "") << ", ";
  }
  m << r.flips << " flips, min angle " << r.min_angle_before << "° -> " << r.min_angle_after
    << "°, mean min angle " << r.mean_min_angle_before << "° -> " << r.mean_min_angle_after << "°";
  return m.str();
}

// Why refinement cannot run on s with these settings; "" when it can.
std::string refine_refusal(const PreparedSurface& s, const SurfaceRefineOptions& r) {
  if (s.path == SurfacePath::kPointCloud) {
    return "refinement is not supported on point clouds (their tufted cover is glued from local "
           "triangulations, with a mass of its own)";
  }
  if (s.supports_signposts()) return "";
  const std::string took = "this input took the " + std::string(intrinsic::to_string(s.path)) +
                           " path (" + s.reason_detail + ")";
  if (r.need_signposts) {
    return took +
           ": refinement then runs on the tufted cover, without signposts or integer "
           "coordinates, so inserted vertices have no place on the input; distance and eigen "
           "support that, this operation needs them (edge-manifold, orientable meshes only)";
  }
  if (r.relax_iterations > 0) {
    return "relaxation moves vertices with signposts or integer coordinates, which the tufted "
           "cover (" +
           took + ") does not have";
  }
  return "";
}

// Refines `tracked` (signposts or integer coordinates, built from the input's faces with the
// same mollification: the same insertions and lengths either way) and records what it did;
// `how`: words for the progress line ("" or " with integer coordinates").
template <class Tracked>
void refine_tracked(const SurfaceRefineOptions& r, Tracked& tracked, const char* how,
                    PreparedSurface& s, const Progress& progress, Stopwatch& watch) {
  intrinsic::RefineOptions refine_opt = refine_options(r, s.target_edge_length);
  refine_opt.on_progress = progress.fraction();
  s.refine_report = intrinsic::delaunay_refine(tracked, refine_opt);
  if (s.path != SurfacePath::kManifold) {
    s.path = SurfacePath::kManifold;  // the encroached boundary edges were split
    s.reason = PathReason::kEdgeManifoldOrientable;
    s.reason_detail = "refined (boundary edges opposite obtuse angles are split by refinement)";
  }
  s.boundary_vertex.clear();  // the refined triangulation's own boundary is the surface's
  if (const Index bad = intrinsic::negative_boundary_weights(tracked.intrinsic())) {
    progress("note: " + std::to_string(bad) +
             " boundary edges still face obtuse angles after refinement (needle cones)");
  }
  progress(describe(s.refine_report) + how + " in " + fmt(watch.restart()) + " s");
}

// ODT relaxation of the inserted vertices of `tracked` (either correspondence), when asked for.
template <class Tracked>
void relax_tracked(const SurfaceRefineOptions& r, Tracked& tracked, PreparedSurface& s,
                   const Progress& progress, Stopwatch& watch) {
  if (r.relax_iterations <= 0) return;
  intrinsic::RelaxOptions ro;
  ro.iterations = r.relax_iterations;
  ro.max_edge_length = r.relax_max_edge;
  s.relax_report = intrinsic::relax_inserted_vertices(tracked, ro);
  progress(describe(s.relax_report) + " in " + fmt(watch.seconds()) + " s");
}

// Refines with integer coordinates, then relaxes.
void refine_with_integer(const SurfaceRefineOptions& r, double mollify_epsilon, PreparedSurface& s,
                         const Progress& progress) {
  Stopwatch watch;
  intrinsic::NormalCoordinateTriangulation nc(s.input.triangles, s.input.positions,
                                              mollify_epsilon);
  refine_tracked(r, nc, " with integer coordinates", s, progress, watch);
  relax_tracked(r, nc, s, progress, watch);
  s.tri = nc.intrinsic();
  s.integer = std::move(nc);
}

// Refines the tufted cover itself, intrinsically (nonmanifold / non-orientable / forced).
void refine_tufted(const SurfaceRefineOptions& r, PreparedSurface& s, const Progress& progress) {
  Stopwatch watch;
  intrinsic::RefineOptions refine_opt = refine_options(r, s.target_edge_length);
  refine_opt.on_progress = progress.fraction();
  s.refine_report = intrinsic::delaunay_refine(s.tri, refine_opt);
  // inserted vertices count as interior for the heat method's boundary condition (the cover
  // folds across the input's boundary edges: they are interior edges of it)
  if (!s.boundary_vertex.empty()) s.boundary_vertex.resize(s.tri.n_vertices(), 0);
  s.seconds_refine = watch.seconds();
  progress(describe(s.refine_report) + " on the tufted cover in " + fmt(s.seconds_refine) + " s");
}

// Refines with signposts, then relaxes.
void refine_with_signposts(const SurfaceRefineOptions& r, double mollify_epsilon,
                           PreparedSurface& s, const Progress& progress) {
  Stopwatch watch;
  intrinsic::SignpostTriangulation st(s.input.triangles, s.input.positions, mollify_epsilon);
  refine_tracked(r, st, "", s, progress, watch);
  relax_tracked(r, st, s, progress, watch);
  s.tri = st.intrinsic();
  s.signposts = std::move(st);
}

void refine(const PrepareOptions& opt, PreparedSurface& s, const Progress& progress) {
  const SurfaceRefineOptions& r = *opt.refine;
  const std::string refusal = refine_refusal(s, r);
  if (!refusal.empty()) throw InvalidInput(refusal);
  s.target_edge_length = r.resolution * s.input_mean_edge_length;
  intrinsic::check_refinement_budget(s.tri, refine_options(r, s.target_edge_length));
  const double seconds_flip = s.seconds_flip;
  if (s.supports_signposts() && r.correspondence == intrinsic::Correspondence::kInteger) {
    refine_with_integer(r, opt.mollify_relative_epsilon, s, progress);
  } else if (s.supports_signposts()) {
    refine_with_signposts(r, opt.mollify_relative_epsilon, s, progress);
  } else {
    refine_tufted(r, s, progress);
  }
  s.seconds_flip = seconds_flip;
  s.refined = true;
}

// Ill-conditioning a factorization cannot survive, in words the user can act on: a cotan weight
// many orders of magnitude above the typical one (needle triangles), and the input vertex with
// the longest side relative to the typical side (in practice a stray vertex far from its
// neighbours, e.g. a wrong coordinate). "" when no weight stands out.
std::string conditioning_hint(const PreparedSurface& s) {
  const Eigen::VectorXd w = intrinsic::cotan_weights(s.tri);
  if (w.size() == 0 || !w.allFinite()) return "";
  std::vector<double> magnitudes(w.data(), w.data() + w.size());
  for (double& m : magnitudes) m = std::abs(m);
  const double largest = *std::max_element(magnitudes.begin(), magnitudes.end());
  const double ratio = largest / intrinsic::robust_mean_length(magnitudes);
  if (!(ratio > 1e6)) return "";
  std::ostringstream m;
  m << "; the largest cotan weight is " << ratio << "x the typical one (needle triangles)";
  // the stray vertex: the one with the most sides over 100x the typical side (all of its own
  // sides are; its neighbours have two each)
  const double h = s.input_mean_edge_length;
  std::vector<Index> long_sides(s.n_input_vertices(), 0);
  double longest = 0.0;
  for (const Triangle& t : s.input.triangles) {
    for (int k = 0; k < 3; ++k) {
      const Index a = t[k], b = t[(k + 1) % 3];
      const double l = (s.input.positions.row(a) - s.input.positions.row(b)).norm();
      longest = std::max(longest, l);
      if (h > 0.0 && l > 100.0 * h) ++long_sides[a], ++long_sides[b];
    }
  }
  const auto far = std::max_element(long_sides.begin(), long_sides.end());
  if (far != long_sides.end() && *far > 0) {
    m << "; input vertex " << (far - long_sides.begin()) << " has sides up to " << longest / h
      << "x the typical side length: a stray vertex far from its neighbours? Move or remove it";
  }
  return m.str();
}

// Runs a solve; a factorization failure gets the conditioning hint appended.
template <class F>
auto with_hint(const PreparedSurface& s, F&& solve) -> decltype(solve()) {
  try {
    return solve();
  } catch (const SolverError& e) {
    throw SolverError(e.what() + conditioning_hint(s));
  }
}

// True when some face has a positive area, judged on its lengths normalized by a power of two
// (so that a tiny but real surface, coordinates near 1e-300, counts).
bool has_positive_area(const std::vector<std::array<double, 3>>& face_lengths) {
  for (const auto& l : face_lengths) {
    const double scale = intrinsic::power_of_two_scale(std::max({l[0], l[1], l[2]}));
    if (intrinsic::triangle_area(l[0] / scale, l[1] / scale, l[2] / scale) > 0.0) return true;
  }
  return false;
}

// One clear error for inputs with nothing to compute on: all vertices coincide, every face is
// degenerate (judged on the input, before mollification makes slivers out of it), a cloud
// whose points give no local triangle.
void require_surface(const PreparedSurface& s) {
  std::vector<std::array<double, 3>> lengths;
  if (s.path == SurfacePath::kPointCloud) {
    for (Index f = 0; f < s.tri.n_faces(); ++f) {
      lengths.push_back({s.tri.halfedge_length(3 * f), s.tri.halfedge_length(3 * f + 1),
                         s.tri.halfedge_length(3 * f + 2)});
    }
  } else {
    for (const Triangle& t : s.input.triangles) {
      std::array<double, 3> l;
      for (int k = 0; k < 3; ++k) {
        l[k] = intrinsic::side_length(s.input.positions.row(t[k]).data(),
                                      s.input.positions.row(t[(k + 1) % 3]).data());
      }
      lengths.push_back(l);
    }
  }
  if (has_positive_area(lengths)) return;
  throw InvalidInput(
      "the input has no surface to compute on: " +
      std::string(s.path == SurfacePath::kPointCloud
                      ? "its points give no local triangle (fewer than 3 distinct points, or all "
                        "on one line?)"
                      : "zero total area (all vertices coincide, or every face is degenerate)") +
      "; " + std::to_string(s.n_input_vertices()) + " vertices, " +
      std::to_string(s.input.triangles.size()) + " triangles read");
}

// The last line of defence before a result leaves the library: a NaN (or an inf where none is
// allowed) is an error naming the stage and the vertex, never an output.
void require_finite(const Eigen::MatrixXd& values, const char* stage, bool inf_allowed) {
  for (Eigen::Index j = 0; j < values.cols(); ++j) {
    for (Eigen::Index v = 0; v < values.rows(); ++v) {
      const double x = values(v, j);
      if (std::isnan(x) || (!inf_allowed && std::isinf(x))) {
        throw SolverError(std::string(stage) + ": the value at vertex " + std::to_string(v) +
                          (values.cols() > 1 ? " (column " + std::to_string(j) + ")" : "") +
                          " is " + fmt(x) + "; the operators of this input are degenerate there");
      }
    }
  }
}

void check_input_vertex_ids(const PreparedSurface& s, const std::vector<Index>& ids,
                            const char* what) {
  const Index n = s.n_input_vertices();
  for (const Index v : ids) {
    if (v < 0 || v >= n) {
      throw InvalidInput(std::string(what) + ": vertex " + std::to_string(v) +
                         " out of range [0, " + std::to_string(n) + ")");
    }
  }
}

}  // namespace

intrinsic::RefineOptions refine_options(const SurfaceRefineOptions& r, double target_length) {
  intrinsic::RefineOptions o;
  o.min_angle_degrees = r.min_angle_degrees;
  o.max_area = r.max_area;
  if (target_length > 0.0) {
    const double a = intrinsic::equilateral_area(target_length);
    o.max_area = o.max_area > 0.0 ? std::min(o.max_area, a) : a;
  }
  o.max_insertions = r.max_insertions;
  o.max_memory_bytes = r.max_memory_bytes;
  o.conform = r.conform;
  return o;
}

std::string describe(const intrinsic::RefineReport& r) {
  std::ostringstream m;
  m << "refined: " << r.vertices_before << " -> " << r.vertices_after << " vertices ("
    << r.face_insertions << " circumcenters, " << r.edge_splits << " edge splits, "
    << r.boundary_splits << " boundary splits";
  if (r.constrained_splits) m << ", " << r.constrained_splits << " curve splits";
  m << "), " << r.flips << " flips, min angle " << r.min_angle_before << "° -> "
    << r.min_angle_after_excluding_needles << "°";
  if (r.needle_faces) m << ", " << r.needle_faces << " needle-cone triangles left alone";
  if (r.failed_traces) m << ", " << r.failed_traces << " bad triangles skipped (trace failed)";
  if (r.constrained_floor) {
    m << ", " << r.constrained_floor << " curve splits refused (curves meeting at small angles)";
  }
  if (r.conforming_splits) {
    m << ", " << r.conforming_splits << " conforming splits (negative cotan weights on curves "
      << "or the boundary)";
  }
  if (r.negative_barrier_weights) {
    m << "; " << r.negative_barrier_weights << " curve or boundary edges keep a negative cotan "
      << "weight (" << r.negative_barrier_floor << " below the split floor, most negative "
      << r.min_relative_barrier_weight << " relative)";
  }
  if (r.conforming_hit_cap) m << "; conforming splits STOPPED at their cap";
  if (r.scale_floor_faces) {
    m << ", " << r.scale_floor_faces << " bad triangles left at the scale floor (insertions there "
      << "were cascading: a minimum angle above about 26.5° has no termination guarantee)";
  }
  if (r.hit_insertion_cap) {
    m << "; STOPPED at the insertion cap, " << r.bad_faces_left << " triangles still bad";
  }
  return m.str();
}

void SurfaceRefineOptions::validate() const {
  require(min_angle_degrees > 0.0 && min_angle_degrees <= 30.0,
          "SurfaceRefineOptions: minimum angle must be in (0, 30] degrees, got " +
              fmt(min_angle_degrees));
  require(resolution >= 0.0 && std::isfinite(resolution),
          "SurfaceRefineOptions: resolution must be finite and ≥ 0, got " + fmt(resolution));
  require(max_area >= 0.0 && std::isfinite(max_area),
          "SurfaceRefineOptions: max_area must be finite and ≥ 0, got " + fmt(max_area));
  require(max_insertions >= -1,
          "SurfaceRefineOptions: max_insertions must be ≥ 0 (or −1 for the default), got " +
              std::to_string(max_insertions));
  require(relax_iterations >= 0, "SurfaceRefineOptions: relax_iterations must be ≥ 0, got " +
                                     std::to_string(relax_iterations));
  require(
      relax_max_edge >= 0.0 && std::isfinite(relax_max_edge),
      "SurfaceRefineOptions: relax_max_edge must be finite and ≥ 0, got " + fmt(relax_max_edge));
  require(
      relax_max_edge == 0.0 || relax_iterations > 0,
      "SurfaceRefineOptions: relax_max_edge splits edges during relaxation: set relax_iterations");
  require(max_memory_bytes >= 0.0,
          "SurfaceRefineOptions: max_memory_bytes must be ≥ 0 (0: automatic), got " +
              fmt(max_memory_bytes));
}

SurfaceRefineOptions accurate_distance_refinement() {
  SurfaceRefineOptions r;
  r.resolution = RefinedDistanceOptions{}.resolution;
  return r;
}

void PrepareOptions::validate() const {
  require(mollify_relative_epsilon >= 0.0 && std::isfinite(mollify_relative_epsilon),
          "PrepareOptions: mollify_relative_epsilon must be finite and ≥ 0, got " +
              fmt(mollify_relative_epsilon));
  require(knn >= 2, "PrepareOptions: knn must be ≥ 2, got " + std::to_string(knn));
  require(!(force_tufted && force_pointcloud),
          "PrepareOptions: force_tufted and force_pointcloud exclude each other");
  if (refine) refine->validate();
}

bool PreparedSurface::supports_signposts() const {
  return path != SurfacePath::kPointCloud && stats.edge_manifold() &&
         (reason == PathReason::kEdgeManifoldOrientable ||
          reason == PathReason::kNegativeBoundaryWeights);
}

std::optional<intrinsic::CorrespondenceView> PreparedSurface::correspondence() const {
  if (signposts) return intrinsic::CorrespondenceView(*signposts);
  if (integer) return intrinsic::CorrespondenceView(*integer);
  return std::nullopt;
}

PreparedSurface prepare_surface(io::SurfaceInput input, const PrepareOptions& options) {
  options.validate();
  const Progress progress(options.progress, options.on_progress);
  PreparedSurface s;
  s.input = std::move(input);
  s.mollify_relative_epsilon = options.mollify_relative_epsilon;
  s.input_mean_edge_length = intrinsic::robust_side_length(s.input.triangles, s.input.positions);
  if (!s.input.has_faces() || options.force_pointcloud) {
    prepare_point_cloud(options, s, progress);
  } else {
    prepare_mesh(options, s, progress);
  }
  require_surface(s);
  if (options.refine) refine(options, s, progress);
  return s;
}

PreparedSurface load_surface(const std::string& path, const PrepareOptions& options) {
  options.validate();
  io::SurfaceInput in = io::read_surface(path, options.on_progress);
  if (options.progress) {
    options.progress("read " + path + ": " + std::to_string(in.positions.rows()) + " vertices, " +
                     std::to_string(in.n_polygons) + " faces (" + in.format + ")");
  }
  return prepare_surface(std::move(in), options);
}

Eigen::VectorXd on_input_vertices(const PreparedSurface& s, const Eigen::VectorXd& values) {
  const Index n = s.n_input_vertices();
  require(values.size() >= n, "on_input_vertices: " + std::to_string(values.size()) +
                                  " values for " + std::to_string(n) + " input vertices");
  return values.head(n);
}

Eigen::MatrixXd on_input_vertices(const PreparedSurface& s, const Eigen::MatrixXd& values) {
  const Index n = s.n_input_vertices();
  require(values.rows() >= n, "on_input_vertices: " + std::to_string(values.rows()) + " rows for " +
                                  std::to_string(n) + " input vertices");
  return values.topRows(n);
}

Eigen::VectorXd from_input_vertices(const PreparedSurface& s, const Eigen::VectorXd& values) {
  const Index n = s.n_input_vertices();
  require(values.size() == n, "from_input_vertices: " + std::to_string(values.size()) +
                                  " values, expected one per input vertex (" + std::to_string(n) +
                                  ")");
  if (const auto c = s.correspondence()) return c->input_to_intrinsic(values);
  require(s.tri.n_vertices() == n,
          "from_input_vertices: the triangulation has inserted vertices without signposts "
          "(refined on the tufted cover): input data cannot be carried onto them");
  return values;
}

void DistanceOptions::validate() const {
  require(
      !time_factor || (*time_factor > 0.0 && std::isfinite(*time_factor)),
      "DistanceOptions: time_factor must be finite and > 0, got " + fmt(time_factor.value_or(0)));
  require(!correction_steps || *correction_steps >= 0,
          "DistanceOptions: correction_steps must be ≥ 0, got " +
              std::to_string(correction_steps.value_or(0)));
}

HeatDistanceOptions distance_options(const PreparedSurface& s, const DistanceOptions& settings) {
  settings.validate();
  const RefinedDistanceOptions accurate;
  const bool sized = s.target_edge_length > 0.0;
  HeatDistanceOptions o;  // its time_factor and correction_steps: the paper's, the one default
  o.time_factor = settings.time_factor.value_or(sized ? accurate.time_factor : o.time_factor);
  o.correction_steps =
      settings.correction_steps.value_or(sized ? accurate.correction_steps : o.correction_steps);
  o.precision = settings.precision.value_or(o.precision);
  o.path_bounds = settings.path_bounds;
  o.solver = settings.solver;
  o.intrinsic_delaunay = false;  // prepare_surface already flipped (unless told not to)
  if (s.input.has_faces() && s.path != SurfacePath::kPointCloud) {
    // t from the input mesh's edges (more accurate than the IDT's on sliver meshes), and the
    // input's boundary (a tufted cover has none of its own)
    o.mean_edge_length = sized ? s.target_edge_length : s.input_mean_edge_length;
    o.boundary_vertices = s.boundary_vertex;
    // the input's vertices, for path_bounds' straight-line lower bound (D-141)
    o.vertex_positions = s.input.positions;
  }
  o.validate();
  return o;
}

namespace {

// s prepared again without the faces of its cut-loose vertices (geodesic_distance()'s
// contract, D-360).
struct OutlierCut {
  std::optional<PreparedSurface> surface;  // none: nothing cut, use s
  std::vector<Index> loose;                // vertices with faces on s.tri and none on surface->tri
  std::vector<char> kept;                  // #V_in: the vertex has a face on surface->tri
  std::vector<Index> face;                 // s.input's face → surface->input's, or kInvalidIndex
  std::vector<char> boundary;  // #V of surface->tri: the input's boundary (the hole's rim is not)
};

// The vertices cut_outlier_stars() cuts loose (#V flags), or empty when there is none.
std::vector<char> outlier_vertices(const io::SurfaceInput& in) {
  const Index nv = static_cast<Index>(in.positions.rows());
  std::vector<double> sides;
  sides.reserve(3 * in.triangles.size());
  for (const Triangle& t : in.triangles) {
    for (int i = 0; i < 3; ++i) {
      sides.push_back((in.positions.row(t[i]) - in.positions.row(t[(i + 1) % 3])).norm());
    }
  }
  std::vector<double> sorted = sides;
  const auto p99 = sorted.begin() + static_cast<std::ptrdiff_t>(sorted.size() * 99 / 100);
  std::nth_element(sorted.begin(), p99, sorted.end());
  const double cap = intrinsic::kOutlierClip * *p99;
  std::vector<char> has_face(nv, 0), has_short(nv, 0);
  std::vector<double> shortest(nv, std::numeric_limits<double>::infinity());
  for (std::size_t f = 0; f < in.triangles.size(); ++f) {
    const Triangle& t = in.triangles[f];
    for (int i = 0; i < 3; ++i) {
      const Index a = t[i], b = t[(i + 1) % 3];
      has_face[a] = 1;
      if (sides[3 * f + i] <= cap) has_short[a] = has_short[b] = 1;
      shortest[a] = std::min(shortest[a], sides[3 * f + i]);
      shortest[b] = std::min(shortest[b], sides[3 * f + i]);
    }
  }
  bool any = false;
  for (Index v = 0; v < nv; ++v) any = any || (has_face[v] && !has_short[v]);
  if (!any) return {};
  // ... and whose every side is also longer than the bounding-box diagonal of the other
  // vertices: a spike beyond the whole model, not a genuine fan of long faces (a cylinder's cap)
  Eigen::RowVector3d lo = Eigen::RowVector3d::Constant(std::numeric_limits<double>::infinity());
  Eigen::RowVector3d hi = -lo;
  for (Index v = 0; v < nv; ++v) {
    if (has_face[v] && has_short[v]) {
      lo = lo.cwiseMin(in.positions.row(v));
      hi = hi.cwiseMax(in.positions.row(v));
    }
  }
  const double extent = (hi - lo).norm();
  std::vector<char> cut_vertex(nv, 0);
  any = false;
  for (Index v = 0; v < nv; ++v) {
    cut_vertex[v] = has_face[v] && !has_short[v] && shortest[v] > extent;
    any = any || cut_vertex[v];
  }
  if (!any) return {};
  return cut_vertex;
}

// The input vertices all of whose sides (in the input's faces) are longer than kOutlierClip ×
// the 99th percentile of the input's side lengths (outliers of the robust length scale, D-132)
// and than the bounding-box diagonal of the vertices with a short side are cut loose: the input's
// faces at them are left out and the rest is prepared as s was (mollified, intrinsic Delaunay, the
// same path). Nothing is cut when no vertex qualifies (the usual case: s is used as it is, bit for
// bit), on refined surfaces and point clouds, or when the rest cannot be prepared. (A query
// whose source lost its faces runs on s.tri: GeodesicDistanceSolver.)
OutlierCut cut_outlier_stars(const PreparedSurface& s) {
  OutlierCut cut;
  const io::SurfaceInput& in = s.input;
  if (s.refined || s.path == SurfacePath::kPointCloud || in.triangles.size() < 34) return cut;
  const Index nv = static_cast<Index>(in.positions.rows());
  const std::vector<char> cut_vertex = outlier_vertices(in);
  if (cut_vertex.empty()) return cut;
  std::vector<char> has_face(nv, 0);
  for (const Triangle& t : in.triangles) has_face[t[0]] = has_face[t[1]] = has_face[t[2]] = 1;
  io::SurfaceInput rest;
  rest.positions = in.positions;
  rest.format = in.format;
  cut.kept.assign(nv, 0);
  cut.face.assign(in.triangles.size(), kInvalidIndex);
  for (std::size_t f = 0; f < in.triangles.size(); ++f) {
    const Triangle& t = in.triangles[f];
    if (cut_vertex[t[0]] || cut_vertex[t[1]] || cut_vertex[t[2]]) continue;
    cut.face[f] = static_cast<Index>(rest.triangles.size());
    rest.triangles.push_back(t);
    cut.kept[t[0]] = cut.kept[t[1]] = cut.kept[t[2]] = 1;
  }
  rest.n_polygons = static_cast<Index>(rest.triangles.size());
  PrepareOptions again;
  again.mollify_relative_epsilon = s.mollify_relative_epsilon;
  again.force_tufted = s.path == SurfacePath::kTufted;
  try {
    cut.surface = prepare_surface(std::move(rest), again);
  } catch (const InvalidInput&) {
    return OutlierCut{};  // e.g. nothing left: keep everything
  }
  for (Index v = 0; v < nv; ++v) {
    if (has_face[v] && !cut.kept[v]) cut.loose.push_back(v);
  }
  cut.boundary = s.boundary_vertex;
  if (cut.boundary.empty()) {
    cut.boundary.assign(s.tri.n_vertices(), 0);
    for (Index h = 0; h < s.tri.n_halfedges(); ++h) {
      if (s.tri.twin(h) == kInvalidIndex) {
        cut.boundary[s.tri.tail(h)] = cut.boundary[s.tri.head(h)] = 1;
      }
    }
  }
  cut.boundary.resize(cut.surface->tri.n_vertices(), 0);
  for (const Index v : cut.loose) cut.boundary[v] = 0;
  return cut;
}

// Each cut-loose vertex's distance (every column of d, #V rows): the shortest way to it along
// s.tri's edges from the vertices that kept faces (relaxed until nothing changes).
template <class Matrix>
void fill_cut_loose(const intrinsic::IntrinsicTriangulation& tri, const std::vector<Index>& loose,
                    Matrix& d) {
  for (std::size_t pass = 0; pass <= loose.size(); ++pass) {
    bool changed = false;
    for (const Index v : loose) {
      // v's distance through its neighbour u along an edge of length len
      auto relax = [&](Index u, double len) {
        for (Index j = 0; j < d.cols(); ++j) {
          if (d(u, j) + len < d(v, j)) {
            d(v, j) = d(u, j) + len;
            changed = true;
          }
        }
      };
      const Index start = tri.vertex_halfedge(v);
      // every outgoing halfedge of v (its fan; on a boundary vertex, from the boundary side)
      for (Index h = start;;) {
        relax(tri.head(h), tri.halfedge_length(h));
        const Index p = intrinsic::IntrinsicTriangulation::prev(h);
        const Index back = tri.twin(p);
        if (back == kInvalidIndex) {  // boundary: the last edge of the fan ends at prev's tail
          relax(tri.tail(p), tri.halfedge_length(p));
          break;
        }
        h = back;
        if (h == start) break;
      }
    }
    if (!changed) break;
  }
}

// A heat-distance recipe on s from input vertices: checks the ids, builds the solver
// (GeodesicDistanceSolver: s.tri without the stars of cut-loose vertices, D-360), runs
// query(solver) and restricts its #V or #V×k values to the input.
template <class Query>
auto distance_recipe(const PreparedSurface& s, const std::vector<Index>& sources,
                     const DistanceOptions& settings, const std::string& what, Query query) {
  require(!sources.empty(), what + ": no source vertex given");
  check_input_vertex_ids(s, sources, (what + ": source").c_str());
  return with_hint(s, [&] {
    const GeodesicDistanceSolver solver(s, settings);
    auto d = on_input_vertices(s, query(solver));
    require_finite(d, what.c_str(), true);  // +inf: unreachable, by convention
    return d;
  });
}

}  // namespace

struct GeodesicDistanceSolver::Impl {
  explicit Impl(const PreparedSurface& surface) : s(surface) {}

  // The solver on s.tri itself: the main one when nothing is cut, else built on first use.
  const HeatDistanceSolver& uncut() const {
    if (!cut.surface) return *solver;
    std::call_once(uncut_once, [this] { uncut_solver.emplace(s.tri, options); });
    return *uncut_solver;
  }
  // True when v (an id in range) lost its faces to the cut: its queries run on s.tri.
  bool on_cut_star(Index v) const {
    return cut.surface && v >= 0 && v < static_cast<Index>(cut.kept.size()) && !cut.kept[v];
  }
  template <class Matrix>
  Matrix filled(Matrix d) const {
    if (cut.surface) fill_cut_loose(s.tri, cut.loose, d);
    return d;
  }

  const PreparedSurface& s;
  HeatDistanceOptions options;  // on s
  OutlierCut cut;
  std::optional<HeatDistanceSolver> solver;  // on surface()
  mutable std::once_flag uncut_once;
  mutable std::optional<HeatDistanceSolver> uncut_solver;
};

GeodesicDistanceSolver::GeodesicDistanceSolver(const PreparedSurface& s,
                                               const DistanceOptions& settings)
    : impl_(std::make_unique<Impl>(s)) {
  Impl& m = *impl_;
  m.options = distance_options(s, settings);
  m.cut = cut_outlier_stars(s);
  if (m.cut.surface) {
    HeatDistanceOptions o = m.options;
    o.boundary_vertices = m.cut.boundary;  // h and positions stay s's
    m.solver.emplace(m.cut.surface->tri, o);
  } else {
    m.solver.emplace(s.tri, m.options);
  }
}

GeodesicDistanceSolver::~GeodesicDistanceSolver() = default;
GeodesicDistanceSolver::GeodesicDistanceSolver(GeodesicDistanceSolver&&) noexcept = default;
GeodesicDistanceSolver& GeodesicDistanceSolver::operator=(GeodesicDistanceSolver&&) noexcept =
    default;

Eigen::VectorXd GeodesicDistanceSolver::compute_distance(const std::vector<Index>& sources,
                                                         HeatDistanceReport* report) const {
  const Impl& m = *impl_;
  for (const Index v : sources) {
    if (m.on_cut_star(v)) return m.uncut().compute_distance(sources, report);
  }
  return m.filled(m.solver->compute_distance(sources, report));
}

Eigen::MatrixXd GeodesicDistanceSolver::compute_distances(
    const std::vector<Index>& sources, std::vector<HeatDistanceReport>* reports,
    const ProgressCallback& on_progress) const {
  const Impl& m = *impl_;
  std::vector<Index> on_cut, on_star;  // column numbers of the sources of each solver
  for (std::size_t j = 0; j < sources.size(); ++j) {
    (m.on_cut_star(sources[j]) ? on_star : on_cut).push_back(static_cast<Index>(j));
  }
  if (on_star.empty()) return m.filled(m.solver->compute_distances(sources, reports, on_progress));
  if (on_cut.empty()) return m.uncut().compute_distances(sources, reports, on_progress);
  // both kinds: each solver its own columns, put back in the given order; progress as the
  // fraction of all sources done (the cut surface's first)
  Eigen::MatrixXd d;
  if (reports) reports->assign(sources.size(), HeatDistanceReport{});
  for (const bool star : {false, true}) {
    const std::vector<Index>& cols = star ? on_star : on_cut;
    std::vector<Index> ids;
    for (const Index j : cols) ids.push_back(sources[j]);
    std::vector<HeatDistanceReport> reps;
    const double before = star ? double(on_cut.size()) / double(sources.size()) : 0.0;
    const double share = double(cols.size()) / double(sources.size());
    ProgressCallback part_progress;
    if (on_progress) {
      part_progress = [&](double fraction, std::string_view stage) {
        on_progress(star && fraction >= 1.0 ? 1.0 : before + share * fraction, stage);
      };
    }
    const Eigen::MatrixXd part =
        star ? m.uncut().compute_distances(ids, reports ? &reps : nullptr, part_progress)
             : m.filled(m.solver->compute_distances(ids, reports ? &reps : nullptr, part_progress));
    if (d.size() == 0) d.resize(part.rows(), Eigen::Index(sources.size()));
    for (std::size_t i = 0; i < cols.size(); ++i) {
      d.col(cols[i]) = part.col(Eigen::Index(i));
      if (reports) (*reports)[cols[i]] = reps[i];
    }
  }
  return d;
}

Eigen::VectorXd GeodesicDistanceSolver::compute_distance_from_points(
    const std::vector<SurfacePoint>& points, HeatDistanceReport* report) const {
  return impl_->filled(impl_->solver->compute_distance_from_points(points, report));
}

Eigen::VectorXd GeodesicDistanceSolver::compute_distance_from_points_uncut(
    const std::vector<SurfacePoint>& points, HeatDistanceReport* report) const {
  return impl_->uncut().compute_distance_from_points(points, report);
}

const PreparedSurface& GeodesicDistanceSolver::surface() const {
  return impl_->cut.surface ? *impl_->cut.surface : impl_->s;
}

bool GeodesicDistanceSolver::cut() const { return impl_->cut.surface.has_value(); }

const std::vector<Index>& GeodesicDistanceSolver::surface_face() const { return impl_->cut.face; }

const HeatDistanceOptions& GeodesicDistanceSolver::options() const { return impl_->options; }

double GeodesicDistanceSolver::time_step() const { return impl_->solver->time_step(); }

Eigen::VectorXd geodesic_distance(const PreparedSurface& s, const std::vector<Index>& sources,
                                  const DistanceOptions& settings, HeatDistanceReport* report) {
  return distance_recipe(
      s, sources, settings, "geodesic_distance",
      [&](const GeodesicDistanceSolver& h) { return h.compute_distance(sources, report); });
}

Eigen::MatrixXd geodesic_distances(const PreparedSurface& s, const std::vector<Index>& sources,
                                   const DistanceOptions& settings,
                                   std::vector<HeatDistanceReport>* reports) {
  return distance_recipe(s, sources, settings, "geodesic_distances",
                         [&](const GeodesicDistanceSolver& h) {
                           return h.compute_distances(sources, reports, settings.on_progress);
                         });
}

EigenPairs eigenmodes(const PreparedSurface& s, Index k, const EigenOptions& options) {
  require(k >= 1 && k < s.tri.n_vertices(),
          "eigenmodes: k = " + std::to_string(k) + " must be in [1, " +
              std::to_string(s.tri.n_vertices()) + ") (the number of vertices)");
  EigenPairs ep = with_hint(s, [&] { return eigenpairs(s.tri, k, options); });
  ep.vectors = on_input_vertices(s, ep.vectors);
  require_finite(ep.values, "eigenmodes (eigenvalues)", false);
  require_finite(ep.vectors, "eigenmodes (eigenvectors)", false);
  return ep;
}

Eigen::VectorXd poisson(const PreparedSurface& s, const Eigen::VectorXd& f,
                        const std::vector<Index>& dirichlet_vertices,
                        const Eigen::VectorXd& dirichlet_values, const PoissonOptions& options) {
  check_input_vertex_ids(s, dirichlet_vertices, "poisson: Dirichlet");
  require(dirichlet_values.size() == static_cast<Eigen::Index>(dirichlet_vertices.size()),
          "poisson: " + std::to_string(dirichlet_values.size()) + " Dirichlet values for " +
              std::to_string(dirichlet_vertices.size()) + " vertices");
  const Eigen::VectorXd u = solve_poisson(s.tri, from_input_vertices(s, f), dirichlet_vertices,
                                          dirichlet_values, options);
  Eigen::VectorXd result = on_input_vertices(s, u);
  require_finite(result, "poisson", false);
  return result;
}

}  // namespace ifem::solvers
