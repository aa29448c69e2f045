// `ifem geodesic`: geodesic paths, loops, curve networks and Bézier curves by FlipOut (edge
// flips on a signpost intrinsic triangulation), traced over the input surface; or the lengths
// of single-source geodesics to every vertex.
#include <algorithm>
#include <charconv>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <limits>
#include <map>
#include <sstream>
#include <string>
#include <tuple>
#include <utility>
#include <vector>

#include "cli.h"
#include "intrinsic/core/errors.h"
#include "intrinsic/core/geometry.h"
#include "intrinsic/core/timer.h"
#include "intrinsic/geodesic/flip_geodesic.h"
#include "intrinsic/geodesic/input_surface.h"
#include "intrinsic/io/detail.h"
#include "intrinsic/io/tokens.h"
#include "intrinsic/refine/common_subdivision.h"
#include "polylines.h"
#include "results.h"

namespace ifem::cli {
namespace {

using intrinsic::EdgePath;
using intrinsic::FlipOutReport;
using intrinsic::SignpostTriangulation;

// A point as the user names it: an input vertex, or a point of a face of the mesh file.
struct PointSpec {
  Index vertex = kInvalidIndex;  // input vertex id; kInvalidIndex for a face point
  Index face = kInvalidIndex;    // face of the file, 0-based
  double u = 0.0, v = 0.0;       // barycentric coordinates (1 − u − v, u, v) of its corners
  std::string token;             // as given, for messages
};

// One curve as the user asks for it, and where it was asked for (for messages).
struct CurveSpec {
  std::vector<PointSpec> points;
  bool closed = false;
  bool pin = true;    // keep every given point on the curve (open paths always do)
  std::string where;  // "--path" or "FILE:LINE"
  bool usage = true;  // a bad point is a command-line error (exit 2), not a file's (exit 1)
};

// A curve once shortened: its lengths and its trace over the input.
struct CurveResult {
  std::string label;  // "path through 3 points"
  double initial_length = 0.0;
  double final_length = 0.0;
  bool closed = false;
  bool collapsed = false;  // a loop that shrank to a point (or a self-edge around one vertex)
  Polyline polyline;       // a loop repeats its first point at the end
};

// What a curve command computed, everything before the output is written.
struct CurveRun {
  std::vector<CurveResult> curves;
  FlipOutReport report;
  std::string extra;  // a line about the curves' making (Bézier control points), or ""
};

using io::parse_whole_integer;
using io::parse_whole_real;

std::vector<std::string> split(const std::string& s, char sep) {
  std::vector<std::string> parts;
  std::string part;
  std::istringstream in(s);
  while (std::getline(in, part, sep)) parts.push_back(part);
  if (!s.empty() && s.back() == sep) parts.emplace_back();
  if (s.empty()) parts.emplace_back();
  return parts;
}

// face:F:u:v into p; "" on success, else what is wrong with it.
std::string parse_face_point(const std::string& token, PointSpec& p) {
  const std::vector<std::string> f = split(token, ':');
  long long face = 0;
  if (f.size() != 4 || !parse_whole_integer(f[1], face) || face < 0 ||
      face > std::numeric_limits<Index>::max() || !parse_whole_real(f[2], p.u) ||
      !parse_whole_real(f[3], p.v)) {
    return "'" + token +
           "' is not a face point: expected face:F:u:v (F a 0-based face index, u and v "
           "finite numbers)";
  }
  if (p.u < 0.0 || p.v < 0.0 || p.u + p.v > 1.0 + 1e-12) {
    return "'" + token +
           "': the barycentric coordinates (1 − u − v, u, v) must be ≥ 0 (u, v ≥ 0, u + v ≤ 1)";
  }
  p.face = static_cast<Index>(face);
  return "";
}

// One point token (a vertex id or face:F:u:v) into p; "" on success, else what is wrong.
std::string parse_point(const std::string& token, PointSpec& p) {
  p = PointSpec{};
  p.token = token;
  if (token.rfind("face:", 0) == 0) return parse_face_point(token, p);
  long long id = 0;
  if (!parse_whole_integer(token, id) || id < 0 || id > std::numeric_limits<Index>::max()) {
    return "'" + token + "' is not a point: expected a vertex id (an integer ≥ 0) or face:F:u:v";
  }
  p.vertex = static_cast<Index>(id);
  return "";
}

// "" when no two consecutive points of c (last and first of a loop too) are the same point,
// else which ones are.
std::string repeated_point(const CurveSpec& c) {
  const std::size_t n = c.points.size();
  for (std::size_t k = 0; k < (c.closed ? n : n - 1); ++k) {
    const PointSpec& a = c.points[k];
    const PointSpec& b = c.points[(k + 1) % n];
    if (a.vertex == b.vertex && a.face == b.face && a.u == b.u && a.v == b.v) {
      return "points " + std::to_string(k + 1) + " and " + std::to_string((k + 1) % n + 1) +
             " are the same point '" + a.token + "' (consecutive points must differ)";
    }
  }
  return "";
}

// --path P0,P1[,...] as one curve (checked before the mesh is read).
CurveSpec path_option(const Args& args) {
  CurveSpec c;
  c.where = "--path";
  c.closed = args.has("loop");
  c.pin = !c.closed || args.has("pin");
  const std::string given = args.get("path");
  for (const std::string& token : split(given, ',')) {
    PointSpec p;
    const std::string problem = parse_point(token, p);
    if (!problem.empty()) throw UsageError("--path '" + given + "': " + problem);
    c.points.push_back(p);
  }
  if (c.points.size() < 2) {
    throw UsageError("--path '" + given + "': needs at least two points (comma separated)");
  }
  const std::string repeated = repeated_point(c);
  if (!repeated.empty()) throw UsageError("--path '" + given + "': " + repeated);
  return c;
}

// The --network file: `path P0 P1 ...` / `loop P0 P1 ...` lines, '#' comments and blank lines
// skipped; anything else is an error at FILE:LINE.
std::vector<CurveSpec> read_network(const std::string& file, bool pin_loops) {
  std::ifstream in(file);
  if (!in) throw IoError(file + ": cannot open");
  std::vector<CurveSpec> curves;
  std::string line;
  for (long lineno = 1; std::getline(in, line); ++lineno) {
    const std::string where = file + ":" + std::to_string(lineno);
    const std::vector<std::string> tokens = io::line_tokens(line);
    if (tokens.empty()) continue;
    if ((tokens[0] != "path" && tokens[0] != "loop") || tokens.size() < 3) {
      throw IoError(where + ": expected 'path P0 P1 ...' or 'loop P0 P1 ...' (at least two " +
                    "points), got '" + line + "'");
    }
    CurveSpec c;
    c.where = where;
    c.usage = false;
    c.closed = tokens[0] == "loop";
    c.pin = !c.closed || pin_loops;
    for (std::size_t k = 1; k < tokens.size(); ++k) {
      PointSpec p;
      const std::string problem = parse_point(tokens[k], p);
      if (!problem.empty()) throw IoError(where + ": " + problem);
      c.points.push_back(p);
    }
    const std::string repeated = repeated_point(c);
    if (!repeated.empty()) throw IoError(where + ": " + repeated);
    curves.push_back(std::move(c));
  }
  if (curves.empty()) throw IoError(file + ": no curves (expected 'path ...' or 'loop ...' lines)");
  return curves;
}

// Every point names a vertex / face of the input (and face points a triangle mesh).
void check_points(const std::vector<CurveSpec>& curves, const io::SurfaceInput& in) {
  const Index nv = static_cast<Index>(in.positions.rows());
  const Index nf = static_cast<Index>(in.triangles.size());
  for (const CurveSpec& c : curves) {
    for (const PointSpec& p : c.points) {
      std::string problem;
      if (p.vertex != kInvalidIndex && p.vertex >= nv) {
        problem = "vertex " + std::to_string(p.vertex) + " out of range [0, " + std::to_string(nv) +
                  ") (the input has " + std::to_string(nv) + " vertices)";
      } else if (p.vertex == kInvalidIndex && in.n_non_triangles > 0) {
        problem = "'" + p.token + "': face points need a triangle mesh (the file has " +
                  std::to_string(in.n_non_triangles) + " faces with more than 3 corners)";
      } else if (p.vertex == kInvalidIndex && p.face >= nf) {
        problem = "'" + p.token + "': face " + std::to_string(p.face) + " out of range [0, " +
                  std::to_string(nf) + ") (the input has " + std::to_string(nf) + " faces)";
      }
      if (problem.empty()) continue;
      if (c.usage) throw UsageError(c.where + " " + problem);
      throw InvalidInput(c.where + ": " + problem);
    }
  }
}

// The signpost triangulation of the input (intrinsic::flipout_surface: refused without area or
// when not edge-manifold and orientable, with what FlipOut needs).
SignpostTriangulation build_signposts(const io::SurfaceInput& in, const Args& args) {
  if (!in.has_faces()) {
    throw InvalidInput("geodesic needs a triangle mesh (the input has no faces: a point cloud)");
  }
  return intrinsic::flipout_surface(in, args.real("mollify"));
}

// p (a face point) as a point of st.input().
intrinsic::SurfacePoint input_point(const SignpostTriangulation& st, const io::SurfaceInput& in,
                                    const std::vector<Index>& input_face, const PointSpec& p) {
  const Eigen::Vector3d w(std::max(0.0, 1.0 - p.u - p.v), p.u, p.v);
  return intrinsic::given_face_point(st, in.triangles, input_face, p.face, w, "'" + p.token + "'");
}

std::string format_point(const Eigen::Vector3d& x) {
  char buf[96];
  std::snprintf(buf, sizeof buf, "(%.9g %.9g %.9g)", x[0], x[1], x[2]);
  return buf;
}

// The intrinsic vertex ids of every curve's points: input vertices as given, face points
// inserted (all before any path is built; the same face point twice is one vertex), each
// inserted point reported on stdout.
std::vector<std::vector<Index>> insert_points(SignpostTriangulation& st, const io::SurfaceInput& in,
                                              const std::vector<CurveSpec>& curves) {
  const std::vector<Index> input_face = intrinsic::given_face_map(st, in.triangles.size());
  std::map<std::tuple<Index, double, double>, Index> inserted;
  std::vector<std::vector<Index>> ids(curves.size());
  for (std::size_t c = 0; c < curves.size(); ++c) {
    for (const PointSpec& p : curves[c].points) {
      if (p.vertex != kInvalidIndex) {
        ids[c].push_back(p.vertex);
        continue;
      }
      const auto key = std::make_tuple(p.face, p.u, p.v);
      auto it = inserted.find(key);
      if (it == inserted.end()) {
        const Index before = st.intrinsic().n_vertices();
        const Index v = intrinsic::insert_surface_point(st, input_point(st, in, input_face, p));
        it = inserted.emplace(key, v).first;
        std::printf("%s %s as vertex %d at %s\n", v >= before ? "inserted" : "snapped",
                    p.token.c_str(), v, format_point(st.position(st.vertex_location(v))).c_str());
      }
      ids[c].push_back(it->second);
    }
  }
  return ids;
}

std::string curve_label(const CurveSpec& c) {
  return std::string(c.closed ? "loop" : "path") + " through " + std::to_string(c.points.size()) +
         " points" + (c.closed && c.pin ? ", pinned" : "") + (c.usage ? "" : " (" + c.where + ")");
}

// Traces the shortened curves over the input (tracing flips nothing: any order is fine).
void trace_curves(const SignpostTriangulation& st, const std::vector<EdgePath>& paths,
                  CurveRun& run) {
  std::vector<char> collapsed(paths.size(), 0);
  for (const Index c : run.report.collapsed_loops) collapsed[c] = 1;
  for (std::size_t c = 0; c < paths.size(); ++c) {
    CurveResult& r = run.curves[c];
    r.closed = paths[c].closed;
    r.collapsed = collapsed[c] != 0;
    r.final_length = intrinsic::path_length(st.intrinsic(), paths[c]);
    if (!paths[c].steps.empty()) r.polyline = intrinsic::path_polyline(st, paths[c]);
  }
}

// --path / --loop / --network: the edge paths through the points, shortened together.
CurveRun shorten_curves(SignpostTriangulation& st, const std::vector<CurveSpec>& specs,
                        const std::vector<std::vector<Index>>& ids) {
  CurveRun run;
  std::vector<intrinsic::CurveThrough> curves;
  for (std::size_t c = 0; c < specs.size(); ++c) {
    curves.push_back({ids[c], specs[c].closed, specs[c].pin, specs[c].where});
  }
  std::vector<EdgePath> paths;
  std::vector<double> initial;
  run.report = intrinsic::shorten_through(st, curves, &paths, &initial);
  for (std::size_t c = 0; c < specs.size(); ++c) {
    CurveResult r;
    r.label = curve_label(specs[c]);
    r.initial_length = initial[c];
    run.curves.push_back(r);
  }
  trace_curves(st, paths, run);
  return run;
}

// --bezier ROUNDS: --path's points are the control points of one geodesic Bézier curve.
CurveRun bezier(SignpostTriangulation& st, const std::vector<Index>& control, int rounds) {
  intrinsic::BezierCurve b = intrinsic::bezier_curve(st, control, rounds);
  CurveRun run;
  run.report = b.report;
  CurveResult r;
  r.label = "Bézier curve of degree " + std::to_string(control.size() - 1) + ", " +
            std::to_string(rounds) + " rounds";
  r.initial_length = b.report.initial_length;
  run.curves.push_back(r);
  trace_curves(st, {b.path}, run);
  run.extra = "Bézier: " + std::to_string(b.controls.size()) + " control points after " +
              std::to_string(rounds) + " rounds of de Casteljau subdivision, " +
              std::to_string(b.inserted_vertices) + " midpoints inserted";
  return run;
}

// One curve per `l` line; a loop's repeated end point is its first index again.
std::string curves_obj(const std::vector<CurveResult>& curves) {
  std::vector<Polyline> lines;
  std::vector<char> closed;
  for (const CurveResult& c : curves) {
    lines.push_back(c.polyline);
    closed.push_back(c.closed);
  }
  return polylines_obj(lines, closed,
                       "ifem geodesic: " + std::to_string(curves.size()) + " curves");
}

// One `x y z` line per point, an empty line between curves.
std::string curves_txt(const std::vector<CurveResult>& curves) {
  std::string out;
  bool first = true;
  for (const CurveResult& c : curves) {
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
void write_curves(const std::string& path, const std::vector<CurveResult>& curves) {
  const std::string ext = io::file_extension(path);
  if (ext == ".ply") {
    std::vector<Polyline> lines;
    for (const CurveResult& c : curves) {
      if (c.polyline.size() >= 2) lines.push_back(c.polyline);
    }
    intrinsic::write_polylines_ply(path, lines, false,
                                   "geodesic curves on the input surface (ifem geodesic)");
  } else {
    io::detail::write_file_atomically(path,
                                      ext == ".obj" ? curves_obj(curves) : curves_txt(curves));
  }
}

// Per curve its lengths, then what FlipOut did; collapsed loops said so.
void print_curves(const CurveRun& run, double seconds) {
  if (!run.extra.empty()) std::printf("%s\n", run.extra.c_str());
  for (std::size_t c = 0; c < run.curves.size(); ++c) {
    const CurveResult& r = run.curves[c];
    std::printf("curve %zu (%s): length %.12g -> %.12g, %zu points%s\n", c + 1, r.label.c_str(),
                r.initial_length, r.final_length, r.polyline.size(),
                r.collapsed
                    ? "; collapsed: a contractible loop shrank to a point or around one vertex"
                    : "");
  }
  const FlipOutReport& rep = run.report;
  std::printf("FlipOut: %d flips, %d iterations, stopped: %s", rep.flips, rep.iterations,
              intrinsic::to_string(rep.stopped_by));
  if (rep.blocked_joints > 0) std::printf(" (%d bent joints left)", rep.blocked_joints);
  std::printf(", %.3g s\n", seconds);
}

void check_modes(const Args& args) {
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
  const bool txt_or_ply = io::file_extension(args.get("output")) != ".obj";
  if (args.has("all-from") && !txt_or_ply) {
    throw UsageError("--output '" + args.get("output") +
                     "': --all-from writes one length per vertex, to a .ply or .txt");
  }
}

// --all-from S: single-source geodesic lengths, one per input vertex.
int run_all_from(const Args& args, const io::SurfaceInput& in, const ResultOutput& out) {
  SignpostTriangulation st = build_signposts(in, args);
  const Index nv = static_cast<Index>(in.positions.rows());
  const Index source = args.count("all-from");
  const Stopwatch watch;
  const intrinsic::SingleSourceGeodesics g = intrinsic::single_source_geodesics(st, source);
  const double seconds = watch.seconds();
  Eigen::VectorXd length = g.length.head(nv);
  Index unreachable = 0;
  double longest = 0.0;
  for (Index v = 0; v < nv; ++v) {
    if (std::isfinite(length[v])) {
      longest = std::max(longest, length[v]);
    } else {
      ++unreachable;
    }
  }
  std::printf(
      "single-source geodesics from vertex %d: %d flips, %d iterations, %d paths left bent, "
      "%.3g s\n",
      source, g.flips, g.iterations, g.blocked, seconds);
  write_results(out, in, {{"geodesic_length", length}});
  std::printf("wrote %s: %d values, max length %.9g, %d unreachable (inf)\n", out.path.c_str(), nv,
              longest, unreachable);
  return 0;
}

int run(const Args& args) {
  const ResultOutput out = result_output(args);  // checked before any computation
  check_modes(args);
  std::vector<CurveSpec> specs;
  if (args.has("path")) specs.push_back(path_option(args));
  const io::SurfaceInput in = read_input(args.positional()[0], args);  // --all-from < #V
  if (args.has("all-from")) return run_all_from(args, in, out);
  if (args.has("network")) specs = read_network(args.get("network"), args.has("pin"));
  check_points(specs, in);
  Stopwatch watch;
  SignpostTriangulation st = build_signposts(in, args);
  progress(args, "signpost triangulation: " + std::to_string(st.intrinsic().n_faces()) +
                     " faces in " + std::to_string(watch.restart()) + " s");
  const std::vector<std::vector<Index>> ids = insert_points(st, in, specs);
  const CurveRun run = args.has("bezier") ? bezier(st, ids[0], args.count("bezier"))
                                          : shorten_curves(st, specs, ids);
  const double seconds = watch.seconds();
  print_curves(run, seconds);
  write_curves(out.path, run.curves);
  std::size_t points = 0;
  double length = 0.0;
  for (const CurveResult& c : run.curves) {
    points += c.polyline.size();
    length += c.final_length;
  }
  std::printf("wrote %s: %zu curve%s, %zu points, length %.12g\n", out.path.c_str(),
              run.curves.size(), run.curves.size() == 1 ? "" : "s", points, length);
  return 0;
}

const char* const kProse =
    "Geodesic curves on a triangle mesh by FlipOut (Sharp & Crane 2020, \"You Can Find\n"
    "Geodesic Paths in Triangle Meshes by Just Flipping Edges\"). A curve starts as a\n"
    "shortest path along mesh edges; wherever it bends by less than π, the intrinsic\n"
    "edges inside the bend are flipped until it can run straight across, so it ends\n"
    "up a geodesic (locally shortest; not always the globally shortest one). The\n"
    "surface never changes: the curves are traced over the input and written as\n"
    "polylines of points on its faces.\n\n"
    "Points (P): a vertex id (0-based, the file's vertex order), or a point inside a\n"
    "face, face:F:u:v (F: 0-based face of the file; barycentric coordinates\n"
    "(1−u−v, u, v) for its corners in the file's order; u, v ≥ 0, u + v ≤ 1). Face\n"
    "points are inserted as vertices first and reported (id, position).\n\n"
    "Give exactly one of --path, --network, --all-from. Needs an edge-manifold,\n"
    "orientable triangle mesh (with or without boundary); nonmanifold and\n"
    "non-orientable meshes and point clouds are refused.\n";

const char* const kEpilogue =
    "Network file (--network): one curve per line, 'path P0 P1 ...' (an open geodesic\n"
    "through the points, kept at each) or 'loop P0 P1 ...' (a closed one, free to\n"
    "move off its points unless --pin); points as above, whitespace separated; '#'\n"
    "starts a comment, blank lines are skipped. All curves are shortened together and\n"
    "never cross each other; they may share points.\n\n"
    "Output: stdout has each curve's length before (edge path) and after FlipOut,\n"
    "the flips, iterations, why it stopped and the time.\n\n"
    "examples:\n"
    "  ifem geodesic bunny.obj --path 0,500,1200 -o path.obj\n"
    "  ifem geodesic torus.obj --path 10,200,350 --loop -o loop.ply\n"
    "  ifem geodesic bunny.obj --path face:12:0.3:0.3,800,1500 --bezier 4 -o curve.txt\n"
    "  ifem geodesic bunny.obj --network curves.txt -o net.obj\n"
    "  ifem geodesic bunny.obj --all-from 0 -o lengths.ply\n";

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
               .explain("single-source geodesics: a geodesic from vertex S to every vertex\n"
                        "(Dijkstra with FlipOut at the frontier); their lengths, one per vertex"),
           text("output", "OUT")
               .short_alias('o')
               .mandatory()
               .with_extensions({".obj", ".ply", ".txt"})
               .explain("curves: OUT.obj ('v' lines, one 'l' line per curve; a loop repeats\n"
                        "its first point), OUT.ply (ASCII: vertices + 'edge' elements), OUT.txt\n"
                        "(one 'x y z' a line, an empty line between curves). --all-from:\n"
                        "OUT.ply (the mesh, vertex property 'geodesic_length') or OUT.txt (one\n"
                        "length a line, input vertex order; 'inf' where unreachable)"),
           real("mollify", "F")
               .at_least(0)
               .at_most(1)
               .defaults_to(format_number(intrinsic::kDefaultMollifyEpsilon))
               .explain("relative mollification margin (as other commands' --mollify)"),
           flag("quiet").explain("no progress lines on stderr")}};
}

}  // namespace

Command geodesic_command() {
  Command c;
  c.summary = "geodesic paths, loops, networks, Bézier curves; single-source (FlipOut)";
  c.spec.name = "geodesic";
  c.spec.positionals = {"MESH"};
  c.spec.prose = kProse;
  c.spec.groups = {geodesic_options()};
  c.spec.epilogue = kEpilogue;
  c.run = run;
  return c;
}

}  // namespace ifem::cli
