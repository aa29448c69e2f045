// `ifem simplify`: intrinsic simplification (intrinsic/simplify/simplify.h) of a mesh or point
// cloud to N vertices, written as a PLY over the input's positions or as the coarse intrinsic
// triangulation with its map to the input (text, 'ifem-simplify 1').
#include <cstdio>
#include <fstream>
#include <string>

#include "cli.h"
#include "fem/prolongation.h"
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

// The tangent-vector prolongation's rows: "c0 c1 c2 re0 im0 re1 im1 re2 im2" per input vertex
// (the coarse vertices of write_map() and complex weights; 0 where the weight is 0).
void write_tangent_map(const std::string& path, const PreparedSurface& ps,
                       const intrinsic::Simplification& s, Index n_rows) {
  const fem::ComplexSparseMatrix Pt = fem::tangent_prolongation(ps.tri, s);
  const Eigen::SparseMatrix<std::complex<double>, Eigen::RowMajor, int> rows(Pt);
  std::ofstream out(path);
  if (!out) throw IoError("cannot write " + path);
  out.precision(17);
  for (Index v = 0; v < n_rows; ++v) {
    const auto& p = s.fine_in_coarse[v];
    Index ids[3];
    for (int k = 0; k < 3; ++k) {
      ids[k] = p.face == kInvalidIndex ? kInvalidIndex : s.coarse.tail(3 * p.face + k);
    }
    std::complex<double> w[3] = {0.0, 0.0, 0.0};
    Index col[3] = {kInvalidIndex, kInvalidIndex, kInvalidIndex};
    int n = 0;
    for (decltype(rows)::InnerIterator it(rows, v); it && n < 3; ++it, ++n) {
      col[n] = it.col();
      w[n] = it.value();
    }
    if (p.face == kInvalidIndex) ids[0] = ids[1] = ids[2] = col[0];
    std::complex<double> wk[3] = {0.0, 0.0, 0.0};  // a repeated corner: its sum, once
    for (int k = 0; k < 3; ++k) {
      if ((k > 0 && ids[k] == ids[0]) || (k == 2 && ids[2] == ids[1])) continue;
      for (int j = 0; j < n; ++j) {
        if (col[j] == ids[k]) wk[k] = w[j];
      }
    }
    out << ids[0] << ' ' << ids[1] << ' ' << ids[2];
    for (const auto& z : wk) out << ' ' << z.real() << ' ' << z.imag();
    out << '\n';
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
  // a point cloud's cover without self-edges (a point on its own link cannot be removed: D-345)
  solvers::PrepareOptions prep = prepare_options(args);
  prep.self_edges = false;
  const PreparedSurface ps = solvers::prepare_surface(read_input(args.positional()[0], args), prep);
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
  if (args.has("tangent-map")) {
    write_tangent_map(args.get("tangent-map"), ps, s, ps.tri.n_vertices());
  }
  const auto& r = s.report;
  std::printf(
      "vertices: %d -> %d (%d removed, %d on the boundary, %d fans flattened, %d pillows "
      "deleted; %zu flips) in %.3f s\n",
      r.vertices_before, r.vertices_after, r.removals, r.boundary_removals, r.flattened, r.pillows,
      r.flips, seconds);
  if (r.stuck > 0) {
    std::printf("%d vertices above the target could not be removed (see --help)%s\n", r.stuck,
                ps.path == intrinsic::SurfacePath::kPointCloud
                    ? ": on a point cloud's cover, mostly points whose link runs between two"
                      " neighbours only (no triangulation of it without a self-edge)"
                    : "");
  }
  std::printf("area kept: largest change %.3g before the per-component rescale\n",
              r.area_change_before_rescale);
  std::printf("wrote %s\n", out.c_str());
  if (args.has("map")) std::printf("wrote %s\n", args.get("map").c_str());
  if (args.has("tangent-map")) std::printf("wrote %s\n", args.get("tangent-map").c_str());
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
      "flipped back to Delaunay. Where flips cannot make 3 faces (an angle sum of 3π or\n"
      "more, no convex flip) the vertex is flattened: its neighbours' polygon is laid\n"
      "out convex in the plane (side lengths kept, inscribed in a circle) and\n"
      "triangulated, so its angle defect moves to them. Kept vertices are input vertices;\n"
      "every removed one is tracked as a point of a coarse triangle (barycentric\n"
      "coordinates), which gives the prolongation P (input vertices × coarse vertices,\n"
      "rows ≥ 0 summing to 1) and the tangent-vector one (--tangent-map).\n\n"
      "Kept exactly: total area (one uniform rescale per component; angles unchanged),\n"
      "Gauss–Bonnet, boundary loops, and each component's Euler characteristic where no\n"
      "vertex with several fans is removed. Every coarse triangle satisfies the triangle\n"
      "inequality with a margin. Nonmanifold meshes and point clouds are simplified on\n"
      "their tufted cover: a vertex with several fans is removed from all at once, and\n"
      "pillows (a closed surface of the cover through one point, e.g. an isolated\n"
      "triangle zipped to its back) are deleted. A point cloud's cover is built here\n"
      "without self-edges (its Delaunay flips skip those; a point on its own link\n"
      "cannot be removed), so point clouds reach --ratio 0.1. Vertices that cannot be\n"
      "removed (a link that no triangulation without a self-edge replaces, a fan with a\n"
      "boundary among several) are kept and counted (docs/decisions.md D-325, D-345).\n";
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
        text("tangent-map", "TMAP.txt")
            .explain("the tangent-vector prolongation's rows: one line per input vertex\n"
                     "'c0 c1 c2 re0 im0 re1 im1 re2 im2': P's weights times the unit\n"
                     "complex number that carries a tangent vector from the coarse vertex\n"
                     "(in its angular coordinate: its reference edge at angle 0, angles\n"
                     "scaled to 2π) through the coarse triangle to the input vertex's\n"
                     "coordinate; |weights| sum to 1 (fem/prolongation.h)"),
        flag("ascii").explain("ASCII PLY instead of binary")}},
      surface_options()};
  c.run = run_simplify;
  return c;
}

}  // namespace ifem::cli
