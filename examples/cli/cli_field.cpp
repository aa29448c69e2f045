// `ifem field`: the smoothest n-direction field (vectors, lines, crosses), free or aligned to
// the boundary and to given directions, with its singularities.
#include <cstdio>
#include <fstream>
#include <sstream>
#include <string>

#include "cli.h"
#include "cli_refine.h"
#include "intrinsic/core/errors.h"
#include "intrinsic/core/timer.h"
#include "intrinsic/io/tokens.h"
#include "results.h"
#include "solvers/tangent_fields.h"

namespace ifem::cli {
namespace {

// Constraint lines 'VERTEX X Y Z' ('#' starts a comment).
std::vector<solvers::InputDirection> read_directions(const std::string& path) {
  std::ifstream in(path);
  if (!in) throw IoError(path + ": cannot open");
  std::vector<solvers::InputDirection> out;
  std::string line;
  for (int number = 1; std::getline(in, line); ++number) {
    const std::string body = line.substr(0, line.find('#'));
    std::istringstream words(body);
    std::vector<std::string> w;
    for (std::string t; words >> t;) w.push_back(t);
    if (w.empty()) continue;
    long long v = 0;
    solvers::InputDirection d;
    bool ok = w.size() == 4 && io::parse_whole_integer(w[0], v) && v >= 0 && v < (1LL << 31);
    for (int k = 0; ok && k < 3; ++k) ok = io::parse_whole_real(w[k + 1], d.direction[k]);
    if (!ok) {
      throw IoError(path + ":" + std::to_string(number) +
                    ": expected 'VERTEX X Y Z' (a vertex id ≥ 0 and a direction), got '" + body +
                    "'");
    }
    d.vertex = static_cast<Index>(v);
    out.push_back(d);
  }
  return out;
}

int run(const Args& args) {
  const ResultOutput out = result_output(args);
  solvers::FieldSettings settings;
  settings.symmetry = static_cast<int>(args.count("symmetry"));
  settings.align_boundary = args.has("align-boundary");
  if (args.has("constraints")) settings.constraints = read_directions(args.get("constraints"));
  std::optional<solvers::RefineSettings> refine;
  if (args.has("refine")) refine = refine_settings(args, 0.0, false);
  const PreparedSurface s = prepare_surface(args.positional()[0], args, refine);
  const Stopwatch watch;
  const solvers::TangentFieldResult r = solvers::direction_field_on(s, settings);
  progress(args, "field in " + std::to_string(watch.seconds()) +
                     " s: " + std::to_string(r.constrained) + " vertices held, " +
                     std::to_string(r.iterations) + " LOBPCG steps, energy " +
                     std::to_string(r.energy));
  if (out.ply) {
    write_results(out, s,
                  {{"fx", r.vectors.col(0)},
                   {"fy", r.vectors.col(1)},
                   {"fz", r.vectors.col(2)},
                   {"angle", r.angle},
                   {"singularity", r.singularity}});
  } else {
    write_rows(out.path, r.vectors);
  }
  std::printf("wrote %s: %d-direction field, %d singular faces, total index %ld/%d\n",
              out.path.c_str(), settings.symmetry, int(r.singular_faces), r.total_index,
              settings.symmetry);
  return 0;
}

}  // namespace

Command field_command() {
  Command c;
  c.summary = "smoothest direction fields (vectors, lines, crosses), free or aligned";
  c.spec.name = "field";
  c.spec.positionals = {"MESH"};
  c.spec.prose =
      "The smoothest N-direction field (N = 1 vectors, 2 lines, 4 crosses) on the\n"
      "intrinsic Delaunay triangulation: the smallest eigenvector of the connection\n"
      "Laplacian (Knöppel et al. 2013), or, with --align-boundary / --constraints, the\n"
      "smoothest field through those directions. Components without a constraint get\n"
      "their own smoothest field.\n"
      "  OUT.ply: the input mesh with per-vertex properties fx fy fz (a unit tangent\n"
      "  vector: one of the N directions), angle (that direction in the vertex's own\n"
      "  coordinate: 0 along its first edge, counter-clockwise with the faces'\n"
      "  orientation) and singularity (indices in units of 1/N of the singular faces,\n"
      "  each on one of its corners; they sum to N·χ on a closed surface).\n"
      "  OUT.txt: 'x y z' per input vertex, in order.\n"
      "Constraints file: lines 'VERTEX X Y Z' (a 0-based input vertex and a direction,\n"
      "projected to the tangent plane there); '#' starts a comment.\n";
  c.spec.groups = {
      {"Options",
       {count("symmetry", "N")
            .at_least(1)
            .defaults_to("1")
            .explain("directions per vertex: 1 vectors, 2 lines, 4 crosses"),
        flag("align-boundary")
            .explain("hold the field along the boundary (manifold meshes with boundary)"),
        text("constraints", "FILE").explain("directions to hold (format above)"),
        text("output", "OUT")
            .short_alias('o')
            .mandatory()
            .with_extensions({".ply", ".txt"})
            .explain("OUT.ply (mesh + fx fy fz angle singularity) or OUT.txt ('x y z' lines)"),
        flag("refine").explain("intrinsic Delaunay refinement first (options below)")}},
      refine_options_group(0.0),
      surface_options()};
  c.spec.epilogue =
      "examples:\n"
      "  ifem field spot.obj --symmetry 4 -o spot_cross.ply\n"
      "  ifem field disk.obj --symmetry 1 --align-boundary -o disk_field.txt\n";
  c.run = run;
  return c;
}

}  // namespace ifem::cli
