// `ifem info`: what a mesh is made of, and what ifem will do with it.
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <sstream>

#include "cli.h"
#include "intrinsic/core/errors.h"
#include "intrinsic/core/geometry.h"
#include "json.h"
#include "solvers/recipes/surface_summary.h"

namespace ifem::cli {
namespace {

// The JSON object's first fields, the ones every input has: the file and its format.
Json begin_json(const std::string& file, const PreparedSurface& s) {
  return Json{{"file", file}, {"format", s.input.format}};
}

// Closes the JSON object with the path ifem takes and why, and prints it.
void print_json(Json& j, const PreparedSurface& s) {
  j["path"] = intrinsic::to_string(s.path);
  j["path_reason"] = s.reason_detail;
  std::printf("%s\n", json_text(j).c_str());
}

// The first line of the text report: the file and its format.
void print_text_header(const std::string& file, const PreparedSurface& s) {
  std::printf("%s (%s)\n", file.c_str(), s.input.format.c_str());
}

// The last line of the text report: the path ifem takes and why.
void print_text_path(const PreparedSurface& s) {
  std::printf("  path: %s (%s)\n", intrinsic::to_string(s.path), s.reason_detail.c_str());
}

// `ifem info` on a point cloud: counts and what the local triangulations produced.
int print_pointcloud(const std::string& file, const PreparedSurface& s, bool json) {
  const pointcloud::Report& c = s.cloud;
  const double area = intrinsic::total_area(s.tri);
  if (json) {
    Json j = begin_json(file, s);
    j["points"] = c.points;
    j["k"] = c.k;
    j["local_triangles"] = c.local_triangles;
    j["isolated_points"] = c.isolated_points;
    j["first_isolated_point"] = c.first_isolated_point;
    j["starless_points"] = c.starless_points;
    j["coincident_points"] = c.coincident_points;
    j["normals_from_file"] = c.normals_from_input;
    j["cover_faces"] = s.tri.n_faces();
    j["cover_edges"] = s.tri.n_edges();
    j["nonmanifold_edges"] = c.cover.nonmanifold_edges;
    j["area"] = area;
    j["mollify_delta"] = c.mollify.delta;
    j["flips_to_idt"] = c.flips.flips;
    j["seconds_knn"] = c.seconds_knn;
    j["seconds_local"] = c.seconds_local;
    j["seconds_cover"] = c.seconds_cover;
    j["seconds_idt"] = c.seconds_idt;
    print_json(j, s);
    return 0;
  }
  print_text_header(file, s);
  std::printf("  points %d, k = %d neighbours, normals from the file on %d points\n", c.points, c.k,
              c.normals_from_input);
  std::printf(
      "  local Delaunay triangles %d (over all stars), points without a star of their "
      "own %d\n",
      c.local_triangles, c.starless_points);
  std::printf("  isolated points %d", c.isolated_points);
  if (c.isolated_points)
    std::printf(" (first %d; zero row in L, zero mass)", c.first_isolated_point);
  std::printf(", points with an exact duplicate %d\n", c.coincident_points);
  std::printf(
      "  tufted cover: %d faces, %d edges (multiplicity %d), %d nonmanifold input edges, "
      "area %.6g\n",
      s.tri.n_faces(), s.tri.n_edges(), s.tri.multiplicity(), c.cover.nonmanifold_edges, area);
  std::printf("  mollification δ = %.3g (margin ε = %.3g, %d faces below it)\n", c.mollify.delta,
              c.mollify.epsilon, c.mollify.faces_below_margin);
  std::printf("  intrinsic Delaunay: %zu flips\n", c.flips.flips);
  std::printf("  time: kNN %.3g s, local Delaunay %.3g s, tufted cover %.3g s, flips %.3g s\n",
              c.seconds_knn, c.seconds_local, c.seconds_cover, c.seconds_idt);
  print_text_path(s);
  return 0;
}

int run_info(const Args& args) {
  const std::string file = args.positional()[0];
  // Always flip here: info reports the flip count; --no-delaunay only skips it.
  PreparedSurface s = prepare_surface(file, args);
  if (s.path == intrinsic::SurfacePath::kPointCloud)
    return print_pointcloud(file, s, args.has("json"));
  const solvers::MeshSummary m = solvers::summarize_mesh(s);
  if (args.has("json")) {
    Json j = begin_json(file, s);
    j["vertices"] = m.vertices;
    j["edges"] = m.edges;
    j["faces"] = m.faces;
    j["polygons"] = m.polygons;
    j["unreferenced_vertices"] = m.unreferenced_vertices;
    j["boundary_edges"] = m.boundary_edges;
    j["boundary_loops"] = m.boundary_loops;
    j["components"] = m.components;
    j["euler_characteristic"] = m.euler_characteristic;
    j["genus"] = m.genus ? Json(*m.genus) : Json(nullptr);
    j["nonmanifold_edges"] = m.nonmanifold_edges;
    j["nonmanifold_vertices"] = m.nonmanifold_vertices;
    j["dropped_degenerate_faces"] = m.dropped_degenerate_faces;
    j["duplicate_faces"] = m.duplicate_faces;
    j["reoriented_faces"] = m.reoriented_faces;
    j["min_angle_deg"] = m.min_angle_deg;
    j["max_angle_deg"] = m.max_angle_deg;
    j["non_delaunay_share"] = m.non_delaunay_share;
    j["flips_to_idt"] = m.flips_to_idt;
    j["mollify_delta"] = m.mollify_delta;
    print_json(j, s);
    return 0;
  }
  print_text_header(file, s);
  std::printf("  vertices %d (unreferenced %d), edges %d, faces %d (from %d polygons)\n",
              m.vertices, m.unreferenced_vertices, m.edges, m.faces, m.polygons);
  std::printf("  components %d, boundary loops %d (%d boundary edges), Euler characteristic %ld",
              m.components, m.boundary_loops, m.boundary_edges, m.euler_characteristic);
  if (m.genus) std::printf(", genus %ld", *m.genus);
  std::printf("\n  nonmanifold edges %d, nonmanifold vertices %d\n", m.nonmanifold_edges,
              m.nonmanifold_vertices);
  std::printf("  repaired: %d degenerate faces dropped, %d faces reoriented, %d duplicate faces\n",
              m.dropped_degenerate_faces, m.reoriented_faces, m.duplicate_faces);
  std::printf("  corner angles %.4g° .. %.4g°, non-Delaunay edges %.2f%%\n", m.min_angle_deg,
              m.max_angle_deg, 100.0 * m.non_delaunay_share);
  std::printf("  mollification δ = %.3g (margin ε = %.3g, %d faces below it)\n", m.mollify_delta,
              m.mollify_epsilon, m.faces_below_margin);
  std::printf("  intrinsic Delaunay: %zu flips\n", m.flips_to_idt);
  print_text_path(s);
  return 0;
}

}  // namespace

Command info_command() {
  Command c;
  c.summary = "describe a mesh: counts, topology, defects, angles, flips to intrinsic Delaunay";
  c.spec.name = "info";
  c.spec.positionals = {"MESH|POINTCLOUD"};
  c.spec.prose =
      "Prints vertex/edge/face counts, components, boundary loops, Euler characteristic\n"
      "and genus, nonmanifold edges and vertices, what was repaired (degenerate faces\n"
      "dropped, faces reoriented), min/max corner angle and the share of non-Delaunay\n"
      "edges of the input, the flips to the intrinsic Delaunay triangulation, and which\n"
      "path (manifold / tufted cover / point cloud) ifem takes for this input and why.\n"
      "On a point cloud: point count, k, local triangles, isolated points, stage times.\n";
  c.spec.groups = {{"Options", {flag("json").explain("one JSON object on stdout instead of text")}},
                   surface_options()};
  c.run = run_info;
  return c;
}

}  // namespace ifem::cli
