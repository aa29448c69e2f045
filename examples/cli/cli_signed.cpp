// `ifem distance --signed` (cli_signed.h).
#include "cli_signed.h"

#include <cmath>
#include <cstdio>
#include <optional>
#include <string>
#include <utility>

#include "cli_curves.h"
#include "cli_isolines.h"
#include "cli_refine.h"
#include "intrinsic/core/errors.h"
#include "intrinsic/core/timer.h"
#include "solvers/recipes/signed_distance.h"
#include "solvers/recipes/text_formats.h"

namespace ifem::cli {
namespace {

solvers::SignedDistanceOptions signed_settings(const Args& args) {
  solvers::SignedDistanceOptions o;
  if (args.has("time-factor")) o.time_factor = args.real("time-factor");
  if (args.has("level-set")) o.level_set = solvers::signed_level_set_from(args.get("level-set"));
  return o;
}

void report(const Args& args, const ResultOutput& out, const Eigen::VectorXd& d, double seconds,
            const solvers::SignedDistanceReport& rep) {
  progress(args, "signed heat method: t = " + format_number(rep.time_step) + ", " +
                     format_number(seconds) + " s" +
                     (rep.stages > 1 ? ", " + std::to_string(rep.stages) + " stages" : "") +
                     (rep.unresolved_vertices > 0 ? ", " + std::to_string(rep.unresolved_vertices) +
                                                        " vertices where the heat underflowed"
                                                  : ""));
  double lo = 0.0, hi = 0.0;
  Index unreached = 0;
  for (Eigen::Index v = 0; v < d.size(); ++v) {
    if (std::isnan(d[v])) {
      ++unreached;
      continue;
    }
    lo = std::min(lo, d[v]);
    hi = std::max(hi, d[v]);
  }
  std::printf("wrote %s: %d values in [%.6g, %.6g], %d unreached (nan)\n", out.path.c_str(),
              int(d.size()), lo, hi, int(unreached));
}

int run_signed_curves(const Args& args, const ResultOutput& out) {
  std::vector<solvers::CurveCondition> curves = read_curves(args);  // fails fast, before the mesh
  io::SurfaceInput input = read_input(args.positional()[0], args);
  std::optional<solvers::SurfaceRefineOptions> refine;
  if (args.has("refine"))
    refine = refine_settings(args, solvers::RefinedDistanceOptions{}.resolution, true);
  CurveRun run{prepare_curves(std::move(input), std::move(curves), args, false, refine), {}};
  const Stopwatch watch;
  solvers::SignedDistanceReport rep;
  const Eigen::VectorXd d = solvers::signed_distance(run.surface, signed_settings(args), &rep);
  const double seconds = watch.seconds();
  run.polylines = curve_polylines_if_asked(args, run.surface);
  const auto iso = isolines_if_asked(args, run.surface.surface.input, d, "signed_distance");
  write_curve_outputs(args, out, run, {{"signed_distance", d}});
  if (iso) write_isolines(*iso);
  report(args, out, d, seconds, rep);
  print_curves_written(args, run);
  return 0;
}

int run_signed_points(const Args& args, const ResultOutput& out) {
  // the file is read before the input (a malformed one fails fast)
  const std::vector<solvers::InputDirection> points =
      recipes::read_constraints_file(args.get("points"));
  const PreparedSurface s = prepare_surface(args.positional()[0], args, std::nullopt);
  const Stopwatch watch;
  solvers::SignedDistanceReport rep;
  const Eigen::VectorXd d = solvers::signed_distance(s, points, signed_settings(args), &rep);
  const double seconds = watch.seconds();
  const auto iso = isolines_if_asked(args, s.input, d, "signed_distance");
  write_results(out, s, {{"signed_distance", d}});
  if (iso) write_isolines(*iso);
  report(args, out, d, seconds, rep);
  return 0;
}

}  // namespace

std::vector<OptionSpec> signed_options() {
  return {
      flag("signed").explain("signed distance by the signed heat method, to --curves FILE or to\n"
                             "--points FILE (see \"Signed distance\" below); writes the property\n"
                             "'signed_distance'"),
      text("points", "FILE")
          .explain("with --signed: oriented points, 'VERTEX NX NY NZ' per line (an input\n"
                   "vertex and its normal, along the surface, to the positive side)"),
      text("level-set", "MODE")
          .defaults_to("zero-set")
          .explain("with --signed: 'zero-set' holds the value 0 on the curves' vertices\n"
                   "(or the points); 'mean' only makes its mean there 0, so the zero\n"
                   "level may move off a broken or noisy curve")};
}

std::string signed_help() {
  return "\nSigned distance (--signed; Feng & Crane 2024, \"A Heat Method for Generalized\n"
         "Signed Distance\"): the sources' normals are diffused by the vector heat method\n"
         "(one step (M + t·L∇) Y = Y₀), normalized to X = Y/|Y|, and L φ = div X gives φ,\n"
         "then φ = 0 on the sources (--level-set). The curves may be open, broken or have\n"
         "gaps: the diffused normals fill in, and the sign stays right around them.\n"
         "Sign: for curves, seen from the side the faces' normals point to and walking\n"
         "along the curve (its first vertex to its second), the right-hand side is\n"
         "positive and the left-hand side negative: a counter-clockwise loop is negative\n"
         "inside. Curves need an edge-manifold, orientable mesh (--refine allowed). For\n"
         "--points the side the normals point to is positive; points work on every input\n"
         "(manifold, nonmanifold through the tufted cover, point clouds), not refined.\n"
         "|φ| is the distance near the sources; far off, a smooth generalization of it.\n"
         "--time-factor m: t = m·h² (default 1; with --refine h is the target length ℓ);\n"
         "larger smooths over gaps and noise. Curve edges longer than h are split first.\n";
}

void check_signed_options(const Args& args) {
  if (!args.has("signed")) {
    for (const char* name : {"points", "level-set"}) {
      if (args.has(name)) {
        throw UsageError(std::string("--") + name + " needs --signed");
      }
    }
    return;
  }
  for (const char* name : {"source", "sources-batch", "correction-steps", "mixed-precision"}) {
    if (args.has(name)) {
      throw UsageError(std::string("--") + name +
                       " cannot be used with --signed (its sources are --curves or --points)");
    }
  }
  if (args.has("curves") == args.has("points")) {
    throw UsageError("--signed needs one of --curves FILE or --points FILE");
  }
  if (args.has("points") && args.has("refine")) {
    throw UsageError("--refine cannot be used with --points (frames come from the input's points)");
  }
  if (args.has("level-set")) {
    try {
      solvers::signed_level_set_from(args.get("level-set"));
    } catch (const InvalidInput& e) {
      throw UsageError(std::string("--level-set ") + e.what());
    }
  }
}

int run_signed(const Args& args, const ResultOutput& out) {
  return args.has("curves") ? run_signed_curves(args, out) : run_signed_points(args, out);
}

}  // namespace ifem::cli
