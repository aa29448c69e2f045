// `ifem transport` and `ifem logmap`: the Vector Heat Method (Sharp, Soliman, Crane 2019) on
// the intrinsic Delaunay triangulation, results on the input's vertices.
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <optional>
#include <sstream>
#include <string>

#include "cli.h"
#include "cli_refine.h"
#include "intrinsic/core/errors.h"
#include "intrinsic/core/timer.h"
#include "intrinsic/io/tokens.h"
#include "results.h"
#include "solvers/recipes/tangent_fields.h"

namespace ifem::cli {
namespace {

// 'x,y,z' as a vector. @throws UsageError
Eigen::Vector3d parse_vector(const std::string& text) {
  std::istringstream in(text);
  Eigen::Vector3d v;
  std::string part;
  int k = 0;
  bool ok = true;
  while (ok && std::getline(in, part, ',')) ok = k < 3 && io::parse_whole_real(part, v[k++]);
  if (!ok || k != 3 || !v.allFinite()) {
    throw UsageError("--vector '" + text + "': expected three finite numbers x,y,z");
  }
  return v;
}

// Prepares the surface (refined with --refine), with one progress line.
PreparedSurface prepared(const Args& args) {
  std::optional<solvers::SurfaceRefineOptions> refine;
  if (args.has("refine")) refine = refine_settings(args, 0.0, false);
  return prepare_surface(args.positional()[0], args, refine);
}

int run_transport(const Args& args) {
  const ResultOutput out = result_output(args);
  const Eigen::Vector3d vector = parse_vector(args.get("vector"));
  const PreparedSurface s = prepared(args);
  const Stopwatch watch;
  const solvers::VectorHeatSolver solver = solvers::vector_heat_solver(s);
  solvers::VectorHeatReport report;
  const Eigen::MatrixX3d x =
      solvers::transport_on(s, solver, args.count("source"), vector, &report);
  progress(args, "vector heat in " + std::to_string(watch.seconds()) + " s");
  if (out.ply) {
    write_results(out, s, {{"fx", x.col(0)}, {"fy", x.col(1)}, {"fz", x.col(2)}});
  } else {
    write_rows(out.path, x);
  }
  std::printf("wrote %s: %d tangent vectors, %d unreached vertices (nan)\n", out.path.c_str(),
              int(x.rows()), int(report.unreached_vertices + report.unresolved_vertices));
  return 0;
}

// --method as the library's enum. @throws UsageError
solvers::LogMapMethod logmap_method(const Args& args) {
  if (!args.has("method")) return solvers::LogMapMethod::kBlend;
  try {
    return solvers::log_map_method_from(args.get("method"));
  } catch (const InvalidInput& e) {
    throw UsageError(std::string("--method ") + e.what());
  }
}

int run_logmap(const Args& args) {
  const ResultOutput out = result_output(args);
  const solvers::LogMapMethod method = logmap_method(args);
  const PreparedSurface s = prepared(args);
  const Stopwatch watch;
  const solvers::VectorHeatSolver solver = solvers::vector_heat_solver(s);
  const solvers::LogMapResult r = solvers::log_map_on(s, solver, args.count("source"), method);
  const Eigen::MatrixX2d& uv = r.uv;
  const Eigen::VectorXd& d = r.distance;
  progress(args, "log map in " + std::to_string(watch.seconds()) + " s");
  if (out.ply) {
    write_results(out, s, {{"u", uv.col(0)}, {"v", uv.col(1)}, {"distance", d}});
  } else {
    write_rows(out.path, uv);
  }
  double dmax = 0.0;
  Index unreached = 0;
  for (Index v = 0; v < d.size(); ++v) {
    if (std::isfinite(d[v])) dmax = std::max(dmax, d[v]);
    if (std::isinf(d[v])) ++unreached;
  }
  std::printf("wrote %s: log map about vertex %d, max distance %.6g, %d unreached vertices (nan)",
              out.path.c_str(), int(args.count("source")), dmax, int(unreached));
  if (r.report.unresolved_vertices > 0) {
    std::printf(", %d unresolved (nan: the heat underflowed)", int(r.report.unresolved_vertices));
  }
  std::printf("\n");
  return 0;
}

OptionSpec source_option() {
  return vertex("source", "V")
      .mandatory()
      .limited_by(InputLimit::kBelowVertexCount)
      .explain("the source: a 0-based input vertex id");
}

}  // namespace

Command transport_command() {
  Command c;
  c.summary = "parallel transport of a tangent vector from a vertex (vector heat method)";
  c.spec.name = "transport";
  c.spec.positionals = {"MESH"};
  c.spec.prose =
      "Transports a vector given at one vertex to every vertex along shortest geodesics\n"
      "(the Vector Heat Method, Sharp, Soliman, Crane 2019: three heat solves with\n"
      "prefactored matrices on the intrinsic Delaunay triangulation). The vector is\n"
      "projected to the source's tangent plane; its length is kept.\n"
      "  OUT.ply: the input mesh with per-vertex properties fx fy fz;\n"
      "  OUT.txt: 'x y z' per input vertex, in order.\n"
      "Every vertex the source reaches gets a finite vector; the others (another\n"
      "connected component, e.g. the other pieces of a triangle soup, vertices used by\n"
      "no face, or so far that the heat underflows) get 'nan nan nan', counted in the\n"
      "last line as unreached (as `ifem distance` writes inf there).\n"
      "On nonmanifold meshes (the tufted cover) and point clouds the vectors live in\n"
      "per-vertex frames from the normals (faces' or given ones, else PCA of the\n"
      "neighbours), oriented consistently by propagation; the transport between\n"
      "neighbours is the minimal rotation of their normals (no --refine there).\n"
      "With --refine the method runs on the refined triangulation; the vectors are\n"
      "written at the input's vertices, in the directions the correspondence (integer\n"
      "coordinates or signposts, --correspondence) places them in.\n";
  c.spec.groups = {
      {"Options",
       {source_option(), text("vector", "X,Y,Z").mandatory().explain("the vector at the source"),
        text("output", "OUT")
            .short_alias('o')
            .mandatory()
            .with_extensions({".ply", ".txt"})
            .explain("OUT.ply (mesh + fx fy fz) or OUT.txt ('x y z' lines)"),
        flag("refine").explain("intrinsic Delaunay refinement first (options below)")}},
      refine_options_group(0.0),
      surface_options()};
  c.spec.epilogue = "example: ifem transport spot.obj --source 0 --vector 1,0,0 -o t.ply\n";
  c.run = run_transport;
  return c;
}

Command logmap_command() {
  Command c;
  c.summary =
      "logarithmic map (Riemannian coordinates) about a vertex (affine and vector heat methods)";
  c.spec.name = "logmap";
  c.spec.positionals = {"MESH"};
  c.spec.prose =
      "The logarithmic map about a vertex: each vertex's Riemannian coordinates\n"
      "(u, v) = d·(cos θ, sin θ), d its geodesic distance to the source and θ the\n"
      "direction in which the geodesic leaves the source, measured from the direction\n"
      "of the source's first edge, counter-clockwise with the faces' orientation.\n"
      "On nonmanifold meshes and point clouds θ is measured from the x axis\n"
      "projected to the source's tangent plane, counter-clockwise about its\n"
      "(propagated) normal.\n"
      "  OUT.ply: the input mesh with per-vertex properties u, v and distance;\n"
      "  OUT.txt: 'u v' per input vertex, in order.\n"
      "Vertices no path from the source reaches (another component, unreferenced)\n"
      "get u = v = nan and distance inf (as `ifem distance`); vertices where the\n"
      "heat underflows (farther than ~600 mean edge lengths) get nan and are\n"
      "counted separately.\n";
  c.spec.groups = {
      {"Options",
       {source_option(),
        text("method", "M")
            .defaults_to("blend")
            .explain("blend: both methods below, per vertex the affine value where\n"
                     "the two agree (within half a mean edge length of radial\n"
                     "shortfall and 5 % of the distance), the vector heat value where\n"
                     "they do not, a smooth step between. Near-exact on flat regions,\n"
                     "the vector heat method's error far away on curved surfaces; the\n"
                     "cost of both (one more vector heat solve than vector-heat).\n"
                     "vector-heat: the Vector Heat Method (Sharp et al. 2019): the\n"
                     "radius is the heat-method distance (what `ifem distance`\n"
                     "computes), the angle from its gradient against the transported\n"
                     "frame. The smaller radius error over a whole curved mesh (about\n"
                     "1-3 %); builds a distance solver (more memory, precompute).\n"
                     "affine: the affine heat method (Soliman, Sharp 2025): the source\n"
                     "diffused as an affine point, one scalar and one vector heat\n"
                     "solve. Exact on flat (developable) regions, errors 5-10x smaller\n"
                     "near the source and in angle: use it for local charts (decals,\n"
                     "patches within ~1/4 of the mesh's extent); far away on curved\n"
                     "surfaces its radius falls short (5-20 %)."),
        text("output", "OUT")
            .short_alias('o')
            .mandatory()
            .with_extensions({".ply", ".txt"})
            .explain("OUT.ply (mesh + u v distance) or OUT.txt"),
        flag("refine").explain("intrinsic Delaunay refinement first (options below)")}},
      refine_options_group(0.0),
      surface_options()};
  c.spec.epilogue = "example: ifem logmap spot.obj --source 0 -o spot_logmap.ply\n";
  c.run = run_logmap;
  return c;
}

}  // namespace ifem::cli
