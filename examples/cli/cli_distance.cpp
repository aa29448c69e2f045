// `ifem distance`: geodesic distance by the heat method on the intrinsic Delaunay triangulation,
// from source vertices or from curves (--curves).
#include <cmath>
#include <cstdio>
#include <fstream>
#include <limits>
#include <optional>
#include <string>
#include <utility>

#include "cli.h"
#include "cli_curves.h"
#include "cli_exact.h"
#include "cli_isolines.h"
#include "cli_refine.h"
#include "cli_signed.h"
#include "cli_solver.h"
#include "intrinsic/core/errors.h"
#include "intrinsic/core/timer.h"
#include "intrinsic/io/tokens.h"
#include "results.h"
#include "solvers/recipes/curves.h"
#include "solvers/recipes/text_formats.h"
#include "solvers/scalar/heat_distance.h"

namespace ifem::cli {
namespace {

// --refine's defaults: the library's accurate mode (resolution, time factor, correction steps)
const solvers::RefinedDistanceOptions kAccurate;

// The heat method's line and the summary, for both forms of the command.
void report(const Args& args, const ResultOutput& out, const Eigen::VectorXd& d, Index nv,
            const std::string& heat, double seconds, const solvers::HeatDistanceReport& rep) {
  progress(args, "heat method: " + heat + std::to_string(rep.stages) + " stage" +
                     (rep.stages > 1 ? "s" : "") + ", " + format_number(seconds) + " s");
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
}

solvers::DistanceOptions distance_settings(const Args& args) {
  solvers::DistanceOptions settings;
  if (args.has("time-factor")) settings.time_factor = args.real("time-factor");
  if (args.has("correction-steps")) settings.correction_steps = args.count("correction-steps");
  if (args.has("mixed-precision")) {
    settings.precision = solvers::HeatDistanceOptions::Precision::kMixed;
  }
  settings.path_bounds = !args.has("no-path-bounds");
  settings.solver = solver_choice(args);
  settings.on_progress = progress_bar(args);
  return settings;
}

// --sources-batch: one distance column per source, each from that source alone.
int run_batch(const Args& args, const ResultOutput& out) {
  const std::string path = args.get("sources-batch");
  // the file is read before the mesh (a malformed one fails fast), its ids checked once #V is known
  const std::vector<recipes::ListedVertex> listed = recipes::read_vertex_list(path);
  std::optional<solvers::SurfaceRefineOptions> refine;
  if (args.has("refine")) refine = refine_settings(args, kAccurate.resolution, false);
  const PreparedSurface s = prepare_surface(args.positional()[0], args, refine);
  const Index nv = s.n_input_vertices();
  const std::vector<Index> sources = recipes::checked_vertex_ids(path, listed, nv);
  const Stopwatch watch;
  std::vector<solvers::HeatDistanceReport> reps;
  const Eigen::MatrixXd d = solvers::geodesic_distances(s, sources, distance_settings(args), &reps);
  const double seconds = watch.seconds();
  Index multi_stage = 0;
  for (const auto& r : reps) multi_stage += r.stages > 1;
  progress(args, "heat method: " + std::to_string(sources.size()) + " sources in " +
                     format_number(seconds) + " s (" +
                     format_number(seconds / double(sources.size())) + " s per source; " +
                     std::to_string(multi_stage) + " needed several stages)");
  const std::string ext = io::file_extension(out.path);
  if (ext == ".npy") {
    write_npy(out.path, d);
  } else if (ext == ".txt") {
    write_rows(out.path, d);
  } else {
    std::vector<io::VertexProperty> props;
    for (Eigen::Index j = 0; j < d.cols(); ++j) {
      props.push_back({"distance_" + std::to_string(j), d.col(j)});
    }
    write_results(out, s, props);
  }
  std::printf("wrote %s: %d vertices × %d sources (one column per source, in %s's order)\n",
              out.path.c_str(), nv, int(d.cols()), path.c_str());
  return 0;
}

// --curves: the distance to the union of the curves (every vertex on them is a source).
int run_distance_curves(const Args& args, const ResultOutput& out) {
  std::vector<solvers::CurveCondition> curves = read_curves(args);  // fails fast, before the mesh
  io::SurfaceInput input = read_input(args.positional()[0], args);
  std::optional<solvers::SurfaceRefineOptions> refine;
  if (args.has("refine")) refine = refine_settings(args, kAccurate.resolution, true);
  CurveRun run{prepare_curves(std::move(input), std::move(curves), args, false, refine), {}};
  const Stopwatch watch;
  solvers::HeatDistanceReport rep;
  const Eigen::VectorXd d = solvers::curve_distance(run.surface, distance_settings(args), &rep);
  const double seconds = watch.seconds();
  run.polylines = curve_polylines_if_asked(args, run.surface);
  const auto iso = isolines_if_asked(args, run.surface.surface.input, d, "distance");
  write_curve_outputs(args, out, run, {{"distance", d}});
  if (iso) write_isolines(*iso);
  report(args, out, d, run.surface.n_input_vertices(), "", seconds, rep);
  print_curves_written(args, run);
  return 0;
}

int run_distance(const Args& args) {
  const ResultOutput out = result_output(args);  // checked before any computation
  check_signed_options(args);
  check_curve_options(args, {{"source",
                              "the curves are the sources (--curves gives the "
                              "distance to the nearest curve)"},
                             {"sources-batch", "the curves are the sources"}});
  check_isoline_options(args);
  check_path_options(args);
  if (args.has("sources-batch") && args.has("isolines")) {
    throw UsageError("--isolines: one field only (not with --sources-batch's columns)");
  }
  if (args.has("sources-batch") && args.has("source")) {
    throw UsageError(
        "--sources-batch and --source cannot be used together: --source gives the "
        "distance to the nearest of its vertices, --sources-batch one column per "
        "vertex");
  }
  if (io::file_extension(out.path) == ".npy" && !args.has("sources-batch")) {
    throw UsageError("--output '" + out.path +
                     "': .npy holds a matrix, written only with "
                     "--sources-batch (use .ply or .txt)");
  }
  if (args.has("signed")) return run_signed(args, out);
  if (args.has("exact")) return run_exact_distance(args, out);
  if (args.has("curves")) return run_distance_curves(args, out);
  if (args.has("sources-batch")) return run_batch(args, out);
  if (!args.has("source")) {
    throw UsageError(
        "missing --source I[,J,...] (or --sources-batch FILE or --curves FILE; see "
        "--help)");
  }
  const std::vector<Index> sources = args.vertices("source");
  // --refine: the library's accurate mode (edges of about 0.4·h, t = ℓ²/4, one correction
  // step: solvers::distance_options; accuracy in BENCHMARKS.md, "Intrinsic Delaunay
  // refinement"); inserted vertices come after the input's, so sources and results keep ids
  std::optional<solvers::SurfaceRefineOptions> refine;
  if (args.has("refine")) refine = refine_settings(args, kAccurate.resolution, false);
  const PreparedSurface s = prepare_surface(args.positional()[0], args, refine);  // ids < #V
  const Index nv = s.n_input_vertices();
  const solvers::DistanceOptions settings = distance_settings(args);
  const solvers::HeatDistanceOptions heat = solvers::distance_options(s, settings);
  const Stopwatch watch;
  solvers::HeatDistanceReport rep;
  const Eigen::VectorXd d = solvers::geodesic_distance(s, sources, settings, &rep);
  const double seconds = watch.seconds();
  const auto iso = isolines_if_asked(args, s.input, d, "distance");
  write_results(out, s, {{"distance", d}});
  if (iso) write_isolines(*iso);
  report(args, out, d, nv,
         "t = " + format_number(heat.time_factor) +
             "·h² (h = " + format_number(heat.mean_edge_length) + "), " +
             std::to_string(heat.correction_steps) + " correction steps, ",
         seconds, rep);
  return 0;
}

const char* const kDistanceProse =
    "Approximate geodesic distance from one or more source vertices by the heat\n"
    "method (Crane, Weischedel, Wardetzky 2013) on the intrinsic Delaunay\n"
    "triangulation: one heat step (M + tL) u = δ with t = m·h² (h = mean edge length\n"
    "of the input mesh), the normalized gradient X = −∇u/|∇u|, then L φ = div X.\n"
    "With several sources the value is the distance to the nearest one; every source\n"
    "is exactly 0. Far from the sources on long meshes the heat underflows; the\n"
    "solver then continues in stages from the frontier of the resolved region.\n"
    "Meshes with boundary use the mean of the Neumann and Dirichlet heat solutions.\n"
    "Each value is then clamped into bounds the exact distance always satisfies: at\n"
    "least the straight-line distance to the nearest source, at most the shortest\n"
    "path along edges and across flat diamonds (never less accurate; docs D-141;\n"
    "--no-path-bounds skips it: faster for many sources, the method's raw values).\n\n"
    "Many sources, each on its own (--sources-batch FILE, instead of --source): a\n"
    "distance matrix, one column per source (landmarks, descriptors, embeddings).\n"
    "The solves of up to 32 sources go through the factors together, so a source\n"
    "costs a fraction of a separate run (BENCHMARKS.md, \"Batched sources\").\n\n"
    "From curves (--curves FILE, format below; instead of --source): the distance to\n"
    "the nearest point of any curve drawn through the mesh's vertices (geodesic paths,\n"
    "loops, Bézier curves). The curves become edges of a constrained intrinsic\n"
    "Delaunay triangulation, every vertex on them is a source (exactly 0 there), and\n"
    "--refine refines without crossing them. Needs an edge-manifold, orientable\n"
    "triangle mesh; the curves' values and slits do not change the distance.\n\n"
    "Exact (--exact, with --source): the exact polyhedral geodesic distance instead\n"
    "(window propagation; slower, no approximation: a reference to measure against).\n";

OptionGroup distance_options() {
  OptionGroup g = {
      "Options",
      {vertex_list("source", "I[,J,...]")
           .explain("0-based vertex ids of the input (comma separated); required unless\n"
                    "--sources-batch or --curves is given"),
       text("sources-batch", "FILE")
           .explain("one 0-based vertex id per line ('#' comments): the distance from\n"
                    "each of them alone, one column per line of FILE, in its order;\n"
                    "OUT.txt: one line per input vertex, columns separated by spaces;\n"
                    "OUT.npy: a NumPy array (#V, k) of float64; OUT.ply: properties\n"
                    "distance_0 .. distance_{k-1}"),
       text("output", "OUT")
           .short_alias('o')
           .mandatory()
           .with_extensions({".ply", ".txt", ".npy"})
           .explain("OUT.ply: the input mesh with a per-vertex property 'distance'\n"
                    "(opens in MeshLab/ParaView/Polyscope); OUT.txt: one value per line.\n"
                    "Always one value per input vertex, in the input's order; 'inf' for\n"
                    "vertices no source reaches (another connected component, vertices\n"
                    "used by no face)"),
       real("time-factor", "m")
           .above(0)
           .explain("t = m·h² (default " +
                    format_number(solvers::HeatDistanceOptions{}.time_factor) + "; " +
                    format_number(kAccurate.time_factor) +
                    " with --refine); larger is smoother, smaller\nis sharper but noisier"),
       count("correction-steps", "N")
           .explain("after the heat method, N times φ ← the solution of\n"
                    "L φ = div(∇φ/|∇φ|) (default " +
                    std::to_string(solvers::HeatDistanceOptions{}.correction_steps) + "; " +
                    std::to_string(kAccurate.correction_steps) + " with --refine)"),
       flag("mixed-precision")
           .explain("read the Poisson factor as floats in the solves (half its bytes per\n"
                    "query; distances move by at most ~3e-7 relative, far below the method's\n"
                    "~1% error). Pays only where the solves are memory-bound: not on the\n"
                    "machine of BENCHMARKS.md, \"Heat queries\""),
       solver_option(),
       flag("no-path-bounds")
           .explain("the heat method's values as solved, without the clamp into the\n"
                    "bounds above (to see or measure the method's own error)"),
       flag("exact").explain(exact_flag_help()),
       flag("refine").explain(
           "the accurate mode: intrinsic Delaunay refinement first (25° and, by\n"
           "default, edges of about 0.4·h: ~10× the vertices), then t = m·ℓ² with\n"
           "ℓ = 0.4·h and m = 0.25, and one correction step; results on the input\n"
           "vertices. Against exact geodesics it is more accurate than the plain heat\n"
           "method on every reference mesh, most of all on sliver meshes (figures:\n"
           "BENCHMARKS.md, \"Intrinsic Delaunay refinement\").\n"
           "--resolution 0 keeps the angle bound only (t from the input's h, m = 1)")}};
  const std::vector<OptionSpec> curves = curve_options(
      "the distance to these curves instead of --source (only where they run\n"
      "counts; their values are ignored)");
  g.options.insert(g.options.end(), curves.begin(), curves.end());
  const std::vector<OptionSpec> paths = exact_path_options();
  g.options.insert(g.options.end(), paths.begin(), paths.end());
  const std::vector<OptionSpec> iso = isoline_options("distance");
  g.options.insert(g.options.end(), iso.begin(), iso.end());
  const std::vector<OptionSpec> signed_distance = signed_options();
  g.options.insert(g.options.end(), signed_distance.begin(), signed_distance.end());
  return g;
}

}  // namespace

Command distance_command() {
  Command c;
  c.summary = "geodesic distance from vertices or curves, signed distance (heat methods)";
  c.spec.name = "distance";
  c.spec.positionals = {"MESH"};
  c.spec.prose = kDistanceProse;
  c.spec.groups = {distance_options(), refine_options_group(kAccurate.resolution),
                   surface_options()};
  c.spec.epilogue =
      curves_file_help(false) + signed_help() +
      "\nexamples: ifem distance bunny.obj --source 0 -o bunny_dist.ply\n"
      "          ifem distance part.obj --source 0 --refine -o part_dist.ply\n"
      "          ifem distance bunny.obj --source 0 --exact -o bunny_exact.txt\n"
      "          ifem distance bunny.obj --source 0 --exact --paths-from 10,20 --paths-out p.obj "
      "-o d.ply\n"
      "          ifem distance bunny.obj --sources-batch landmarks.txt -o D.npy\n"
      "          ifem distance bunny.obj --curves curves.txt --curves-out c.obj -o d.ply\n"
      "          ifem distance bunny.obj --source 0 --isolines 10 --isolines-out iso.obj -o "
      "d.ply\n"
      "          ifem distance bunny.obj --signed --curves curves.txt -o sd.ply\n"
      "          ifem distance scan.ply --signed --points oriented.txt -o sd.ply\n";
  c.run = run_distance;
  return c;
}

}  // namespace ifem::cli
