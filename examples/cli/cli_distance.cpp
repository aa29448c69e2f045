// `ifem distance`: geodesic distance by the heat method on the intrinsic Delaunay triangulation.
#include <cmath>
#include <cstdio>
#include <optional>

#include "cli.h"
#include "cli_refine.h"
#include "intrinsic/core/errors.h"
#include "intrinsic/core/timer.h"
#include "results.h"
#include "solvers/heat_distance.h"

namespace ifem::cli {
namespace {

// --refine's defaults: the library's accurate mode (resolution, time factor, correction steps)
const solvers::RefinedDistanceSettings kAccurate;

int run(const Args& args) {
  const ResultOutput out = result_output(args);  // checked before any computation
  const std::vector<Index> sources = args.vertices("source");
  // --refine: the library's accurate mode (edges of about 0.4·h, t = ℓ²/4, one correction
  // step: solvers::distance_options; accuracy in BENCHMARKS.md, "Intrinsic Delaunay
  // refinement"); inserted vertices come after the input's, so sources and results keep ids
  std::optional<solvers::RefineSettings> refine;
  if (args.has("refine")) refine = refine_settings(args, kAccurate.resolution, false);
  const PreparedSurface s = prepare_surface(args.positional()[0], args, refine);  // ids < #V
  const Index nv = s.n_input_vertices();
  solvers::DistanceSettings settings;
  if (args.has("time-factor")) settings.time_factor = args.real("time-factor");
  if (args.has("correction-steps")) settings.correction_steps = args.count("correction-steps");
  const solvers::HeatDistanceOptions heat = solvers::distance_options(s, settings);
  const Stopwatch watch;
  solvers::HeatDistanceReport rep;
  const Eigen::VectorXd d = solvers::geodesic_distance(s, sources, settings, &rep);
  progress(args, "heat method: t = " + format_number(heat.time_factor) +
                     "·h² (h = " + format_number(heat.mean_edge_length) + "), " +
                     std::to_string(heat.correction_steps) + " correction steps, " +
                     std::to_string(rep.stages) + " stage" + (rep.stages > 1 ? "s" : "") + ", " +
                     format_number(watch.seconds()) + " s");
  write_results(out, s, {{"distance", d}});
  Index unreachable = 0;
  double dmax = 0.0;
  for (Index v = 0; v < nv; ++v) {
    if (std::isfinite(d[v])) {
      dmax = std::max(dmax, d[v]);
    } else {
      ++unreachable;
    }
  }
  std::printf("wrote %s: %d values, max distance %.6g, %d unreachable (inf)\n", out.path.c_str(),
              nv, dmax, unreachable);
  return 0;
}

}  // namespace

Command distance_command() {
  Command c;
  c.summary = "geodesic distance from source vertices (heat method, intrinsic Delaunay)";
  c.spec.name = "distance";
  c.spec.positionals = {"MESH"};
  c.spec.prose =
      "Approximate geodesic distance from one or more source vertices by the heat\n"
      "method (Crane, Weischedel, Wardetzky 2013) on the intrinsic Delaunay\n"
      "triangulation: one heat step (M + tL) u = δ with t = m·h² (h = mean edge length\n"
      "of the input mesh), the normalized gradient X = −∇u/|∇u|, then L φ = div X.\n"
      "With several sources the value is the distance to the nearest one; every source\n"
      "is exactly 0. Far from the sources on long meshes the heat underflows; the\n"
      "solver then continues in stages from the frontier of the resolved region.\n"
      "Meshes with boundary use the mean of the Neumann and Dirichlet heat solutions.\n";
  c.spec.groups = {
      {"Options",
       {vertex_list("source", "I[,J,...]")
            .mandatory()
            .explain("0-based vertex ids of the input (comma separated)"),
        text("output", "OUT")
            .short_alias('o')
            .mandatory()
            .with_extensions({".ply", ".txt"})
            .explain("OUT.ply: the input mesh with a per-vertex property 'distance'\n"
                     "(opens in MeshLab/ParaView/Polyscope); OUT.txt: one value per line.\n"
                     "Always one value per input vertex, in the input's order; 'inf' for\n"
                     "vertices no source reaches (another connected component, vertices\n"
                     "used by no face)"),
        real("time-factor", "m")
            .above(0)
            .explain("t = m·h² (default 1; " + format_number(kAccurate.time_factor) +
                     " with --refine); larger is smoother, smaller\nis sharper but noisier"),
        count("correction-steps", "N")
            .explain("after the heat method, N times φ ← the solution of\n"
                     "L φ = div(∇φ/|∇φ|) (default 0; " +
                     std::to_string(kAccurate.correction_steps) + " with --refine)"),
        flag("refine").explain(
            "the accurate mode: intrinsic Delaunay refinement first (25° and, by\n"
            "default, edges of about 0.4·h: ~10× the vertices), then t = m·ℓ² with\n"
            "ℓ = 0.4·h and m = 0.25, and one correction step; results on the input\n"
            "vertices. Against exact geodesics it is more accurate than the plain heat\n"
            "method on every reference mesh, most of all on sliver meshes (figures:\n"
            "BENCHMARKS.md, \"Intrinsic Delaunay refinement\").\n"
            "--resolution 0 keeps the angle bound only (t from the input's h, m = 1)")}},
      refine_options_group(kAccurate.resolution),
      surface_options()};
  c.spec.epilogue =
      "examples: ifem distance bunny.obj --source 0 -o bunny_dist.ply\n"
      "          ifem distance part.obj --source 0 --refine -o part_dist.ply\n";
  c.run = run;
  return c;
}

}  // namespace ifem::cli
