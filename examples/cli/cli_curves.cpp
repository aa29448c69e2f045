#include "cli_curves.h"

#include <cstdio>
#include <iterator>
#include <utility>

#include "intrinsic/core/errors.h"

namespace ifem::cli {

std::vector<OptionSpec> curve_options(const std::string& use) {
  return {text("curves", "FILE").explain(use + "\n(file format below)"),
          text("curves-out", "FILE.obj")
              .with_extensions({".obj"})
              .explain("with --curves: the curves as inserted, traced over the input surface\n"
                       "('v' lines, one 'l' line per curve, in the file's order; a closed\n"
                       "curve's 'l' line ends at its first point)"),
          count("max-iterations", "N")
              .explain("with --curves: FlipOut's cap on reroutes, all curves together\n"
                       "(default 10 × edges + 1000); curves that reach it are not geodesic\n"
                       "yet: an error (exit 1, stating what was reached) unless\n"
                       "--accept-partial"),
          flag("accept-partial")
              .explain("with --curves: go on with curves FlipOut left at its iteration cap\n"
                       "(--max-iterations; not geodesic yet; without it such curves are an\n"
                       "error, exit 1)"),
          flag("no-conform")
              .explain("with --curves --refine: keep curve and boundary edges whose cotan\n"
                       "weight is negative after refinement (by default they are split\n"
                       "until every weight is >= 0, so u stays within the curves' values)")};
}

std::string curves_file_help(bool values_used, const std::string& command) {
  std::string h =
      "Curves file (--curves FILE): one curve per line, through input vertices (0-based\n"
      "ids, the file's vertex order); '#' starts a comment, blank lines are skipped. A\n"
      "line is optional keywords (any order, each at most once), then its values, then\n"
      "its vertex ids:\n"
      "  [closed | bezier[=R]] [slit] VALUE v0 v1 ... vk          one value all along\n"
      "  [closed | bezier[=R]] [slit] A0 A1 ... Ak : v0 v1 ... vk  Ai at vi, linear in\n"
      "                                                            arc length between\n"
      "  (none)      an open geodesic through v0, v1, ..., vk in order (FlipOut, kept at\n"
      "              every vertex given; it may bend there)\n"
      "  closed      a closed geodesic loop through them, back to v0 (do not repeat v0;\n"
      "              per-vertex values close back to A0)\n"
      "  bezier[=R]  a geodesic Bézier curve with v0 ... vk as control points, R rounds\n"
      "              of de Casteljau subdivision (R in [0, 16], default 4); its values:\n"
      "              one, or two (at its two ends: A0 A1 : v0 ... vk). Degree d adds\n"
      "              up to d(d+1)/2 · (2^R − 1) vertices: refused up front (with the\n"
      "              most rounds that fit) over --memory-budget or when its segments\n"
      "              would fall below 1/16 of the mesh's mean edge length\n"
      "  slit        a cut: the surface is cut open along the curve and u may jump\n"
      "              across it. VALUE becomes LEFT RIGHT (two numbers) and the list form\n"
      "              LEFTS : RIGHTS : VERTICES (as many lefts as rights)\n"
      "At least 2 vertices, no vertex twice in a row; curves may meet and cross at\n"
      "vertices but not share an edge. Values are finite numbers.\n"
      "Left and right of a slit: walking along the curve from its first vertex to its\n"
      "second, the left-hand side as seen from the side the face normals point to (the\n"
      "side from which the faces' corners run counter-clockwise). An end of an open\n"
      "slit inside the surface is a single point: it takes the mean of the two sides'\n"
      "values there; so does a vertex where curves with different values meet (both\n"
      "counted as conflicting vertices).\n";
  if (!values_used) {
    h += command +
         " uses only where the curves run: every line still starts with its\n"
         "value(s) (so one file serves poisson, distance and field), and they are\n"
         "ignored. Mind that '12 40 77' is the value 12 on a curve through 40 and 77.\n";
  }
  h += "Examples (one curve a line):\n"
       "  0.5 12 40 77              # geodesic 12→40→77 held at 0.5\n"
       "  closed 1 5 9 13           # closed loop through 5, 9, 13, held at 1\n"
       "  bezier 0 3 8 20 31        # Bézier curve, control vertices 3 8 20 31, at 0\n"
       "  0 0.5 1 : 12 40 77        # 0 at 12, 0.5 at 40, 1 at 77, linear in arc length\n"
       "  slit 0 1 12 40 77         # a cut: 0 on its left, 1 on its right\n"
       "  slit 0 1 : 1 0 : 12 77    # a cut whose sides vary: left 0→1, right 1→0\n"
       "  bezier=6 0 1 : 3 8 20 31  # Bézier, 6 rounds, 0 at its start → 1 at its end\n";
  return h;
}

namespace {

// The shared options that make no sense with --curves, and why.
const CurveRefusal kCurveRefusals[] = {
    {"tufted", "curves need signposts, hence an edge-manifold, orientable mesh (no tufted cover)"},
    {"pointcloud", "curves run through the edges of a triangle mesh (no point clouds)"},
    {"knn", "curves run through the edges of a triangle mesh (no point clouds)"},
    {"no-delaunay",
     "the curves are inserted into the constrained intrinsic Delaunay triangulation"},
    {"relax", "relaxation is not offered with curves (refinement is: --refine)"},
    {"max-edge", "relaxation is not offered with curves (refinement is: --refine)"},
};

}  // namespace

void check_curve_options(const Args& args, const std::vector<CurveRefusal>& refused) {
  if (!args.has("curves")) {
    if (args.has("curves-out")) {
      throw UsageError("--curves-out writes the curves of --curves FILE, which was not given");
    }
    if (args.has("accept-partial")) {
      throw UsageError("--accept-partial accepts curves of --curves FILE, which was not given");
    }
    if (args.has("max-iterations")) {
      throw UsageError(
          "--max-iterations caps FlipOut on the curves of --curves FILE, which was "
          "not given");
    }
    if (args.has("no-conform")) {
      throw UsageError("--no-conform applies to --curves with --refine; --curves was not given");
    }
    return;
  }
  if (args.has("no-conform") && !args.has("refine")) {
    throw UsageError("--no-conform turns off a step of --refine, which was not given");
  }
  std::vector<CurveRefusal> all = refused;
  all.insert(all.end(), std::begin(kCurveRefusals), std::end(kCurveRefusals));
  for (const CurveRefusal& r : all) {
    if (args.has(r.option)) {
      throw UsageError("--" + r.option + " cannot be used with --curves: " + r.reason);
    }
  }
  if (args.has("curves-out")) result_output(args, "curves-out");  // the extension, up front
}

namespace {

// "3 paths, 1 closed curve, 1 Bézier curve; 2 slits"
std::string curve_counts(const std::vector<solvers::CurveCondition>& curves) {
  Index n[3] = {0, 0, 0}, slits = 0;
  for (const solvers::CurveCondition& c : curves) {
    ++n[static_cast<int>(c.shape)];
    slits += c.slit;
  }
  const char* names[3][2] = {
      {"path", "paths"}, {"closed curve", "closed curves"}, {"Bézier curve", "Bézier curves"}};
  std::string s;
  for (int k = 0; k < 3; ++k) {
    if (n[k] == 0) continue;
    s += (s.empty() ? "" : ", ") + std::to_string(n[k]) + " " + names[k][n[k] != 1];
  }
  if (slits > 0) s += "; " + std::to_string(slits) + (slits == 1 ? " slit" : " slits");
  return s;
}

// What the library's progress lines leave out: curve edges left non-Delaunay, negative weights.
void report_surface(const Args& args, const solvers::CurveSurface& s) {
  if (s.constrained_flips.unflippable > 0) {
    progress(args, std::to_string(s.constrained_flips.unflippable) +
                       " curve edges are not Delaunay (kept: they are constrained)");
  }
  if (s.signs.negative_unconstrained > 0 || s.signs.negative_constrained > 0) {
    progress(args, "negative cotan weights: " + std::to_string(s.signs.negative_constrained) +
                       " on curve edges, " + std::to_string(s.signs.negative_unconstrained) +
                       " elsewhere (min " + format_number(s.signs.min_weight) + ")");
  }
}

}  // namespace

std::vector<solvers::CurveCondition> read_curves(const Args& args) {
  std::vector<solvers::CurveCondition> curves = solvers::read_curves_file(args.get("curves"));
  progress(args, "read " + args.get("curves") + ": " + std::to_string(curves.size()) + " curve" +
                     (curves.size() == 1 ? "" : "s") + " (" + curve_counts(curves) + ")");
  return curves;
}

solvers::CurveSurface prepare_curves(io::SurfaceInput input,
                                     std::vector<solvers::CurveCondition> curves, const Args& args,
                                     bool need_values,
                                     const std::optional<solvers::SurfaceRefineOptions>& refine) {
  solvers::validate_curves(curves, static_cast<Index>(input.positions.rows()), need_values);
  solvers::CurveSurfaceOptions opt;
  opt.mollify_relative_epsilon = args.real("mollify");
  opt.refine = refine;
  opt.accept_partial = args.has("accept-partial");
  opt.flipout.max_iterations = args.count_or("max-iterations", -1);
  // the vertices Bézier curves add against --memory-budget (0: the library's default)
  opt.max_memory_bytes = args.real_or("memory-budget", 0.0) * 1e9;
  if (opt.refine && args.has("no-conform")) opt.refine->conform = false;
  if (!args.has("quiet")) {
    opt.progress = [](const std::string& line) {
      clear_progress_bar();
      std::fprintf(stderr, "ifem: %s\n", line.c_str());
    };
  }
  opt.on_progress = progress_bar(args);
  solvers::CurveSurface s =
      solvers::prepare_curve_surface(std::move(input), std::move(curves), opt);
  report_surface(args, s);
  return s;
}

std::vector<Polyline> curve_polylines_if_asked(const Args& args, const solvers::CurveSurface& s) {
  if (!args.has("curves-out")) return {};
  return solvers::curve_polylines(s);
}

void write_curve_outputs(const Args& args, const ResultOutput& out, const CurveRun& run,
                         const std::vector<io::VertexProperty>& properties) {
  write_curve_outputs(args, out, run, [&] { write_results(out, run.surface.surface, properties); });
}

void write_curve_outputs(const Args& args, const ResultOutput& out, const CurveRun& run,
                         const std::function<void()>& write) {
  write();
  if (!args.has("curves-out")) return;
  std::vector<char> closed;
  for (const solvers::CurveCondition& c : run.surface.curves) {
    closed.push_back(c.shape == intrinsic::CurveShape::kLoop);
  }
  try {
    write_polylines_obj(args.get("curves-out"), run.polylines, closed,
                        "ifem: " + std::to_string(run.polylines.size()) + " curves of " +
                            args.get("curves") + " on " + args.positional()[0]);
  } catch (...) {
    std::remove(out.path.c_str());  // both outputs or none
    throw;
  }
}

void print_curves_written(const Args& args, const CurveRun& run) {
  if (!args.has("curves-out")) return;
  std::size_t points = 0;
  for (const Polyline& p : run.polylines) points += p.size();
  std::printf("wrote %s: %zu curves, %zu points\n", args.get("curves-out").c_str(),
              run.polylines.size(), points);
}

}  // namespace ifem::cli
