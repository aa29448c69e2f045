// `ifem trace`: straight geodesics (the exponential map) from a point of the input surface in
// given directions, for a given length. The recipe is the library's
// (solvers/recipes/trace_geodesic.h); this file reads the arguments and writes the results.
#include <cstdio>
#include <string>
#include <vector>

#include "cli.h"
#include "intrinsic/core/errors.h"
#include "intrinsic/io/detail.h"
#include "intrinsic/refine/common_subdivision.h"
#include "json.h"
#include "polylines.h"
#include "solvers/recipes/geodesic.h"
#include "solvers/recipes/trace_geodesic.h"

namespace ifem::cli {
namespace {

using recipes::GeodesicRay;

recipes::GivenPoint from_option(const Args& args) {
  recipes::GivenPoint p;
  const std::string problem = recipes::parse_point_token(args.get("from"), p);
  if (!problem.empty()) throw UsageError("--from " + problem);
  return p;
}

// --direction X,Y,Z or the lines of --directions FILE (exactly one of them).
std::vector<Eigen::Vector3d> directions(const Args& args) {
  if (args.has("direction") == args.has("directions")) {
    throw UsageError("give exactly one of --direction X,Y,Z and --directions FILE");
  }
  if (args.has("directions")) return recipes::read_directions_file(args.get("directions"));
  Eigen::Vector3d d;
  const std::string problem = recipes::parse_direction(args.get("direction"), d);
  if (!problem.empty()) throw UsageError("--direction " + problem);
  return {d};
}

Json vec_json(const Eigen::Vector3d& x) { return Json::array({x[0], x[1], x[2]}); }

Json ray_json(const GeodesicRay& r, const Eigen::Vector3d& asked) {
  Json end;
  end["token"] = r.end.token();
  end["face"] = r.end.face;
  end["bary"] = Json::array({r.end.bary[0], r.end.bary[1], r.end.bary[2]});
  end["vertex"] = r.end.vertex == kInvalidIndex ? Json() : Json(r.end.vertex);
  end["position"] = vec_json(r.end.position);
  Json j;
  j["direction"] = vec_json(asked);
  j["start_direction"] = vec_json(r.start_direction);
  j["length"] = r.length;
  j["points"] = r.polyline.size();
  j["hit_boundary"] = r.hit_boundary;
  j["slides"] = r.slides;
  j["end"] = end;
  j["end_direction"] = vec_json(r.end_direction);
  return j;
}

void print_text(const std::vector<GeodesicRay>& rays, double length) {
  for (std::size_t i = 0; i < rays.size(); ++i) {
    const GeodesicRay& r = rays[i];
    const Eigen::Vector3d& x = r.end.position;
    std::printf("ray %zu: length %.12g, %zu points, end %s at (%.9g %.9g %.9g)", i + 1, r.length,
                r.polyline.size(), r.end.token().c_str(), x[0], x[1], x[2]);
    if (r.end.vertex != kInvalidIndex) std::printf(" = vertex %d", r.end.vertex);
    if (r.hit_boundary) std::printf("; stopped at the boundary (%.6g of %.6g)", r.length, length);
    if (r.slides > 0) std::printf("; slid along %d boundary sides", r.slides);
    std::printf("\n");
  }
}

// Atomic in every format (path.tmp, then rename): nothing is written when a ray fails.
void write_rays(const std::string& path, const std::vector<GeodesicRay>& rays) {
  std::vector<Polyline> lines;
  for (const GeodesicRay& r : rays) lines.push_back(r.polyline);
  const std::string ext = io::file_extension(path);
  if (ext == ".ply") {
    std::vector<Polyline> kept;
    for (const Polyline& l : lines) {
      if (l.size() >= 2) kept.push_back(l);
    }
    intrinsic::write_polylines_ply(path, kept, false, "geodesic rays on the input (ifem trace)");
  } else if (ext == ".obj") {
    write_polylines_obj(path, lines, {}, "ifem trace: " + std::to_string(rays.size()) + " rays");
  } else {
    std::string out;
    for (std::size_t i = 0; i < lines.size(); ++i) {
      if (i > 0) out += '\n';
      for (const Eigen::Vector3d& x : lines[i]) {
        for (int d = 0; d < 3; ++d) {
          if (d > 0) out += ' ';
          io::detail::append_double(out, x[d]);
        }
        out += '\n';
      }
    }
    io::detail::write_file_atomically(path, out);
  }
}

int run_trace(const Args& args) {
  const recipes::GivenPoint from = from_option(args);
  const std::vector<Eigen::Vector3d> dirs = directions(args);
  const double length = args.real("length");
  const io::SurfaceInput in = read_input(args.positional()[0], args);
  const std::string problem = recipes::point_problem(from, in);
  if (!problem.empty()) throw UsageError("--from " + problem);
  const recipes::GeodesicTracer tracer(in);
  recipes::TraceGeodesicOptions options;
  options.slide_on_boundary = args.has("slide");
  std::vector<GeodesicRay> rays;
  for (std::size_t i = 0; i < dirs.size(); ++i) {
    try {
      rays.push_back(tracer.trace(from, dirs[i], length, options));
    } catch (const InvalidInput& e) {
      throw InvalidInput((dirs.size() > 1 ? "ray " + std::to_string(i + 1) + ": " : "") + e.what());
    }
  }
  if (args.has("output")) write_rays(args.get("output"), rays);
  if (args.has("json")) {
    Json j;
    j["mesh"] = args.positional()[0];
    j["from"] = args.get("from");
    j["length"] = length;
    j["output"] = args.has("output") ? Json(args.get("output")) : Json();
    j["rays"] = Json::array();
    for (std::size_t i = 0; i < rays.size(); ++i) j["rays"].push_back(ray_json(rays[i], dirs[i]));
    std::printf("%s\n", json_text(j).c_str());
    return 0;
  }
  print_text(rays, length);
  if (args.has("output")) {
    std::printf("wrote %s: %zu ray%s\n", args.get("output").c_str(), rays.size(),
                rays.size() == 1 ? "" : "s");
  }
  return 0;
}

const char* const kTraceProse =
    "Straight geodesics (the exponential map): from a point of the surface, the\n"
    "line that never turns, leaving in a given direction, for a given length. It is\n"
    "traced face by face over the input's own triangles (each face unfolded into the\n"
    "plane of the last: no flips, no mollification), so the polyline lies on the\n"
    "input and its length is the one asked, to rounding.\n\n"
    "Points (P): a vertex id (0-based, the file's order), or face:F:u:v, the point\n"
    "of face F (0-based) with barycentric coordinates (1−u−v, u, v) for its corners\n"
    "in the file's order. The direction is 3D and need not be tangent: at a face\n"
    "point it is projected onto the face's plane; at a vertex onto the plane normal\n"
    "to the angle-weighted vertex normal, where the projected edges cut the plane\n"
    "into wedges, each mapped linearly onto the corner between the same edges (a\n"
    "direction along an edge runs along it; at a flat vertex nothing changes). A\n"
    "face point at a corner is that vertex. At a boundary vertex a direction off the\n"
    "surface is refused; a direction along the normal is refused everywhere.\n\n"
    "Through a vertex the ray goes on across the fan around it (straight on at a\n"
    "flat vertex). At the boundary it stops (stdout and --json say so, with the\n"
    "length traced), or with --slide runs on along the boundary.\n\n"
    "Needs an edge-manifold, orientable triangle mesh: nonmanifold meshes (a ray has\n"
    "no single way on across an edge of 3+ faces) and point clouds are refused.\n";

const char* const kTraceEpilogue =
    "Output: stdout has one line per ray: its length, its points, its end as a point\n"
    "token (face:F:u:v, usable as --from again; '= vertex V' when it ends at one),\n"
    "and whether it stopped at the boundary. --json prints the same as one object\n"
    "(per ray: direction, start_direction (the tangent it left in), length, points,\n"
    "hit_boundary, slides, end {token, face, bary, vertex, position}, end_direction).\n"
    "Nothing is written unless every ray traces.\n\n"
    "examples:\n"
    "  ifem trace bunny.obj --from 120 --direction 1,0,0 --length 0.5 -o ray.obj\n"
    "  ifem trace bunny.obj --from face:12:0.3:0.3 --direction 0,1,1 --length 2 --json\n"
    "  ifem trace plate.obj --from 0 --directions dirs.txt --length 3 --slide -o fan.ply\n";

OptionGroup trace_options() {
  return {"Options",
          {text("from", "P").mandatory().explain("the start point (see Points)"),
           text("direction", "X,Y,Z")
               .explain("the direction to leave in (3D, any length > 0; see above)"),
           text("directions", "FILE")
               .explain("several rays from P: one direction 'X Y Z' a line ('#' comments)"),
           real("length", "L")
               .mandatory()
               .at_least(0)
               .explain("how far to go, in the mesh's length unit"),
           flag("slide").explain("at the boundary, go on along it (default: stop there)"),
           text("output", "OUT")
               .short_alias('o')
               .with_extensions({".obj", ".ply", ".txt"})
               .explain("the rays: OUT.obj ('v' lines, one 'l' line per ray), OUT.ply (ASCII:\n"
                        "vertices + 'edge' elements), OUT.txt (one 'x y z' a line, an empty\n"
                        "line between rays)"),
           flag("json").explain("one JSON object on stdout instead of text"),
           flag("quiet").explain("no progress lines on stderr")}};
}

}  // namespace

Command trace_command() {
  Command c;
  c.summary = "straight geodesics from a point in a direction (exponential map)";
  c.spec.name = "trace";
  c.spec.positionals = {"MESH"};
  c.spec.prose = kTraceProse;
  c.spec.groups = {trace_options()};
  c.spec.epilogue = kTraceEpilogue;
  c.run = run_trace;
  return c;
}

}  // namespace ifem::cli
