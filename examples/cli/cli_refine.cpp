// `ifem refine`: intrinsic Delaunay refinement of a mesh (Chew's 2nd algorithm; inserted vertices
// kept on the input by integer coordinates or signposts).
#include "cli_refine.h"

#include <cmath>
#include <cstdio>
#include <optional>
#include <sstream>

#include "intrinsic/core/errors.h"
#include "intrinsic/core/geometry.h"
#include "intrinsic/core/timer.h"
#include "intrinsic/integer/correspondence.h"
#include "intrinsic/refine/common_subdivision.h"

namespace ifem::cli {

OptionGroup refine_options_group(double resolution_default) {
  return {"Refinement options",
          {real("min-angle", "A")
               .above(0)
               .at_most(30)
               .defaults_to(format_number(intrinsic::RefineOptions{}.min_angle_degrees))
               .explain("smallest corner angle wanted, degrees"),
           real("resolution", "C")
               .at_least(0)
               .defaults_to(format_number(resolution_default))
               .explain("also refine until edges are about C·h long (h = mean edge length\n"
                        "of the input): triangles larger than the equilateral one of side\n"
                        "C·h are split (0 = off)"),
           real("max-area", "X")
               .at_least(0)
               .explain("also split triangles of area above X (default: no bound; 0 = none)"),
           count("max-insertions", "N")
               .explain("stop after N inserted vertices (default 10 × input vertices\n"
                        "+ 2000, plus 4 × area / (max area) with a size bound)"),
           real("memory-budget", "GB")
               .above(0)
               .explain("refuse a refinement whose estimated memory (about 4 KiB per\n"
                        "vertex, see the message) exceeds GB gigabytes, and stop\n"
                        "inserting there (default: half the physical memory, or 80%\n"
                        "of ulimit -v); with --curves, also Bézier curves whose added\n"
                        "vertices (estimated up front) exceed it; with --exact, the\n"
                        "windows (64 bytes each)"),
           count("relax", "ITER")
               .defaults_to("0")
               .explain("then ITER passes of optimal Delaunay (ODT) relaxation of the\n"
                        "inserted vertices, each moved inside its flat star on the surface\n"
                        "(input vertices never move; min angle kept)"),
           real("max-edge", "L")
               .at_least(0)
               .explain("with --relax: after each pass split edges longer than L at their\n"
                        "midpoints (the next pass relaxes the new vertices; default: no bound)"),
           text("correspondence", "KIND")
               .defaults_to("integer")
               .explain("how inserted vertices keep their places on the input surface:\n"
                        "'integer' (normal coordinates: how many input edges cross each\n"
                        "intrinsic edge, so the common subdivision's combinatorics are exact\n"
                        "integers and it partitions the input's faces on every mesh tried)\n"
                        "or 'signposts' (a direction and length per edge, traced in floating\n"
                        "point; on a few near-degenerate meshes the traced overlay does not\n"
                        "cover the input faces exactly, docs/decisions.md D-330). Pick\n"
                        "signposts to compare with earlier results or other tools that use\n"
                        "them, or when only the refined mesh is wanted and time counts (a\n"
                        "little faster on needle-heavy meshes). Both give the same\n"
                        "triangulation and results. With --curves, FlipOut draws the curves\n"
                        "on signposts and its flips and insertions are replayed on the\n"
                        "integer coordinates (the same triangulation). Tufted-cover\n"
                        "refinement (nonmanifold input) uses neither")}};
}

solvers::SurfaceRefineOptions refine_settings(const Args& args, double default_resolution,
                                              bool need_signposts) {
  solvers::SurfaceRefineOptions r;  // every value below is range-checked by the option table
  r.min_angle_degrees = args.real("min-angle");
  r.resolution = args.real_or("resolution", default_resolution);
  r.max_area = args.real_or("max-area", 0.0);
  r.max_insertions = args.count_or("max-insertions", -1);  // -1: the library's cap
  r.relax_iterations = args.count("relax");
  r.relax_max_edge = args.real_or("max-edge", 0.0);
  r.need_signposts = need_signposts;
  try {
    r.correspondence = intrinsic::parse_correspondence(
        args.has("correspondence") ? args.get("correspondence") : "integer");
  } catch (const InvalidInput& e) {
    throw UsageError(std::string("--correspondence: ") + e.what());
  }
  r.max_memory_bytes = args.real_or("memory-budget", 0.0) * 1e9;  // 0: the library's default
  if (r.relax_max_edge > 0.0 && r.relax_iterations == 0) {
    throw UsageError("--max-edge splits during --relax ITER");
  }
  r.validate();
  return r;
}

namespace {

double input_min_angle(const io::SurfaceInput& input) {
  const auto t =
      intrinsic::IntrinsicTriangulation::from_positions(input.triangles, input.positions);
  double m = intrinsic::kPi;
  for (Index f = 0; f < t.n_faces(); ++f) m = std::min(m, intrinsic::min_corner_angle(t, f));
  return m * 180.0 / intrinsic::kPi;
}

// Everything `ifem refine` writes, computed before the first file is written (no partial
// output on a failure).
struct RefineOutputs {
  intrinsic::CommonSubdivision overlay;                    ///< -o
  std::vector<std::vector<Eigen::Vector3d>> traced_edges;  ///< --lines
  std::vector<Triangle> faces;                             ///< --mesh: the refined faces
  Eigen::VectorXd inserted;                                ///< --mesh: 1 on inserted vertices
  Positions positions;                                     ///< --mesh: every vertex in 3D
};

RefineOutputs compute_outputs(const Args& args, const intrinsic::CorrespondenceView& st) {
  RefineOutputs o;
  Stopwatch watch;
  if (args.has("output")) {
    o.overlay = st.common_subdivision(args.real_or("memory-budget", 0.0) * 1e9);
    progress(args, "common subdivision: " + std::to_string(o.overlay.faces.size()) +
                       " triangles in " + std::to_string(watch.restart()) + " s");
  }
  if (args.has("lines")) {
    o.traced_edges = st.traced_edges_3d();
    progress(args, "traced " + std::to_string(o.traced_edges.size()) +
                       " intrinsic edges over the input in " + std::to_string(watch.restart()) +
                       " s");
  }
  if (args.has("mesh")) {
    const auto& tri = st.intrinsic();
    o.faces.resize(tri.n_faces());
    for (Index f = 0; f < tri.n_faces(); ++f) {
      o.faces[f] = {tri.tail(3 * f), tri.tail(3 * f + 1), tri.tail(3 * f + 2)};
    }
    o.inserted.resize(tri.n_vertices());
    for (Index v = 0; v < tri.n_vertices(); ++v) o.inserted[v] = v >= st.n_input_vertices();
    o.positions = st.vertex_positions();
  }
  return o;
}

// Writes the requested files; returns one line per file for the summary.
std::vector<std::string> write_outputs(const Args& args, const intrinsic::CorrespondenceView& st,
                                       const RefineOutputs& o) {
  const bool binary = !args.has("ascii");
  std::vector<std::string> wrote;
  if (args.has("output")) {
    intrinsic::write_common_subdivision_ply(args.get("output"), o.overlay, binary);
    wrote.push_back(args.get("output") + " (common subdivision, " +
                    std::to_string(o.overlay.faces.size()) + " triangles)");
  }
  if (args.has("lines")) {
    intrinsic::write_polylines_ply(args.get("lines"), o.traced_edges, binary);
    wrote.push_back(args.get("lines") + " (" + std::to_string(o.traced_edges.size()) +
                    " traced edges, PLY line set)");
  }
  if (args.has("mesh")) {
    io::write_ply(args.get("mesh"), o.positions, o.faces, {{"inserted", o.inserted}}, binary);
    wrote.push_back(args.get("mesh") + " (refined triangulation)");
  }
  if (args.has("save")) {
    st.save(args.get("save"));
    wrote.push_back(args.get("save") + " (intrinsic triangulation, " +
                    intrinsic::file_format(st.kind()) + ")");
  }
  return wrote;
}

// The summary on stdout: vertex counts, angles before and after, relaxation, the cap.
void print_summary(const PreparedSurface& s, double min_angle_input) {
  const intrinsic::RefineReport& r = s.refine_report;
  const intrinsic::RelaxReport& rr = s.relax_report;
  std::printf("vertices: %d input -> %d refined (%d inserted)\n", r.vertices_before,
              r.vertices_after, r.insertions);
  std::printf("min angle: %.3f° input, %.3f° intrinsic Delaunay, %.3f° refined", min_angle_input,
              r.min_angle_before, r.min_angle_after_excluding_needles);
  if (r.needle_faces) {
    std::printf(" (%d needle-cone triangles left alone; %.3f° with them)", r.needle_faces,
                r.min_angle_after);
  }
  std::printf("\n");
  if (rr.passes > 0) {
    std::printf(
        "relaxed: %d ODT passes, %d moves, %d edge splits; min angle %.3f° -> "
        "%.3f°, mean min angle %.3f° -> %.3f°\n",
        rr.passes, rr.moved, rr.splits, rr.min_angle_before, rr.min_angle_after,
        rr.mean_min_angle_before, rr.mean_min_angle_after);
  }
  if (r.scale_floor_faces) {
    std::printf(
        "%d triangles left below the bound at the scale floor (insertions there were cascading "
        "towards a point: --min-angle above about 26.5° has no termination guarantee)\n",
        r.scale_floor_faces);
  }
  if (r.hit_insertion_cap) {
    std::printf("stopped at the insertion cap: %d triangles still below the bounds\n",
                r.bad_faces_left);
  }
}

int run_refine(const Args& args) {
  if (!args.has("output") && !args.has("save") && !args.has("lines") && !args.has("mesh")) {
    throw UsageError("missing -o OUT.ply (or --save / --lines / --mesh; see --help)");
  }
  // refinement with signposts or integer coordinates (the library refuses inputs that cannot
  // have them)
  const PreparedSurface s =
      prepare_surface(args.positional()[0], args, refine_settings(args, 0.0, true));
  const intrinsic::CorrespondenceView correspondence = *s.correspondence();
  const RefineOutputs outputs = compute_outputs(args, correspondence);
  const std::vector<std::string> wrote = write_outputs(args, correspondence, outputs);
  print_summary(s, input_min_angle(s.input));
  for (const std::string& w : wrote) std::printf("wrote %s\n", w.c_str());
  return 0;
}

}  // namespace

Command refine_command() {
  Command c;
  c.summary = "intrinsic Delaunay refinement (min angle); common subdivision as a PLY mesh";
  c.spec.name = "refine";
  c.spec.positionals = {"MESH"};
  c.spec.prose =
      "Refines the intrinsic Delaunay triangulation of MESH by inserting circumcenters\n"
      "(Chew's second algorithm, located on the surface with integer coordinates or\n"
      "signposts, --correspondence) until every\n"
      "triangle has all corner angles ≥ A. The surface itself never changes: inserted\n"
      "vertices lie on the input's triangles. Triangles whose small angle sits at a\n"
      "cone vertex with total angle below the bound (2× it inside) cannot be fixed and\n"
      "are left alone and counted. Needs at least one of -o, --lines, --mesh, --save.\n\n"
      "Supported inputs: edge-manifold, orientable meshes, with or without boundary\n"
      "(nonmanifold and non-orientable meshes are refined on their tufted cover by\n"
      "`ifem distance --refine` and `ifem eigen --refine`, which need no correspondence;\n"
      "here they are an error, as are point clouds).\n";
  c.spec.groups = {
      {"Options",
       {text("output", "OUT.ply")
            .short_alias('o')
            .with_extensions({".ply"})
            .explain("the common subdivision: the overlay of the intrinsic and input\n"
                     "triangulations as a triangle mesh on the input surface (each overlay\n"
                     "polygon fanned into triangles), face properties 'intrinsic_face' and\n"
                     "'input_face' (0-based, input faces in the file's order)"),
        text("lines", "LINES.ply")
            .with_extensions({".ply"})
            .explain("the intrinsic edges traced over the input surface, as a PLY line set\n"
                     "(vertex + edge elements)"),
        text("mesh", "FILE.ply")
            .with_extensions({".ply"})
            .explain("the refined triangulation, inserted vertices at their positions on\n"
                     "the surface (property 'inserted')"),
        text("save", "FILE.ifem")
            .explain("the input and the intrinsic triangulation (gluing, lengths, and\n"
                     "normal coordinates with roundabouts and spokes, or signposts with\n"
                     "inserted-vertex locations) as text, format 'ifem-integer 1' or\n"
                     "'ifem-signpost 1' (--correspondence); ifem view / render\n"
                     "--triangulation read either"),
        flag("ascii").explain("ASCII PLY instead of binary")}},
      refine_options_group(0.0),
      surface_options()};
  c.run = run_refine;
  return c;
}

}  // namespace ifem::cli
