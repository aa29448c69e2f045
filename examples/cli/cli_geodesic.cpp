// `ifem geodesic`: a geodesic path through given vertices by FlipOut (edge flips on a signpost
// intrinsic triangulation), written as an OBJ polyline on the input surface.
#include <cstdio>
#include <fstream>
#include <string>
#include <vector>

#include "cli.h"
#include "intrinsic/core/errors.h"
#include "intrinsic/core/timer.h"
#include "intrinsic/geodesic/flip_geodesic.h"
#include "results.h"

namespace ifem::cli {
namespace {

using intrinsic::EdgePath;
using intrinsic::FlipOutReport;
using intrinsic::SignpostTriangulation;

// Atomic (path.tmp, then rename): no partial file on an error.
void write_polyline_obj(const std::string& path, const std::vector<Eigen::Vector3d>& line) {
  const std::string tmp = path + ".tmp";
  std::ofstream f(tmp);
  if (!f) throw IoError(path + ": cannot open for writing");
  f.precision(17);
  f << "# ifem geodesic: " << line.size() << " points\n";
  for (const Eigen::Vector3d& p : line) f << "v " << p[0] << ' ' << p[1] << ' ' << p[2] << '\n';
  f << 'l';
  for (std::size_t i = 0; i < line.size(); ++i) f << ' ' << i + 1;
  f << '\n';
  f.close();
  if (!f || std::rename(tmp.c_str(), path.c_str()) != 0) {
    std::remove(tmp.c_str());
    throw IoError(path + ": write failed");
  }
}

// Shortens the edge path between two waypoints and appends its trace to `line` (traced right
// away: later segments flip edges this one used).
double add_segment(SignpostTriangulation& st, Index a, Index b, const Args& args,
                   std::vector<Eigen::Vector3d>* line) {
  EdgePath path = intrinsic::shortest_edge_path(st, a, b);
  const FlipOutReport rep = intrinsic::shorten(st, path);
  const std::vector<Eigen::Vector3d> seg = intrinsic::path_polyline(st, path);
  line->insert(line->end(), seg.begin() + (line->empty() ? 0 : 1), seg.end());
  progress(args,
           std::to_string(a) + " → " + std::to_string(b) + ": edge path " +
               format_number(rep.initial_length) + " → geodesic " +
               format_number(rep.final_length) + " (" + std::to_string(rep.flips) + " flips, " +
               std::to_string(rep.iterations) + " reroutes" +
               (rep.stopped_by == intrinsic::FlipOutStop::kConverged ? "" : ", not converged") +
               ")");
  return rep.final_length;
}

int run(const Args& args) {
  const std::string out = result_output(args).path;  // checked before any computation
  const std::vector<Index> through = args.vertices("path");
  if (through.size() < 2) throw UsageError("--path needs at least two vertices");
  const io::SurfaceInput in = read_input(args.positional()[0], args);
  if (!in.has_faces()) throw UsageError("geodesic needs a triangle mesh (the input has no faces)");
  const Stopwatch watch;
  SignpostTriangulation st(in.triangles, in.positions, args.real("mollify"));
  std::vector<Eigen::Vector3d> line;
  double length = 0.0;
  for (std::size_t k = 0; k + 1 < through.size(); ++k) {
    length += add_segment(st, through[k], through[k + 1], args, &line);
  }
  write_polyline_obj(out, line);
  std::printf("wrote %s: %zu points, length %.9g (%.3g s)\n", out.c_str(), line.size(), length,
              watch.seconds());
  return 0;
}

}  // namespace

Command geodesic_command() {
  Command c;
  c.summary = "geodesic path through given vertices (FlipOut edge flips)";
  c.spec.name = "geodesic";
  c.spec.positionals = {"MESH"};
  c.spec.prose =
      "A locally shortest (geodesic) path through the given vertices, in order, by\n"
      "FlipOut (Sharp & Crane 2020): a shortest edge path (Dijkstra) between each two\n"
      "consecutive vertices, shortened by intrinsic edge flips until it bends by no\n"
      "less than π on either side at every vertex it passes, then traced over the\n"
      "input surface. The given vertices stay on the path (it may bend there). Needs\n"
      "an edge-manifold, orientable triangle mesh.\n";
  c.spec.groups = {
      {"Options",
       {vertex_list("path", "V0,V1[,V2,...]")
            .mandatory()
            .explain("0-based vertex ids of the input the path runs through, in order"),
        text("output", "OUT")
            .short_alias('o')
            .mandatory()
            .with_extensions({".obj"})
            .explain("OUT.obj: the path's points on the surface ('v' lines) and one 'l' line"),
        real("mollify", "F")
            .at_least(0)
            .at_most(1)
            .defaults_to(format_number(intrinsic::kDefaultMollifyEpsilon))
            .explain("relative mollification margin (as other commands' --mollify)"),
        flag("quiet").explain("no progress lines on stderr")}}};
  c.spec.epilogue = "example: ifem geodesic bunny.obj --path 0,500,1200 -o path.obj\n";
  c.run = run;
  return c;
}

}  // namespace ifem::cli
