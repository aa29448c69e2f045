// `ifem poisson`: L u = M f with Dirichlet values on chosen vertices, or on curves (--curves).
#include <cmath>
#include <cstdio>
#include <fstream>
#include <optional>
#include <utility>

#include "cli.h"
#include "cli_curves.h"
#include "cli_isolines.h"
#include "cli_refine.h"
#include "cli_solver.h"
#include "intrinsic/core/errors.h"
#include "intrinsic/core/timer.h"
#include "intrinsic/io/tokens.h"
#include "results.h"
#include "solvers/recipes/curves.h"
#include "solvers/recipes/text_formats.h"
#include "solvers/scalar/poisson.h"

namespace ifem::cli {
namespace {

// --rhs: f on the input's vertices (default 0), every value finite.
Eigen::VectorXd read_rhs(const Args& args, Index nv) {
  Eigen::VectorXd f = Eigen::VectorXd::Zero(nv);
  if (!args.has("rhs")) return f;
  f = io::read_values(args.get("rhs"));
  if (f.size() != nv) {
    throw InvalidInput("--rhs " + args.get("rhs") + ": " + std::to_string(f.size()) +
                       " values, expected one per input vertex (" + std::to_string(nv) + ")");
  }
  for (Index v = 0; v < nv; ++v) {
    if (!std::isfinite(f[v])) {
      throw IoError("--rhs " + args.get("rhs") + ": value " + std::to_string(v + 1) + " (vertex " +
                    std::to_string(v) + ") is " + format_number(f[v]) + ", not a finite number");
    }
  }
  return f;
}

// What both forms of the command read before any computation (so bad files fail fast): the
// mesh, f, the Dirichlet vertices and values, the refinement settings.
struct PoissonInputs {
  io::SurfaceInput input;
  Index nv = 0;
  Eigen::VectorXd f, g;
  std::vector<Index> dv;
  std::optional<solvers::SurfaceRefineOptions> refine;
};

PoissonInputs read_poisson_inputs(const Args& args) {
  PoissonInputs in;
  in.input = read_input(args.positional()[0], args);
  in.nv = static_cast<Index>(in.input.positions.rows());
  in.f = read_rhs(args, in.nv);
  if (args.has("dirichlet")) {
    recipes::DirichletValues d = recipes::read_dirichlet_file(args.get("dirichlet"), in.nv);
    in.dv = std::move(d.vertices);
    in.g = std::move(d.values);
  }
  if (args.has("refine")) in.refine = refine_settings(args, 0.0, true);
  return in;
}

// --curves: u held at the curves' values on a constrained triangulation (solvers/recipes/curves.h).
int run_poisson_curves(const Args& args, const ResultOutput& out) {
  std::vector<solvers::CurveCondition> curves = read_curves(args);  // fails fast, before the mesh
  PoissonInputs in = read_poisson_inputs(args);
  const Index nv = in.nv;
  CurveRun run{prepare_curves(std::move(in.input), std::move(curves), args, true, in.refine), {}};
  solvers::PoissonOptions opt;
  opt.screening = args.real("screening");
  opt.solver = solver_choice(args);
  const Stopwatch watch;
  const solvers::CurvePoissonResult r = solvers::curve_poisson(run.surface, in.f, in.dv, in.g, opt);
  progress(args, "solved in " + std::to_string(watch.seconds()) + " s: u held on " +
                     std::to_string(r.dirichlet_vertices) + " curve vertices; " +
                     std::to_string(r.conflicting_vertices) +
                     " conflicting vertices (values differ there: the mean is used); " +
                     std::to_string(r.slit_copies) +
                     " slit copies (vertices added by cutting slits open)");
  run.polylines = curve_polylines_if_asked(args, run.surface);
  const auto iso = isolines_if_asked(args, run.surface.surface.input, r.u, "u");
  write_curve_outputs(args, out, run, {{"u", r.u}});
  if (iso) write_isolines(*iso);
  std::printf("wrote %s: %d values, %zu curves, u in [%.6g, %.6g]\n", out.path.c_str(), nv,
              run.surface.curves.size(), nv > 0 ? r.u.minCoeff() : 0.0,
              nv > 0 ? r.u.maxCoeff() : 0.0);
  print_curves_written(args, run);
  return 0;
}

int run_poisson(const Args& args) {
  const ResultOutput out = result_output(args);  // checked before any computation
  check_curve_options(args, {});
  check_isoline_options(args);
  if (args.has("curves")) return run_poisson_curves(args, out);
  // refined (a correspondence needed): f is interpolated linearly onto the inserted vertices, which
  // lie on input faces; the Dirichlet vertices are input vertices, which keep their ids
  PoissonInputs in = read_poisson_inputs(args);
  const Index nv = in.nv;
  const std::vector<Index>& dv = in.dv;
  const PreparedSurface s = prepare_surface(std::move(in.input), args, in.refine);
  solvers::PoissonOptions opt;
  opt.screening = args.real("screening");
  opt.solver = solver_choice(args);
  const Stopwatch watch;
  const Eigen::VectorXd u = solvers::poisson(s, in.f, dv, in.g, opt);  // on the input's vertices
  progress(args, "solved in " + std::to_string(watch.seconds()) + " s");
  const auto iso = isolines_if_asked(args, s.input, u, "u");
  write_results(out, s, {{"u", u}});
  if (iso) write_isolines(*iso);
  std::printf("wrote %s: %d values, %zu Dirichlet vertices%s\n", out.path.c_str(), nv, dv.size(),
              dv.empty() && opt.screening == 0 ? " (none: zero-mean solution per component)" : "");
  return 0;
}

const char* const kPoissonProse =
    "Solves the Poisson problem −Δu = f, i.e. L u = M f (L the intrinsic Delaunay\n"
    "cotan Laplacian, PSD; M the lumped mass), or the screened problem\n"
    "(L + cM) u = M f, with u fixed on the Dirichlet vertices and natural (zero\n"
    "Neumann) conditions everywhere else, including on the mesh boundary.\n\n"
    "Without Dirichlet data (and c = 0) a connected component is pure Neumann: f is\n"
    "made compatible by removing its mass-weighted mean and the zero-mean solution is\n"
    "returned. Vertices used by no face get 0 (or their Dirichlet value).\n\n"
    "Data on curves (--curves FILE, format below; diffusion curves): u is held at\n"
    "given values along curves drawn through the mesh's vertices: geodesic paths and\n"
    "loops (FlipOut) or geodesic Bézier curves. They become edges of a constrained\n"
    "intrinsic Delaunay triangulation (never flipped, split but never crossed by\n"
    "--refine), and u takes the curves' values (linear in arc length between given\n"
    "values) on every vertex along them, also on vertices inserted on them. A slit\n"
    "cuts the surface open along its curve: u may jump across it, with its own\n"
    "values on each side. --rhs, --dirichlet and --screening work as without curves.\n"
    "Curves need an edge-manifold, orientable triangle mesh (with or without\n"
    "boundary); nonmanifold meshes and point clouds are refused.\n";

OptionGroup poisson_options() {
  OptionGroup g{
      "Options",
      {text("dirichlet", "FILE")
           .explain("lines 'vertex value' (0-based input vertex id, then a finite value);\n"
                    "'#' starts a comment; any other line is an error. Example:\n"
                    "    0 1.0\n"
                    "    57 -2.5"),
       text("rhs", "FILE")
           .explain("f, one value per line, one line per input vertex (default 0:\n"
                    "Laplace's equation)"),
       real("screening", "c").at_least(0).defaults_to("0").explain("the screening c"),
       solver_option(),
       text("output", "OUT")
           .short_alias('o')
           .mandatory()
           .with_extensions({".ply", ".txt"})
           .explain("OUT.ply (mesh + per-vertex property 'u') or OUT.txt (one value per\n"
                    "line), in the input's vertex order"),
       flag("refine").explain(
           "intrinsic Delaunay refinement first (options below): f is interpolated\n"
           "linearly onto inserted vertices, the Dirichlet vertices stay input\n"
           "vertices, u is reported on the input's vertices (manifold path only;\n"
           "with --curves: constrained, no --relax / --max-edge)")}};
  const std::vector<OptionSpec> curves = curve_options(
      "u = the curves' values on every vertex along them (Dirichlet data on\n"
      "curves; with --refine, on the vertices refinement puts on them too)");
  g.options.insert(g.options.end(), curves.begin(), curves.end());
  const std::vector<OptionSpec> iso = isoline_options("u");
  g.options.insert(g.options.end(), iso.begin(), iso.end());
  return g;
}

}  // namespace

Command poisson_command() {
  Command c;
  c.summary = "solve (L + cM) u = M f with Dirichlet values on any vertices or on curves";
  c.spec.name = "poisson";
  c.spec.positionals = {"MESH"};
  c.spec.prose = kPoissonProse;
  c.spec.groups = {poisson_options(), refine_options_group(0.0), surface_options()};
  c.spec.epilogue = curves_file_help(true) +
                    "\nexamples: ifem poisson disk.obj --dirichlet bc.txt -o u.ply\n"
                    "          ifem poisson bunny.obj --curves curves.txt --curves-out c.obj -o "
                    "u.ply\n";
  c.run = run_poisson;
  return c;
}

}  // namespace ifem::cli
