// `ifem refine`: intrinsic Delaunay refinement of a mesh (signposts, Chew's 2nd algorithm).
#include "cli_refine.h"

#include <cmath>
#include <cstdio>
#include <optional>
#include <sstream>

#include "intrinsic/core/errors.h"
#include "intrinsic/core/geometry.h"
#include "intrinsic/surface/build_surface.h"
#include "intrinsic/surface/face_analysis.h"

namespace ifem::cli {

namespace {
std::string format_default(double v) {
  char buf[32];
  std::snprintf(buf, sizeof buf, "%g", v);
  return buf;
}
}  // namespace

OptionGroup refine_options_group(double resolution_default) {
  return {"Refinement options",
          {real("min-angle", "A")
               .above(0)
               .at_most(30)
               .defaults_to(format_default(intrinsic::RefineOptions{}.min_angle_degrees))
               .explain("smallest corner angle wanted, degrees"),
           real("resolution", "C")
               .at_least(0)
               .defaults_to(format_default(resolution_default))
               .explain("also refine until edges are about C·h long (h = mean edge length\n"
                        "of the input): triangles larger than the equilateral one of side\n"
                        "C·h are split (0 = off)"),
           real("max-area", "X")
               .at_least(0)
               .explain("also split triangles of area above X (default: no bound; 0 = none)"),
           count("max-insertions", "N")
               .explain("stop after N inserted vertices (default 10 × input vertices\n"
                        "+ 2000, plus 4 × area / (max area) with a size bound)"),
           count("relax", "ITER")
               .defaults_to("0")
               .explain("then ITER passes of optimal Delaunay (ODT) relaxation of the\n"
                        "inserted vertices, each moved inside its flat star on the surface\n"
                        "(input vertices never move; min angle kept)"),
           real("max-edge", "L")
               .at_least(0)
               .explain("with --relax: after each pass split edges longer than L at their\n"
                        "midpoints (the next pass relaxes the new vertices; default: no bound)")}};
}

double refine_target_length(const PreparedSurface& s, const Args& args, double default_resolution) {
  const double c = args.real_or("resolution", default_resolution);  // ≥ 0, finite (table)
  if (c == 0.0 || !s.input.has_faces()) return 0.0;
  return c * intrinsic::mean_side_length(s.input.triangles, s.input.positions);
}

intrinsic::RefineOptions refine_options(const Args& args, double target_length) {
  intrinsic::RefineOptions o;
  o.min_angle_degrees = args.real("min-angle");
  o.max_area = args.real_or("max-area", 0.0);
  if (target_length > 0.0) {
    const double a = intrinsic::equilateral_area(target_length);
    o.max_area = o.max_area > 0.0 ? std::min(o.max_area, a) : a;
  }
  o.max_insertions = args.count_or("max-insertions", -1);  // -1: the library's cap
  return o;
}

std::string refine_unsupported(const PreparedSurface& s, bool need_signposts) {
  if (s.path == "pointcloud") {
    return "refinement is not supported on point clouds (their tufted cover is glued from local "
           "triangulations, with a mass of its own)";
  }
  if (need_signposts) {
    return "this input took the " + s.path + " path (" + s.path_reason +
           "): refinement then runs on the tufted cover, without signposts, so inserted "
           "vertices have no place on the input; `ifem distance --refine` and `ifem eigen "
           "--refine` support that, this command needs signposts (edge-manifold, orientable "
           "meshes only)";
  }
  return "refinement supports edge-manifold, orientable meshes (signposts) and the tufted "
         "cover; this input took the " +
         s.path + " path (" + s.path_reason + ")";
}

namespace {

// Refinement with signposts runs on the manifold Δ-complex of the input. A mesh that took the
// tufted path only because boundary edges opposite obtuse angles kept negative weights is fine:
// refinement splits exactly those (encroached) boundary edges.
bool refinable(const PreparedSurface& s) {
  return s.path != "pointcloud" && s.stats.edge_manifold() &&
         s.path_reason.find("non-orientable") == std::string::npos && s.path_reason != "--tufted";
}

}  // namespace

namespace {

std::string describe(const intrinsic::RefineReport& r) {
  std::ostringstream m;
  m << "refined: " << r.vertices_before << " -> " << r.vertices_after << " vertices ("
    << r.face_insertions << " circumcenters, " << r.edge_splits << " edge splits, "
    << r.boundary_splits << " boundary splits), " << r.flips << " flips, min angle "
    << r.min_angle_before << "° -> " << r.min_angle_after_excluding_needles << "°";
  if (r.needle_faces) m << ", " << r.needle_faces << " needle-cone triangles left alone";
  if (r.failed_traces) m << ", " << r.failed_traces << " bad triangles skipped (trace failed)";
  if (r.hit_insertion_cap) {
    m << "; STOPPED at the insertion cap, " << r.bad_faces_left << " triangles still bad";
  }
  return m.str();
}

std::string describe_relax(const intrinsic::RelaxReport& r) {
  std::ostringstream m;
  m << "relaxed: " << r.passes << " ODT passes, " << r.moved << " moves (" << r.rejected
    << " rejected, longest " << r.max_displacement << "), ";
  if (r.splits > 0) {
    m << r.splits << " long edges split (longest now " << r.max_edge_after << ")"
      << (r.hit_split_cap ? " STOPPED at the split cap" : "") << ", ";
  }
  m << r.flips << " flips, min angle " << r.min_angle_before << "° -> " << r.min_angle_after
    << "°, mean min angle " << r.mean_min_angle_before << "° -> " << r.mean_min_angle_after << "°";
  return m.str();
}

}  // namespace

std::optional<intrinsic::SignpostTriangulation> refine_prepared(
    PreparedSurface& s, const Args& args, double default_resolution, bool need_signposts,
    intrinsic::RefineReport* report, intrinsic::RelaxReport* relax_report) {
  const Index relax = args.count("relax");                // ≥ 0 (table)
  const double max_edge = args.real_or("max-edge", 0.0);  // ≥ 0 (table)
  if (max_edge > 0.0 && relax == 0) throw UsageError("--max-edge splits during --relax ITER");
  const double t0 = now_seconds();
  const double target = refine_target_length(s, args, default_resolution);
  if (!refinable(s)) {
    // nonmanifold / non-orientable / --tufted: refine the tufted cover itself, intrinsically
    if (s.path != "tufted" || need_signposts) {
      throw InvalidInput(refine_unsupported(s, need_signposts));
    }
    if (relax > 0) {
      throw UsageError("--relax moves vertices with signposts, which the tufted cover (" +
                       s.path_reason + ") does not have");
    }
    const intrinsic::RefineReport r =
        intrinsic::delaunay_refine(s.tri, refine_options(args, target));
    // inserted vertices count as interior for the heat method's boundary condition (the
    // cover folds across the input's boundary edges: they are interior edges of it)
    if (!s.boundary_vertex.empty()) s.boundary_vertex.resize(s.tri.n_vertices(), 0);
    progress(args,
             describe(r) + " on the tufted cover in " + std::to_string(now_seconds() - t0) + " s");
    if (report) *report = r;
    if (relax_report) *relax_report = intrinsic::RelaxReport{};
    return std::nullopt;
  }
  intrinsic::SignpostTriangulation st(s.input.triangles, s.input.positions, args.real("mollify"));
  const intrinsic::RefineReport r = intrinsic::delaunay_refine(st, refine_options(args, target));
  s.tri = st.intrinsic();
  if (s.path != "manifold") {
    s.path = "manifold";
    s.path_reason = "refined (boundary edges opposite obtuse angles are split by refinement)";
  }
  s.boundary_vertex.clear();  // the refined triangulation's own boundary is the surface's
  if (const Index bad = intrinsic::negative_boundary_weights(s.tri)) {
    progress(args, "note: " + std::to_string(bad) +
                       " boundary edges still face obtuse angles after refinement (needle cones)");
  }
  progress(args, describe(r) + " in " + std::to_string(now_seconds() - t0) + " s");
  if (report) *report = r;
  intrinsic::RelaxReport rr;
  if (relax > 0) {
    const double t1 = now_seconds();
    intrinsic::RelaxOptions ro;
    ro.iterations = relax;
    ro.max_edge_length = max_edge;
    rr = intrinsic::relax_inserted_vertices(st, ro);
    progress(args, describe_relax(rr) + " in " + std::to_string(now_seconds() - t1) + " s");
  }
  if (relax_report) *relax_report = rr;
  s.tri = st.intrinsic();  // the relaxed lengths (the same connectivity up to flips)
  return st;
}

namespace {

double input_min_angle(const PreparedSurface& s) {
  const auto t =
      intrinsic::IntrinsicTriangulation::from_positions(s.input.triangles, s.input.positions);
  double m = intrinsic::kPi;
  for (Index f = 0; f < t.n_faces(); ++f) m = std::min(m, intrinsic::min_corner_angle(t, f));
  return m * 180.0 / intrinsic::kPi;
}

int run(const Args& args) {
  if (!args.has("output") && !args.has("save") && !args.has("lines") && !args.has("mesh")) {
    throw UsageError("missing -o OUT.ply (or --save / --lines / --mesh; see --help)");
  }
  PreparedSurface s = prepare_surface(args.positional()[0], args);
  if (!refinable(s)) throw InvalidInput(refine_unsupported(s, true));
  const double min_in = input_min_angle(s);
  intrinsic::RefineReport r;
  intrinsic::RelaxReport rr;
  const intrinsic::SignpostTriangulation st = *refine_prepared(s, args, 0.0, true, &r, &rr);
  // everything is computed before the first file is written: no partial output on a failure
  double t0 = now_seconds();
  const bool binary = !args.has("ascii");
  intrinsic::CommonSubdivision cs;
  if (args.has("output")) {
    cs = intrinsic::common_subdivision(st);
    progress(args, "common subdivision: " + std::to_string(cs.faces.size()) + " triangles in " +
                       std::to_string(now_seconds() - t0) + " s");
  }
  std::vector<std::vector<Eigen::Vector3d>> lines;
  if (args.has("lines")) {
    t0 = now_seconds();
    lines = st.traced_edges_3d();
    progress(args, "traced " + std::to_string(lines.size()) +
                       " intrinsic edges over the input in " + std::to_string(now_seconds() - t0) +
                       " s");
  }
  std::vector<Triangle> faces;
  Eigen::VectorXd inserted;
  const auto& tri = st.intrinsic();
  if (args.has("mesh")) {
    faces.resize(tri.n_faces());
    for (Index f = 0; f < tri.n_faces(); ++f) {
      faces[f] = {tri.tail(3 * f), tri.tail(3 * f + 1), tri.tail(3 * f + 2)};
    }
    inserted.resize(tri.n_vertices());
    for (Index v = 0; v < tri.n_vertices(); ++v) inserted[v] = v >= st.n_input_vertices();
  }
  std::vector<std::string> wrote;
  if (args.has("output")) {
    intrinsic::write_common_subdivision_ply(args.get("output"), cs, binary);
    wrote.push_back(args.get("output") + " (common subdivision, " +
                    std::to_string(cs.faces.size()) + " triangles)");
  }
  if (args.has("lines")) {
    intrinsic::write_polylines_ply(args.get("lines"), lines, binary);
    wrote.push_back(args.get("lines") + " (" + std::to_string(lines.size()) +
                    " traced edges, PLY line set)");
  }
  if (args.has("mesh")) {
    io::write_ply(args.get("mesh"), st.vertex_positions(), faces, {{"inserted", inserted}}, binary);
    wrote.push_back(args.get("mesh") + " (refined triangulation)");
  }
  if (args.has("save")) {
    st.save(args.get("save"));
    wrote.push_back(args.get("save") + " (intrinsic triangulation, ifem-signpost 1)");
  }
  std::printf("vertices: %d input -> %d refined (%d inserted)\n", r.vertices_before,
              r.vertices_after, r.insertions);
  std::printf("min angle: %.3f° input, %.3f° intrinsic Delaunay, %.3f° refined", min_in,
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
  if (r.hit_insertion_cap) {
    std::printf("stopped at the insertion cap: %d triangles still below the bounds\n",
                r.bad_faces_left);
  }
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
      "(Chew's second algorithm, located on the surface with signposts) until every\n"
      "triangle has all corner angles ≥ A. The surface itself never changes: inserted\n"
      "vertices lie on the input's triangles. Triangles whose small angle sits at a\n"
      "cone vertex with total angle below the bound (2× it inside) cannot be fixed and\n"
      "are left alone and counted. Needs at least one of -o, --lines, --mesh, --save.\n\n"
      "Supported inputs: edge-manifold, orientable meshes, with or without boundary\n"
      "(nonmanifold and non-orientable meshes are refined on their tufted cover by\n"
      "`ifem distance --refine` and `ifem eigen --refine`, which need no signposts;\n"
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
            .explain("the input and the intrinsic triangulation (gluing, lengths,\n"
                     "signposts, inserted-vertex locations) as text, format\n"
                     "'ifem-signpost 1' (intrinsic/refine/signpost.cpp)"),
        flag("ascii").explain("ASCII PLY instead of binary")}},
      refine_options_group(0.0),
      surface_options()};
  c.run = run;
  return c;
}

}  // namespace ifem::cli
