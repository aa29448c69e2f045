// `ifem geodesic`: geodesic paths, loops, curve networks and Bézier curves by FlipOut (edge
// flips on a signpost intrinsic triangulation), traced over the input surface; or the lengths
// of single-source geodesics to every vertex. The recipe is the library's
// (solvers/recipes/geodesic.h); this file reads the arguments and writes the results.
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <sstream>
#include <string>
#include <utility>
#include <vector>

#include "cli.h"
#include "intrinsic/core/errors.h"
#include "intrinsic/io/detail.h"
#include "intrinsic/refine/common_subdivision.h"
#include "polylines.h"
#include "results.h"
#include "solvers/recipes/geodesic.h"
#include "solvers/recipes/text_formats.h"

namespace ifem::cli {
namespace {

using recipes::GeodesicCurve;
using recipes::GivenCurve;
using recipes::GivenPoint;

// --path P0,P1[,...] as one curve (checked before the mesh is read).
GivenCurve path_option(const Args& args) {
  GivenCurve c;
  c.origin = "--path";
  c.closed = args.has("loop");
  c.pin = !c.closed || args.has("pin");
  const std::string given = args.get("path");
  for (const std::string& token : recipes::split_fields(given, ',')) {
    GivenPoint p;
    const std::string problem = recipes::parse_point_token(token, p);
    if (!problem.empty()) throw UsageError("--path '" + given + "': " + problem);
    c.points.push_back(p);
  }
  if (c.points.size() < 2) {
    throw UsageError("--path '" + given + "': needs at least two points (comma separated)");
  }
  const std::string repeated = recipes::repeated_point(c);
  if (!repeated.empty()) throw UsageError("--path '" + given + "': " + repeated);
  return c;
}

// --path's points name vertices / faces of the input: a usage error (exit 2) when not.
void check_path_points(const GivenCurve& c, const io::SurfaceInput& in) {
  for (const GivenPoint& p : c.points) {
    const std::string problem = recipes::point_problem(p, in);
    if (!problem.empty()) throw UsageError("--path " + problem);
  }
}

std::string curve_label(const GivenCurve& c, bool from_file) {
  return std::string(c.closed ? "loop" : "path") + " through " + std::to_string(c.points.size()) +
         " points" + (c.closed && c.pin ? ", pinned" : "") +
         (from_file ? " (" + c.origin + ")" : "");
}

// One curve per `l` line; a loop's repeated end point is its first index again.
std::string curves_obj(const std::vector<GeodesicCurve>& curves) {
  std::vector<Polyline> lines;
  std::vector<char> closed;
  for (const GeodesicCurve& c : curves) {
    lines.push_back(c.polyline);
    closed.push_back(c.closed);
  }
  return polylines_obj(lines, closed,
                       "ifem geodesic: " + std::to_string(curves.size()) + " curves");
}

// One `x y z` line per point, an empty line between curves.
std::string curves_txt(const std::vector<GeodesicCurve>& curves) {
  std::string out;
  bool first = true;
  for (const GeodesicCurve& c : curves) {
    if (c.polyline.empty()) continue;
    if (!first) out += '\n';
    first = false;
    for (const Eigen::Vector3d& x : c.polyline) {
      for (int d = 0; d < 3; ++d) {
        if (d > 0) out += ' ';
        io::detail::append_double(out, x[d]);
      }
      out += '\n';
    }
  }
  return out;
}

// Atomic in every format (path.tmp, then rename): no partial file on an error.
void write_curves(const std::string& path, const std::vector<GeodesicCurve>& curves) {
  const std::string ext = io::file_extension(path);
  if (ext == ".ply") {
    std::vector<Polyline> lines;
    for (const GeodesicCurve& c : curves) {
      if (c.polyline.size() >= 2) lines.push_back(c.polyline);
    }
    intrinsic::write_polylines_ply(path, lines, false,
                                   "geodesic curves on the input surface (ifem geodesic)");
  } else {
    io::detail::write_file_atomically(path,
                                      ext == ".obj" ? curves_obj(curves) : curves_txt(curves));
  }
}

std::string format_point(const Eigen::Vector3d& x) {
  char buf[96];
  std::snprintf(buf, sizeof buf, "(%.9g %.9g %.9g)", x[0], x[1], x[2]);
  return buf;
}

// The inserted face points, then per curve its lengths, then what FlipOut did.
void print_curves(const recipes::GeodesicCurves& run, const std::vector<GivenCurve>& specs,
                  bool from_file, int bezier_rounds) {
  for (const recipes::InsertedPoint& p : run.inserted) {
    const std::string token = p.token.substr(1, p.token.size() - 2);  // without the quotes
    std::printf("%s %s as vertex %d at %s\n", p.snapped ? "snapped" : "inserted", token.c_str(),
                p.vertex, format_point(p.position).c_str());
  }
  if (bezier_rounds >= 0) {
    std::printf(
        "Bézier: %d control points after %d rounds of de Casteljau subdivision, %d "
        "midpoints inserted\n",
        run.bezier_control_points, bezier_rounds, run.bezier_midpoints);
  }
  for (std::size_t c = 0; c < run.curves.size(); ++c) {
    const GeodesicCurve& r = run.curves[c];
    const std::string label = bezier_rounds >= 0
                                  ? "Bézier curve of degree " +
                                        std::to_string(specs[0].points.size() - 1) + ", " +
                                        std::to_string(bezier_rounds) + " rounds"
                                  : curve_label(specs[c], from_file);
    std::printf("curve %zu (%s): length %.12g -> %.12g, %zu points%s\n", c + 1, label.c_str(),
                r.initial_length, r.length, r.polyline.size(),
                r.collapsed
                    ? "; collapsed: a contractible loop shrank to a point or around one vertex"
                    : "");
  }
  if (run.tufted_cover) {
    std::printf(
        "exact distance on the tufted cover (nonmanifold mesh, no FlipOut): %zu windows, "
        "%.3g s\n",
        run.windows, run.seconds_flipout);
    return;
  }
  const intrinsic::FlipOutReport& rep = run.report;
  std::printf("FlipOut: %d flips, %d iterations, stopped: %s", rep.flips, rep.iterations,
              intrinsic::to_string(rep.stopped_by));
  if (rep.blocked_joints > 0) std::printf(" (%d bent joints left)", rep.blocked_joints);
  std::printf(", %.3g s\n", run.seconds_flipout);
}

// --start as the library's enum. @throws UsageError
intrinsic::StartPath start_path(const Args& args) {
  if (!args.has("start")) return intrinsic::StartPath::kBest;
  try {
    return intrinsic::start_path_from(args.get("start"));
  } catch (const InvalidInput& e) {
    throw UsageError(std::string("--start ") + e.what());
  }
}

void check_modes(const Args& args) {
  (void)start_path(args);  // a bad --start is refused before the mesh is read
  const int modes = args.has("path") + args.has("network") + args.has("all-from");
  if (modes != 1) {
    throw UsageError("give exactly one of --path, --network, --all-from (see --help)");
  }
  if (args.has("loop") && !args.has("path")) {
    throw UsageError("--loop closes the --path curve (in a --network file, write 'loop' lines)");
  }
  if (args.has("bezier") && (!args.has("path") || args.has("loop"))) {
    throw UsageError("--bezier takes --path's points as control points of an open curve");
  }
  if (args.has("pin") && !args.has("loop") && !args.has("network")) {
    throw UsageError("--pin keeps a loop's points (--loop, or the loop lines of --network)");
  }
  if (args.has("single-source-flipout") && !args.has("all-from")) {
    throw UsageError("--single-source-flipout goes with --all-from");
  }
  const bool txt_or_ply = io::file_extension(args.get("output")) != ".obj";
  if (args.has("all-from") && !txt_or_ply) {
    throw UsageError("--output '" + args.get("output") +
                     "': --all-from writes one length per vertex, to a .ply or .txt");
  }
}

recipes::GeodesicOptions geodesic_options_of(const Args& args) {
  recipes::GeodesicOptions o;
  o.mollify_relative_epsilon = args.real("mollify");
  o.start = start_path(args);
  if (args.has("bezier")) o.bezier_rounds = static_cast<int>(args.count("bezier"));
  o.flipout.max_iterations = args.count_or("max-iterations", -1);
  o.accept_partial = args.has("accept-partial");
  o.max_memory_bytes = args.real_or("memory-budget", 0.0) * 1e9;
  o.single_source_flipout = args.has("single-source-flipout");
  o.on_progress = progress_bar(args);
  return o;
}

// --all-from S: single-source geodesic lengths, one per input vertex.
int run_all_from(const Args& args, const io::SurfaceInput& in, const ResultOutput& out) {
  const Index source = args.count("all-from");
  const recipes::SingleSourceResult g = recipes::geodesic(in, source, geodesic_options_of(args));
  const Index nv = static_cast<Index>(g.length.size());
  Index unreachable = 0;
  double longest = 0.0;
  for (Index v = 0; v < nv; ++v) {
    if (std::isfinite(g.length[v])) {
      longest = std::max(longest, g.length[v]);
    } else {
      ++unreachable;
    }
  }
  if (g.exact) {
    std::printf("single-source geodesics from vertex %d: exact distance%s, %zu windows, %.3g s\n",
                source, g.tufted_cover ? " on the tufted cover (nonmanifold mesh)" : "", g.windows,
                g.seconds);
  } else {
    std::printf(
        "single-source geodesics from vertex %d: FlipOut, %d flips, %d iterations, %d paths left "
        "bent, %.3g s\n",
        source, g.flips, g.iterations, g.blocked, g.seconds);
  }
  write_results(out, in, {{"geodesic_length", g.length}});
  std::printf("wrote %s: %d values, max length %.9g, %d unreachable (inf)\n", out.path.c_str(), nv,
              longest, unreachable);
  return 0;
}

int run_geodesic(const Args& args) {
  const ResultOutput out = result_output(args);  // checked before any computation
  check_modes(args);
  std::vector<GivenCurve> specs;
  if (args.has("path")) specs.push_back(path_option(args));
  const io::SurfaceInput in = read_input(args.positional()[0], args);  // --all-from < #V
  if (args.has("all-from")) return run_all_from(args, in, out);
  if (args.has("network")) specs = recipes::read_network_file(args.get("network"), args.has("pin"));
  if (args.has("path")) check_path_points(specs[0], in);
  const recipes::GeodesicCurves run = recipes::geodesic(in, specs, geodesic_options_of(args));
  progress(args, std::string(run.tufted_cover ? "tufted cover" : "signpost triangulation") +
                     " in " + std::to_string(run.seconds_signposts) + " s");
  if (run.seconds_guide > 0.0) {
    progress(args,
             "start guide (exact or heat distance) in " + std::to_string(run.seconds_guide) + " s");
  }
  if (!run.start_won.empty()) progress(args, "start won: " + run.start_won);
  print_curves(run, specs, args.has("network"),
               args.has("bezier") ? static_cast<int>(args.count("bezier")) : -1);
  write_curves(out.path, run.curves);
  std::size_t points = 0;
  double length = 0.0;
  for (const GeodesicCurve& c : run.curves) {
    points += c.polyline.size();
    length += c.length;
  }
  std::printf("wrote %s: %zu curve%s, %zu points, length %.12g\n", out.path.c_str(),
              run.curves.size(), run.curves.size() == 1 ? "" : "s", points, length);
  return 0;
}

const char* const kGeodesicProse =
    "Geodesic curves on a triangle mesh by FlipOut (Sharp & Crane 2020, \"You Can Find\n"
    "Geodesic Paths in Triangle Meshes by Just Flipping Edges\"). A curve starts as a\n"
    "shortest path along mesh edges; wherever it bends by less than π, the intrinsic\n"
    "edges inside the bend are flipped until it can run straight across, so it ends\n"
    "up a geodesic: locally shortest, in the class of its start around the vertices\n"
    "(which side of each it passes). For a path between two points FlipOut therefore\n"
    "starts from several paths (--start) and keeps the shortest geodesic. The\n"
    "surface never changes: the curves are traced over the input and written as\n"
    "polylines of points on its faces.\n\n"
    "Points (P): a vertex id (0-based, the file's vertex order), or a point inside a\n"
    "face, face:F:u:v (F: 0-based face of the file; barycentric coordinates\n"
    "(1−u−v, u, v) for its corners in the file's order; u, v ≥ 0, u + v ≤ 1). Face\n"
    "points are inserted as vertices first and reported (id, position).\n\n"
    "A path between two points (--start best or guided) is never longer than the\n"
    "exact distance between them: where FlipOut's geodesic is (it can stay held\n"
    "at saddle vertices, with more than 2π of angle around them), the exact\n"
    "distance's shortest path is written instead and the progress line 'start\n"
    "won: exact path (...)' says so.\n\n"
    "Give exactly one of --path, --network, --all-from. FlipOut needs an\n"
    "edge-manifold, orientable triangle mesh (with or without boundary). On a\n"
    "nonmanifold or non-orientable mesh, --path A,B (two points) and --all-from S\n"
    "still run: exact shortest paths on the mesh's tufted cover (every face\n"
    "doubled, the copies glued around each edge: the surface `ifem distance\n"
    "--exact` measures; a path on it is a path on the mesh, of the same length;\n"
    "around an edge of 4+ faces it crosses only between neighbouring faces in\n"
    "their order about the edge); --loop, --network, --bezier, more than two\n"
    "points and --single-source-flipout are refused there (they need FlipOut's\n"
    "signposts). Point clouds are refused.\n";

const char* const kGeodesicEpilogue =
    "Network file (--network): one curve per line, 'path P0 P1 ...' (an open geodesic\n"
    "through the points, kept at each) or 'loop P0 P1 ...' (a closed one, free to\n"
    "move off its points unless --pin); points as above, whitespace separated; '#'\n"
    "starts a comment, blank lines are skipped. All curves are shortened together and\n"
    "never cross each other; they may share points.\n\n"
    "Output: stdout has each curve's length before (edge path) and after FlipOut,\n"
    "the flips, iterations, why it stopped and the time.\n\n"
    "examples:\n"
    "  ifem geodesic bunny.obj --path 0,500,1200 -o path.obj\n"
    "  ifem geodesic bunny.obj --path 0,1200 --start dijkstra -o fast.obj\n"
    "  ifem geodesic torus.obj --path 10,200,350 --loop -o loop.ply\n"
    "  ifem geodesic bunny.obj --path face:12:0.3:0.3,800,1500 --bezier 4 -o curve.txt\n"
    "  ifem geodesic bunny.obj --network curves.txt -o net.obj\n"
    "  ifem geodesic bunny.obj --all-from 0 -o lengths.ply\n"
    "  ifem geodesic conrod.obj --path 0,900 -o path.obj    (nonmanifold: tufted cover)\n";

// Long function: the option table (data: one entry per option, each with its help text).
OptionGroup geodesic_options() {
  return {"Options",
          {text("path", "P0,P1[,...]")
               .explain("the curve's points, in order (comma separated; see Points): a geodesic\n"
                        "through them, kept at every one (it may bend there)"),
           flag("loop").explain("with --path: a closed curve through the points, shortened freely\n"
                                "(the points only shape its start) unless --pin"),
           flag("pin").explain("loops keep passing through their points (--loop, network loops)"),
           count("bezier", "ROUNDS")
               .at_most(16)
               .explain("with --path: a geodesic Bézier curve with --path's points as control\n"
                        "points, ROUNDS rounds of de Casteljau subdivision (0: the geodesic\n"
                        "control polygon)"),
           text("network", "FILE").explain("curves from FILE (format below), shortened together"),
           vertex("all-from", "S")
               .limited_by(InputLimit::kBelowVertexCount)
               .explain("single-source geodesics: the shortest geodesic from vertex S to\n"
                        "every vertex, from the exact distance (as `ifem distance --exact`,\n"
                        "on the mesh's own faces: no flip; on a nonmanifold mesh, on its\n"
                        "tufted cover); their lengths, one per vertex.\n"
                        "Over --memory-budget, or with --single-source-flipout: Dijkstra\n"
                        "with FlipOut at the frontier, whose geodesics are locally shortest\n"
                        "(never below the exact distance, equal to it on 94-100% of the\n"
                        "vertices of the reference meshes; fewer on meshes of slivers)"),
           flag("single-source-flipout")
               .explain("with --all-from: build every geodesic by FlipOut instead of the\n"
                        "exact distance (slower; edge paths of the intrinsic triangulation;\n"
                        "refused on nonmanifold and non-orientable meshes: no signposts)"),
           text("output", "OUT")
               .short_alias('o')
               .mandatory()
               .with_extensions({".obj", ".ply", ".txt"})
               .explain("curves: OUT.obj ('v' lines, one 'l' line per curve; a loop repeats\n"
                        "its first point), OUT.ply (ASCII: vertices + 'edge' elements), OUT.txt\n"
                        "(one 'x y z' a line, an empty line between curves). --all-from:\n"
                        "OUT.ply (the mesh, vertex property 'geodesic_length') or OUT.txt (one\n"
                        "length a line, input vertex order; 'inf' where unreachable)"),
           text("start", "S")
               .defaults_to("best")
               .explain("FlipOut's start paths. best: for a path between two points, the\n"
                        "exact distance to each end (as `ifem distance --exact`) and six\n"
                        "edge paths along the faces the exact geodesic crosses (three to\n"
                        "the end, three to the start reversed), each shortened and then\n"
                        "moved over the vertices beside it while that shortens it, until\n"
                        "one reaches the exact length; if none does, the shortest edge\n"
                        "path and six paths down the exact distance too. The shortest\n"
                        "geodesic wins and a progress line names its start. When the exact\n"
                        "distance exceeds the memory budget, the six paths follow a heat\n"
                        "distance's descent instead. Cost: the exact distance to the end\n"
                        "(it dominates; the one to the start only when the first path\n"
                        "falls short) plus usually one such search, each tried on the one\n"
                        "triangulation and undone (no copies). guided: the same without\n"
                        "the shortest edge path. dijkstra: the shortest edge path, one\n"
                        "FlipOut (fastest; the result may go round a vertex the wrong\n"
                        "way). Other curves\n"
                        "(several points, loops, networks, --bezier) always start from\n"
                        "shortest edge paths"),
           real("mollify", "F")
               .at_least(0)
               .at_most(1)
               .defaults_to(format_number(intrinsic::kOwnLengthsMollifyEpsilon))
               .explain("relative mollification margin (the input's own lengths, as --exact)"),
           count("max-iterations", "N")
               .explain("FlipOut's cap on reroutes, all curves together (default\n"
                        "10 × edges + 1000). Curves that reach it are not geodesic yet: an\n"
                        "error (exit 1, nothing written, stating what was reached) unless\n"
                        "--accept-partial"),
           flag("accept-partial")
               .explain("write curves that stopped at --max-iterations as they are (not\n"
                        "geodesic; stdout says 'stopped: iteration cap')"),
           real("memory-budget", "GB")
               .above(0)
               .explain("--all-from: the exact distance's windows waiting at once (64 bytes\n"
                        "each; over it, FlipOut, or on a nonmanifold mesh a refusal with the\n"
                        "figures). --path A,B on a nonmanifold mesh: all its windows (the\n"
                        "path is traced back through them). --bezier: refuse a curve whose added\n"
                        "vertices (estimated up front: d(d+1)/2 · (2^R − 1) for degree d, R\n"
                        "rounds; 4 KiB each) exceed GB gigabytes (default: half the physical\n"
                        "memory, or 80% of ulimit -v). Rounds whose segments fall below 1/16\n"
                        "of the mean edge length are refused too, naming the most rounds that fit"),
           flag("quiet").explain(
               "no progress lines and no progress bar on stderr (the bar is drawn\nonly when "
               "stderr is a terminal, once the command has run 2 s)")}};
}

}  // namespace

Command geodesic_command() {
  Command c;
  c.summary = "geodesic paths, loops, networks, Bézier curves (FlipOut); single-source";
  c.spec.name = "geodesic";
  c.spec.positionals = {"MESH"};
  c.spec.prose = kGeodesicProse;
  c.spec.groups = {geodesic_options()};
  c.spec.epilogue = kGeodesicEpilogue;
  c.run = run_geodesic;
  return c;
}

}  // namespace ifem::cli
