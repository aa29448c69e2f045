// `ifem simplify`: intrinsic simplification (intrinsic/simplify/simplify.h) of a mesh or point
// cloud to N vertices, written as a PLY over the input's positions or as the coarse intrinsic
// triangulation with its map to the input (text, 'ifem-simplify 1').
#include <cstdio>
#include <fstream>
#include <string>

#include "cli.h"
#include "intrinsic/core/errors.h"
#include "intrinsic/core/timer.h"
#include "solvers/recipes/recipes.h"

namespace ifem::cli {
namespace {

bool ends_with(const std::string& s, const std::string& suffix) {
  return s.size() >= suffix.size() &&
         s.compare(s.size() - suffix.size(), suffix.size(), suffix) == 0;
}

// The coarse triangulation and its map as text (format in the --help of -o).
void write_ifem(const std::string& path, const intrinsic::Simplification& s) {
  const std::string tmp = path + ".tmp";
  {
    std::ofstream out(tmp);
    if (!out) throw IoError("cannot write " + path);
    const auto& c = s.coarse;
    out.precision(17);
    out << "ifem-simplify 1\n"
        << c.n_vertices() << ' ' << c.n_faces() << ' ' << c.multiplicity() << ' '
        << s.fine_in_coarse.size() << '\n';
    for (Index f = 0; f < c.n_faces(); ++f) {
      for (int k = 0; k < 3; ++k) {
        const Index h = 3 * f + k;
        out << c.tail(h) << ' ' << c.twin(h) << ' ' << c.halfedge_length(h)
            << (k == 2 ? '\n' : ' ');
      }
    }
    for (Index v : s.coarse_to_fine) out << v << '\n';
    for (const auto& p : s.fine_in_coarse) {
      out << p.face << ' ' << p.bary[0] << ' ' << p.bary[1] << ' ' << p.bary[2] << '\n';
    }
    if (!out) throw IoError("cannot write " + path);
  }
  if (std::rename(tmp.c_str(), path.c_str()) != 0) throw IoError("cannot write " + path);
}

// The coarse faces over the input's positions; vertex property 'input_vertex' (the input id of
// each coarse vertex).
void write_coarse_ply(const std::string& path, const PreparedSurface& ps,
                      const intrinsic::Simplification& s, bool binary) {
  const auto& c = s.coarse;
  Positions pos(c.n_vertices(), 3);
  Eigen::VectorXd id(c.n_vertices());
  for (Index v = 0; v < c.n_vertices(); ++v) {
    const Index fine = s.coarse_to_fine[v];
    pos.row(v).setZero();
    if (fine < ps.n_input_vertices()) pos.row(v) = ps.input.positions.row(fine);
    id[v] = fine;
  }
  std::vector<Triangle> faces(c.n_faces());
  for (Index f = 0; f < c.n_faces(); ++f)
    faces[f] = {c.tail(3 * f), c.tail(3 * f + 1), c.tail(3 * f + 2)};
  io::write_ply(path, pos, faces, {{"input_vertex", id}}, binary);
}

// P's rows: one line per input vertex, "c0 c1 c2 w0 w1 w2" (coarse vertex ids and weights).
void write_map(const std::string& path, const intrinsic::Simplification& s, Index n_rows) {
  std::ofstream out(path);
  if (!out) throw IoError("cannot write " + path);
  out.precision(17);
  std::vector<Index> coarse_of(s.fine_in_coarse.size(), kInvalidIndex);
  for (Index c = 0; c < Index(s.coarse_to_fine.size()); ++c) coarse_of[s.coarse_to_fine[c]] = c;
  for (Index v = 0; v < n_rows; ++v) {
    const auto& p = s.fine_in_coarse[v];
    if (p.face == kInvalidIndex) {
      out << coarse_of[v] << ' ' << coarse_of[v] << ' ' << coarse_of[v] << " 1 0 0\n";
      continue;
    }
    for (int k = 0; k < 3; ++k) out << s.coarse.tail(3 * p.face + k) << ' ';
    out << p.bary[0] << ' ' << p.bary[1] << ' ' << p.bary[2] << '\n';
  }
  if (!out) throw IoError("cannot write " + path);
}

int run_simplify(const Args& args) {
  if (args.has("vertices") == args.has("ratio")) {
    throw UsageError("give exactly one of --vertices N and --ratio R");
  }
  const std::string out = args.get("output");
  if (!ends_with(out, ".ply") && !ends_with(out, ".ifem")) {
    throw UsageError("-o " + out + ": the output is FILE.ply or FILE.ifem");
  }
  const PreparedSurface ps = prepare_surface(args.positional()[0], args);
  intrinsic::SimplifyOptions o;
  if (args.has("vertices")) o.target_vertices = args.count("vertices");
  if (args.has("ratio")) o.ratio = args.real("ratio");
  if (o.target_vertices >= ps.tri.n_vertices()) {
    throw UsageError("--vertices " + std::to_string(o.target_vertices) +
                     " must be below the input's " + std::to_string(ps.tri.n_vertices()) +
                     " vertices");
  }
  o.on_progress = progress_bar(args);
  Stopwatch watch;
  const intrinsic::Simplification s = recipes::simplify(ps, o);
  const double seconds = watch.restart();
  if (ends_with(out, ".ifem")) {
    write_ifem(out, s);
  } else {
    write_coarse_ply(out, ps, s, !args.has("ascii"));
  }
  if (args.has("map")) write_map(args.get("map"), s, ps.tri.n_vertices());
  const auto& r = s.report;
  std::printf("vertices: %d -> %d (%d removed, %d on the boundary; %zu flips) in %.3f s\n",
              r.vertices_before, r.vertices_after, r.removals, r.boundary_removals, r.flips,
              seconds);
  if (r.stuck > 0) {
    std::printf("%d vertices above the target could not be removed (see --help)%s\n", r.stuck,
                ps.path == intrinsic::SurfacePath::kPointCloud
                    ? ": a point cloud's points have many fans, some wound around the point"
                      " more than once"
                    : "");
  }
  std::printf("area kept: largest change %.3g before the per-component rescale\n",
              r.area_change_before_rescale);
  std::printf("wrote %s\n", out.c_str());
  if (args.has("map")) std::printf("wrote %s\n", args.get("map").c_str());
  return 0;
}

}  // namespace

Command simplify_command() {
  Command c;
  c.summary = "intrinsic simplification to N vertices, with the map from the input";
  c.spec.name = "simplify";
  c.spec.positionals = {"MESH"};
  c.spec.prose =
      "Coarsens the intrinsic Delaunay triangulation of MESH to N vertices by intrinsic\n"
      "vertex removal: the cheapest vertex (star area × (|angle defect| + 4π / area)) is\n"
      "flipped to degree 3 (an ear on the boundary) and removed, then the new sides are\n"
      "flipped back to Delaunay. Kept vertices are input vertices; every removed one is\n"
      "tracked as a point of a coarse triangle (barycentric coordinates), which gives the\n"
      "prolongation P (input vertices × coarse vertices, rows ≥ 0 summing to 1).\n\n"
      "Kept exactly: each component's Euler characteristic, boundary loops and total\n"
      "area (one uniform rescale per component; angles unchanged). Every coarse triangle\n"
      "satisfies the triangle inequality with a margin. Vertices that cannot be removed\n"
      "that way (several fans on a nonmanifold input, no convex flips) are kept and\n"
      "counted. Nonmanifold meshes and point clouds are simplified on their tufted cover.\n"
      "Point clouds coarsen little (about 5–20 % removed): on their cover a point has\n"
      "many fans, some wound around it more than once (angle sum ≥ 3π, which no three\n"
      "faces can replace without moving lengths) (docs/decisions.md D-290).\n";
  c.spec.groups = {
      {"Options",
       {count("vertices", "N").above(0).explain("stop at N vertices (below the input's count)"),
        real("ratio", "R").above(0).at_most(1).explain("keep the fraction R of the vertices"),
        text("output", "OUT")
            .short_alias('o')
            .mandatory()
            .with_extensions({".ply", ".ifem"})
            .explain("OUT.ply: the coarse triangles over the input positions of the kept\n"
                     "vertices (the intrinsic triangles drawn straight), vertex property\n"
                     "'input_vertex' (0-based input id); on the tufted cover both copies\n"
                     "of each face.\n"
                     "OUT.ifem: text 'ifem-simplify 1': a line '#Vc #F multiplicity #V',\n"
                     "#F lines 'tail twin length' ×3 (halfedge 3f+s, twin −1 on the\n"
                     "boundary), #Vc lines: the input vertex of each coarse vertex, #V\n"
                     "lines 'face b0 b1 b2': each input vertex in a coarse face (−1 when\n"
                     "unreferenced)"),
        text("map", "MAP.txt")
            .explain("P's rows: one line per input vertex 'c0 c1 c2 w0 w1 w2' (coarse\n"
                     "vertex ids, 0-based, and weights)"),
        flag("ascii").explain("ASCII PLY instead of binary")}},
      surface_options()};
  c.run = run_simplify;
  return c;
}

}  // namespace ifem::cli
