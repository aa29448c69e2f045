#include "cli_exact.h"

#include <cmath>
#include <cstdio>
#include <optional>
#include <string>

#include "cli_isolines.h"
#include "cli_refine.h"
#include "intrinsic/core/timer.h"
#include "polylines.h"
#include "solvers/recipes/exact_distance.h"

namespace ifem::cli {

const char* exact_flag_help() {
  return "exact polyhedral geodesic distance instead of the heat method: window\n"
         "propagation over the faces (Chen-Han / Xin-Wang with pruning), from the\n"
         "edge lengths alone, so it runs on the input's own faces (not flipped: on\n"
         "scans the intrinsic Delaunay faces need several times the windows), on\n"
         "the tufted cover (--tufted, nonmanifold meshes) and after --refine (same\n"
         "surface, same distances). Cost: time grows about as #F^1.5 (the windows;\n"
         "figures in BENCHMARKS.md); memory: the windows waiting at once (64 bytes\n"
         "each), all of them with --paths-from; --memory-budget GB stops it with the\n"
         "figures instead of exhausting memory. Takes --source only; --mollify\n"
         "defaults to 1e-12 here (the input's own lengths; only zero-area faces\n"
         "are lifted, by about 1e-12 of the mean edge)";
}

void check_path_options(const Args& args) {
  if (args.has("paths-from") != args.has("paths-out")) {
    throw UsageError("--paths-from I,J,... and --paths-out FILE go together (--exact)");
  }
  if (!args.has("paths-from")) return;
  if (!args.has("exact")) throw UsageError("--paths-from needs --exact");
  if (args.has("refine")) {
    throw UsageError("--paths-from draws on the input's own faces: not with --refine");
  }
}

std::vector<OptionSpec> exact_path_options() {
  return {text("paths-from", "I,J,...")
              .explain("with --exact: also the exact geodesic from each of these input\n"
                       "vertices back to its nearest source, written to --paths-out (the\n"
                       "distances are the same)"),
          text("paths-out", "PATHS")
              .with_extensions({".obj", ".ply"})
              .explain("the paths' file: PATHS.obj ('v' and 'l' lines) or PATHS.ply (vertex\n"
                       "and edge elements), one polyline per --paths-from vertex, from it\n"
                       "to the source")};
}

int run_exact_distance(const Args& args, const ResultOutput& out) {
  for (const char* heat :
       {"time-factor", "correction-steps", "mixed-precision", "curves", "sources-batch"}) {
    if (args.has(heat)) {
      throw UsageError(std::string("--exact does not take --") + heat +
                       " (a heat-method or batch option; --exact takes --source)");
    }
  }
  if (!args.has("source")) throw UsageError("--exact needs --source I[,J,...] (see --help)");
  const std::vector<Index> sources = args.vertices("source");
  std::optional<solvers::SurfaceRefineOptions> refine;
  if (args.has("refine")) refine = refine_settings(args, 0.0, false);
  solvers::PrepareOptions prep = prepare_options(args);
  // exact on the input's own lengths: a margin only for zero-area faces unless asked (D-350)
  if (!args.has("mollify")) prep.mollify_relative_epsilon = intrinsic::kOwnLengthsMollifyEpsilon;
  prep.refine = refine;
  const bool want_paths = args.has("paths-from");
  // On the input's own faces (the paths need them; flips keep the distance and cost windows:
  // docs/decisions.md D-321); refinement flips regardless.
  prep.intrinsic_delaunay = false;
  const PreparedSurface s = solvers::prepare_surface(read_input(args.positional()[0], args), prep);
  intrinsic::ExactDistanceOptions o;
  o.max_memory_bytes = args.real_or("memory-budget", 0.0) * 1e9;  // 0: the library's default
  o.keep_paths = want_paths;
  const Stopwatch watch;
  intrinsic::ExactDistance full;
  const Eigen::VectorXd d = solvers::exact_distance(s, sources, o, &full);
  const double seconds = watch.seconds();
  progress(args, "exact distance: " + std::to_string(full.windows) + " windows, " +
                     std::to_string(full.pseudo_sources) + " pseudo-sources, " +
                     format_number(seconds) + " s");
  std::vector<std::vector<Eigen::Vector3d>> paths;
  if (want_paths) paths = solvers::exact_paths_3d(s, full, args.vertices("paths-from"));
  const auto iso = isolines_if_asked(args, s.input, d, "distance");
  write_results(out, s, {{"distance", d}});
  if (iso) write_isolines(*iso);
  if (want_paths) {
    const std::string file = args.get("paths-out");
    write_polylines(file, paths, {}, "exact geodesics back to the nearest source (ifem distance)");
    std::printf("wrote %s: %d paths\n", file.c_str(), int(paths.size()));
  }
  Index unreachable = 0;
  double dmax = 0.0;
  for (Index v = 0; v < d.size(); ++v) {
    if (std::isfinite(d[v])) {
      dmax = std::max(dmax, d[v]);
    } else {
      ++unreachable;
    }
  }
  std::printf("wrote %s: %d values, max distance %.17g, %d unreachable (inf)\n", out.path.c_str(),
              int(d.size()), dmax, unreachable);
  return 0;
}

}  // namespace ifem::cli
