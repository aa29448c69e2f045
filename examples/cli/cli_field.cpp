// `ifem field`: the smoothest n-direction field (vectors, lines, crosses), free or aligned to
// the boundary, to given directions and to curves (--curves), with its singularities.
#include <cstdio>
#include <fstream>
#include <sstream>
#include <string>

#include "cli.h"
#include "cli_curves.h"
#include "cli_refine.h"
#include "intrinsic/core/errors.h"
#include "intrinsic/core/timer.h"
#include "intrinsic/io/tokens.h"
#include "results.h"
#include "solvers/recipes/curve_fields.h"
#include "solvers/recipes/tangent_fields.h"
#include "solvers/recipes/text_formats.h"

namespace ifem::cli {
namespace {

solvers::FieldOptions field_settings(const Args& args) {
  solvers::FieldOptions settings;
  settings.symmetry = static_cast<int>(args.count("symmetry"));
  settings.align_boundary = args.has("align-boundary");
  if (args.has("constraints"))
    settings.constraints = recipes::read_constraints_file(args.get("constraints"));
  return settings;
}

// The progress line after the solve and the properties written.
std::vector<io::VertexProperty> report(const Args& args, const PreparedSurface& s,
                                       const solvers::TangentFieldResult& r, double seconds) {
  progress(args, "field in " + std::to_string(seconds) + " s: " + std::to_string(r.constrained) +
                     " vertices held, " + std::to_string(r.iterations) + " LOBPCG steps, energy " +
                     std::to_string(r.energy) +
                     (s.path == intrinsic::SurfacePath::kManifold
                          ? std::string()
                          : "; 3D frames, " + std::to_string(r.orientation_conflicts) +
                                " neighbour pairs with opposite normals"));
  if (r.components > 1 || r.empty_components > 0) {
    progress(args,
             std::to_string(r.components) + " components: " + std::to_string(r.free_components) +
                 " with their own smoothest field, " +
                 std::to_string(r.components - r.free_components - r.empty_components) +
                 " held by constraints, " + std::to_string(r.empty_components) +
                 " without a field (" + std::to_string(r.flat_components) +
                 " flat: zero area; vectors 0 0 0 there)" +
                 (r.skipped_constraints > 0
                      ? ", " + std::to_string(r.skipped_constraints) + " directions on them skipped"
                      : std::string()));
  }
  return {{"fx", r.vectors.col(0)},
          {"fy", r.vectors.col(1)},
          {"fz", r.vectors.col(2)},
          {"angle", r.angle},
          {"singularity", r.singularity}};
}

// The face property: the index around each input face (empty when unknown).
std::vector<io::VertexProperty> face_properties(const solvers::TangentFieldResult& r) {
  if (r.face_singularity.size() == 0) return {};
  return {{"singularity", r.face_singularity.cast<double>()}};
}

void print_written(const ResultOutput& out, const solvers::FieldOptions& settings,
                   const solvers::TangentFieldResult& r) {
  std::printf("wrote %s: %d-direction field, %d singular faces, total index %ld/%d\n",
              out.path.c_str(), settings.symmetry, int(r.singular_faces), r.total_index,
              settings.symmetry);
}

// --curves: the curves inserted as edges of the constrained triangulation, the field held
// along them (solvers/recipes/curve_fields.h).
int run_field_curves(const Args& args, const ResultOutput& out) {
  std::vector<solvers::CurveCondition> curves = read_curves(args);  // fails fast, before the mesh
  const solvers::FieldOptions settings = field_settings(args);
  io::SurfaceInput input = read_input(args.positional()[0], args);
  std::optional<solvers::SurfaceRefineOptions> refine;
  if (args.has("refine")) refine = refine_settings(args, 0.0, true);
  CurveRun run{prepare_curves(std::move(input), std::move(curves), args, false, refine), {}};
  const Stopwatch watch;
  const solvers::TangentFieldResult r = solvers::curve_direction_field(run.surface, settings);
  const std::vector<io::VertexProperty> properties =
      report(args, run.surface.surface, r, watch.seconds());
  run.polylines = curve_polylines_if_asked(args, run.surface);
  if (out.ply) {
    write_curve_outputs(args, out, run, [&] {
      write_results(out, run.surface.surface, properties, face_properties(r));
    });
  } else {
    write_curve_outputs(args, out, run, [&] { write_rows(out.path, r.vectors); });
  }
  print_written(out, settings, r);
  print_curves_written(args, run);
  return 0;
}

int run_field(const Args& args) {
  const ResultOutput out = result_output(args);
  check_curve_options(args, {});
  if (args.has("curves")) return run_field_curves(args, out);
  const solvers::FieldOptions settings = field_settings(args);
  std::optional<solvers::SurfaceRefineOptions> refine;
  if (args.has("refine")) refine = refine_settings(args, 0.0, false);
  const PreparedSurface s = prepare_surface(args.positional()[0], args, refine);
  const Stopwatch watch;
  const solvers::TangentFieldResult r = solvers::direction_field_on(s, settings);
  const std::vector<io::VertexProperty> properties = report(args, s, r, watch.seconds());
  if (out.ply) {
    write_results(out, s, properties, face_properties(r));
  } else {
    write_rows(out.path, r.vectors);
  }
  print_written(out, settings, r);
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
      "Laplacian (Knöppel et al. 2013), or, with --align-boundary / --constraints /\n"
      "--curves, the smoothest field through those directions. Every connected\n"
      "component without a constraint gets its own smoothest field (a triangle soup\n"
      "works: one per piece); a component without area (e.g. one zero-area face: no\n"
      "tangent plane) gets none: vectors 0 0 0 and angle 0 there, directions given on\n"
      "it are skipped. A progress line counts the components and how each was treated.\n"
      "Along the boundary, a corner holds the field along both of its sides when N\n"
      "allows it (a cross at a corner of 90° or 270°), else the N-direction mean of\n"
      "the two sides (for vectors the bisector); on a flat polygon a cross field\n"
      "along the boundary is constant.\n"
      "  OUT.ply: the input mesh with per-vertex properties fx fy fz (a unit tangent\n"
      "  vector: one of the N directions), angle (that direction in the vertex's own\n"
      "  coordinate: 0 along its first edge, counter-clockwise with the faces'\n"
      "  orientation) and singularity (indices in units of 1/N of the singular faces\n"
      "  of the intrinsic triangulation, each on one of its corners), and the per-face\n"
      "  property singularity: the index of each input face in units of 1/N (the field's\n"
      "  turning around the face's three edges, relative to parallel transport, plus N\n"
      "  times its share of curvature; they sum to N·χ on a closed surface), one per\n"
      "  triangle written (a polygon of the input is written as its triangles).\n"
      "  OUT.txt: 'x y z' per input vertex, in order.\n"
      "On nonmanifold meshes (the tufted cover) and point clouds the field lives in\n"
      "per-vertex 3D frames from the normals, oriented by propagation: angle is then\n"
      "from the x axis projected to the tangent plane; singularities come from the\n"
      "input's faces (none for point clouds); --refine is refused there, and\n"
      "--align-boundary follows the input's boundary (edges of one face; refused for\n"
      "point clouds).\n"
      "Constraints file: lines 'VERTEX X Y Z' (a 0-based input vertex and a direction,\n"
      "projected to the tangent plane there); '#' starts a comment.\n\n"
      "Aligned to curves (--curves FILE, format below; thesis Fig. 10 left): curves\n"
      "drawn through the mesh's vertices (geodesic paths and loops by FlipOut,\n"
      "geodesic Bézier curves) become edges of a constrained intrinsic Delaunay\n"
      "triangulation, exactly as for poisson/distance --curves, and the field is held\n"
      "along them at every vertex on them: along the curve edge (inside a curve, the\n"
      "mean of the edge leaving the vertex and the continuation of the edge arriving,\n"
      "in the N-th power; N = 1 points the way the curve runs, from its first vertex\n"
      "on). Combines with --align-boundary and --constraints. The curves' values are\n"
      "not used and a slit is an ordinary curve. Needs an edge-manifold, orientable\n"
      "triangle mesh; --refine refines without crossing the curves.\n";
  OptionGroup options = {
      "Options",
      {count("symmetry", "N")
           .at_least(1)
           .defaults_to("1")
           .explain("directions per vertex: 1 vectors, 2 lines, 4 crosses"),
       flag("align-boundary").explain("hold the field along the boundary (meshes with boundary)"),
       text("constraints", "FILE").explain("directions to hold (format above)"),
       text("output", "OUT")
           .short_alias('o')
           .mandatory()
           .with_extensions({".ply", ".txt"})
           .explain("OUT.ply (mesh + fx fy fz angle singularity) or OUT.txt ('x y z' lines)"),
       flag("refine").explain("intrinsic Delaunay refinement first (options below;\n"
                              "with --curves: constrained, no --relax / --max-edge)")}};
  const std::vector<OptionSpec> curves = curve_options(
      "hold the field along the curves, at every vertex on them (with\n"
      "--refine, on the vertices refinement puts on them too)");
  options.options.insert(options.options.end(), curves.begin(), curves.end());
  c.spec.groups = {options, refine_options_group(0.0), surface_options()};
  c.spec.epilogue =
      curves_file_help(false, "field") +
      "examples:\n"
      "  ifem field spot.obj --symmetry 4 -o spot_cross.ply\n"
      "  ifem field disk.obj --symmetry 1 --align-boundary -o disk_field.txt\n"
      "  # a Bézier curve with control vertices 120 455 873 1201 and a loop through\n"
      "  # 40 77 93 310; the leading 0 of each line is its value (unused by field)\n"
      "  printf 'bezier 0 120 455 873 1201\\nclosed 0 40 77 93 310\\n' > curves.txt\n"
      "  ifem field scan.ply --symmetry 4 --curves curves.txt --curves-out c.obj -o cross.ply\n";
  c.run = run_field;
  return c;
}

}  // namespace ifem::cli
