// `ifem isolines`: the level sets of a per-vertex field (a PLY property or a values file, as the
// other commands write them) as polylines on the input surface; and the --isolines options of
// the commands that compute a field.
#include "cli_isolines.h"

#include <cerrno>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <string>
#include <vector>

#include "intrinsic/core/errors.h"
#include "intrinsic/core/timer.h"
#include "intrinsic/io/detail.h"
#include "intrinsic/io/mesh_io.h"
#include "polylines.h"
#include "solvers/recipes/text_formats.h"

namespace ifem::cli {
namespace {

std::string plural(std::size_t n, const std::string& word) {
  return std::to_string(n) + " " + word + (n == 1 ? "" : "s");
}

IsolineOutput make_output(const std::string& path, std::vector<recipes::Isoline> lines,
                          std::size_t n_levels, const std::string& title) {
  IsolineOutput out;
  out.path = path;
  out.lines = std::move(lines);
  out.n_levels = n_levels;
  out.title = title;
  return out;
}

// The input's faces, or the refusal of a point cloud.
void check_faces(const io::SurfaceInput& input, const std::string& what) {
  if (!input.has_faces()) {
    throw InvalidInput(what + ": isolines need a mesh with faces (the input is a point cloud)");
  }
}

// --values a,b,c: each a finite number (its range is checked against the field's later).
std::vector<double> parse_values(const std::string& given) {
  std::vector<double> values;
  for (const std::string& token : recipes::split_fields(given, ',')) {
    char* end = nullptr;
    errno = 0;
    const double v = token.empty() ? NAN : std::strtod(token.c_str(), &end);
    if (token.empty() || *end != '\0' || errno == ERANGE || !std::isfinite(v)) {
      throw UsageError("--values '" + given + "': '" + token + "' is not a finite number");
    }
    values.push_back(v);
  }
  return values;
}

// FIELD: a .txt of one value per line, or the property `--property` (or the only one) of a PLY.
Eigen::VectorXd read_field(const Args& args, Index nv) {
  const std::string file = args.positional()[1];
  Eigen::VectorXd f;
  if (io::file_extension(file) == ".txt") {
    if (args.has("property")) {
      throw UsageError("--property: " + file + " is a values file (one value per line), it has " +
                       "no named properties");
    }
    f = io::read_values(file);
  } else {
    const io::SurfaceInput in = io::read_surface(file);
    std::string names;
    for (const io::VertexProperty& p : in.vertex_properties) names += " " + p.name;
    if (names.empty()) names = " (none)";
    if (!args.has("property") && in.vertex_properties.size() != 1) {
      throw UsageError(file + " has several per-vertex properties: choose one with --property" +
                       " NAME (it has:" + names + ")");
    }
    const std::string name = args.has("property") ? args.get("property") : "";
    for (const io::VertexProperty& p : in.vertex_properties) {
      if (name.empty() || p.name == name) f = p.values;
    }
    if (f.size() == 0 && !name.empty()) {
      throw InvalidInput(file + ": no per-vertex property '" + name + "' (it has:" + names + ")");
    }
  }
  if (f.size() != nv) {
    throw InvalidInput(file + ": " + std::to_string(f.size()) + " values, the mesh has " +
                       std::to_string(nv) + " vertices");
  }
  return f;
}

int run_isolines(const Args& args) {
  const std::string path = args.get("output");
  if (args.has("values") == args.has("count")) {
    throw UsageError("give exactly one of --values c1,c2,... and --count N (see --help)");
  }
  const std::vector<double> given =
      args.has("values") ? parse_values(args.get("values")) : std::vector<double>{};
  const io::SurfaceInput input = read_input(args.positional()[0], args);
  check_faces(input, args.positional()[0]);
  const Eigen::VectorXd f = read_field(args, Index(input.positions.rows()));
  const std::vector<double> levels =
      args.has("count") ? recipes::isoline_levels(f, args.count("count")) : given;
  const Stopwatch watch;
  std::vector<recipes::Isoline> lines =
      recipes::isolines(input.positions, input.triangles, f, levels);
  progress(args, "isolines: " + plural(levels.size(), "level") + " in " +
                     format_number(watch.seconds()) + " s");
  const IsolineOutput out = make_output(path, std::move(lines), levels.size(),
                                        "ifem isolines of " + args.positional()[1]);
  if (args.has("points")) {
    std::string text = "# isoline value face b0 b1 b2 x y z (one line per point)\n";
    for (std::size_t i = 0; i < out.lines.size(); ++i) {
      for (const recipes::IsolinePoint& p : out.lines[i].points) {
        text += std::to_string(i) + ' ';
        io::detail::append_double(text, out.lines[i].value);
        text += ' ' + std::to_string(p.face);
        for (int k = 0; k < 3; ++k) (text += ' '), io::detail::append_double(text, p.bary[k]);
        for (int k = 0; k < 3; ++k) (text += ' '), io::detail::append_double(text, p.position[k]);
        text += '\n';
      }
    }
    io::detail::write_file_atomically(args.get("points"), text);
  }
  write_isolines(out);
  return 0;
}

const char* const kIsolinesProse =
    "The level sets {f = c} of a per-vertex field f as polylines on the surface\n"
    "(marching triangles): f is linear on each triangle of MESH, every point of a\n"
    "curve lies on an input edge where f crosses c (f interpolated there is c), and\n"
    "the pieces are chained into polylines; a curve that comes back to its start is\n"
    "written closed. FIELD is any command's per-vertex output on the same mesh: a PLY\n"
    "(distance, poisson, eigen, ...; --property picks the property) or a .txt of one\n"
    "value per line. Vertices with a non-finite value (the inf of unreachable\n"
    "vertices) cut no curve.\n\n"
    "A vertex exactly at c counts as above c: a curve through it passes through the\n"
    "vertex once (no duplicate point, no gap); a plateau at c gives its rim only.\n"
    "Curves end on the mesh boundary or where the level set branches (a saddle\n"
    "exactly at c).\n";

const char* const kIsolinesEpilogue =
    "\nexamples: ifem distance bunny.obj --source 0 -o d.ply\n"
    "          ifem isolines bunny.obj d.ply --property distance --count 10 -o iso.obj\n"
    "          ifem isolines bunny.obj d.ply --values 0.05,0.1 -o iso.ply --points p.txt\n"
    "          ifem view bunny.obj --field d.ply --curves iso.obj -o bunny.html\n"
    "or in one run: ifem distance bunny.obj --source 0 --isolines 10 --isolines-out iso.obj "
    "-o d.ply\n";

}  // namespace

std::vector<OptionSpec> isoline_options(const std::string& field) {
  return {count("isolines", "N")
              .at_least(1)
              .explain("also the isolines of '" + field +
                       "' at N levels evenly spaced inside its\n"
                       "range (as ifem isolines --count N), written to --isolines-out"),
          text("isolines-out", "ISO")
              .with_extensions({".obj", ".ply"})
              .explain("the isolines' file: ISO.obj ('l' lines, loops closed) or ISO.ply\n"
                       "(vertex and edge elements)")};
}

void check_isoline_options(const Args& args) {
  if (args.has("isolines") != args.has("isolines-out")) {
    throw UsageError(
        "--isolines N and --isolines-out FILE go together (the levels and their file)");
  }
}

std::optional<IsolineOutput> isolines_if_asked(const Args& args, const io::SurfaceInput& input,
                                               const Eigen::VectorXd& f, const std::string& name) {
  if (!args.has("isolines")) return std::nullopt;
  check_faces(input, "--isolines");
  const Eigen::VectorXd fi = f.head(input.positions.rows());
  const std::vector<double> levels = recipes::isoline_levels(fi, args.count("isolines"));
  return make_output(args.get("isolines-out"),
                     recipes::isolines(input.positions, input.triangles, fi, levels), levels.size(),
                     "ifem isolines of " + name);
}

void write_isolines(const IsolineOutput& out) {
  std::vector<Polyline> polylines;
  std::vector<char> closed;
  std::size_t n_closed = 0, n_points = 0;
  for (const recipes::Isoline& l : out.lines) {
    Polyline p;
    for (const recipes::IsolinePoint& q : l.points) p.push_back(q.position);
    if (l.closed) p.push_back(l.points.front().position);  // the writers' closed form
    polylines.push_back(std::move(p));
    closed.push_back(l.closed ? 1 : 0);
    n_closed += l.closed;
    n_points += l.points.size();
  }
  write_polylines(out.path, polylines, closed, out.title);
  std::printf("wrote %s: %s (%zu closed) at %s, %s\n", out.path.c_str(),
              plural(out.lines.size(), "isoline").c_str(), n_closed,
              plural(out.n_levels, "level").c_str(), plural(n_points, "point").c_str());
}

Command isolines_command() {
  Command c;
  c.summary = "isolines of a per-vertex field as polylines on the surface";
  c.spec.name = "isolines";
  c.spec.positionals = {"MESH", "FIELD"};
  c.spec.prose = kIsolinesProse;
  c.spec.groups = {
      {"Options",
       {text("output", "OUT")
            .short_alias('o')
            .mandatory()
            .with_extensions({".obj", ".ply"})
            .explain("OUT.obj: 'v' and 'l' lines, a loop's 'l' line ends at its first\n"
                     "point (ifem view --curves shows it); OUT.ply: a line set (vertex\n"
                     "and edge elements; a loop repeats its first point)"),
        text("property", "NAME")
            .explain("the per-vertex property of FIELD.ply (default: its only one)"),
        text("values", "C1,C2,...").explain("the levels, each within the field's range"),
        count("count", "N")
            .at_least(1)
            .explain("N levels evenly spaced strictly inside the field's range\n"
                     "(min + i·(max − min)/(N + 1), i = 1..N; finite values only)"),
        text("points", "FILE.txt")
            .with_extensions({".txt"})
            .explain("also every point as a surface point, one line each:\n"
                     "'isoline value face b0 b1 b2 x y z' (face: 0-based triangle of MESH,\n"
                     "b: barycentric coordinates for its corners; isoline: 0-based, in\n"
                     "OUT's order)"),
        flag("quiet").explain("no progress lines on stderr")}}};
  c.spec.epilogue = kIsolinesEpilogue;
  c.run = run_isolines;
  return c;
}

}  // namespace ifem::cli
