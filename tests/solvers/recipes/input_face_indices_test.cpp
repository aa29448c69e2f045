// A field's singularities on the input's own faces (solvers/recipes/tangent_fields.h,
// input_face_indices()): Poincaré–Hopf on the input faces of a sphere (2n) and a torus (0) after
// intrinsic flips, refinement and curves; the same as the intrinsic faces' where nothing was
// flipped; next to the intrinsic singularities; written as a PLY face property and read back.
#include <gtest/gtest.h>

#include <cmath>
#include <complex>
#include <filesystem>
#include <random>
#include <string>
#include <utility>
#include <vector>

#include "intrinsic/io/mesh_io.h"
#include "solvers/recipes/curve_fields.h"
#include "solvers/recipes/tangent_fields.h"
#include "solvers/test_util.h"

namespace ifem::solvers {
namespace {

using intrinsic::kPi;

// A torus (radii 1 and 0.4) from a nu×nv grid, each quad split along a diagonal.
intrinsic::TriangleMesh torus(int nu, int nv) {
  intrinsic::TriangleMesh m;
  m.positions.resize(nu * nv, 3);
  auto id = [&](int i, int j) { return Index((j % nv) * nu + (i % nu)); };
  for (int j = 0; j < nv; ++j) {
    for (int i = 0; i < nu; ++i) {
      const double u = 2 * kPi * i / nu, v = 2 * kPi * j / nv;
      m.positions.row(id(i, j)) << (1 + 0.4 * std::cos(v)) * std::cos(u),
          (1 + 0.4 * std::cos(v)) * std::sin(u), 0.4 * std::sin(v);
      m.faces.push_back({id(i, j), id(i + 1, j), id(i + 1, j + 1)});
      m.faces.push_back({id(i, j), id(i + 1, j + 1), id(i, j + 1)});
    }
  }
  return m;
}

int total(const Eigen::VectorXi& index) { return index.size() ? index.sum() : -999; }

struct Surface {
  const char* name;
  intrinsic::TriangleMesh mesh;
  int chi;
};

class InputFaceIndices : public ::testing::TestWithParam<int> {};

// After flips (needles at a UV sphere's poles, a jittered torus) and after refinement, the
// input faces' indices still sum to n·χ: the flipped-away references are accounted for.
TEST_P(InputFaceIndices, SumToNChiAfterFlipsAndRefinement) {
  const int n = GetParam();
  const std::vector<Surface> surfaces = {
      {"jittered uv sphere", test::jittered(intrinsic::uv_sphere(12, 40), 0.05), 2},
      {"jittered torus", test::jittered(torus(36, 12), 0.03), 0}};
  for (const Surface& m : surfaces) {
    for (const bool refine : {false, true}) {
      SCOPED_TRACE(std::string(m.name) + (refine ? ", refined" : ""));
      PrepareOptions o;
      if (refine) o.refine = SurfaceRefineOptions{};
      const PreparedSurface s = prepare_surface(test::as_input(m.mesh), o);
      ASSERT_EQ(s.path, intrinsic::SurfacePath::kManifold);
      EXPECT_GT(s.flips.flips, 0u);
      EXPECT_EQ(s.integer.has_value(), refine);  // the default correspondence (D-330)
      FieldOptions settings;
      settings.symmetry = n;
      const TangentFieldResult r = direction_field_on(s, settings);
      ASSERT_EQ(r.face_singularity.size(), Eigen::Index(m.mesh.faces.size()));
      EXPECT_EQ(total(r.face_singularity), n * m.chi);
      EXPECT_EQ(r.total_index, n * m.chi);
      // a smoothest field has few singularities, on the input faces as on the intrinsic ones
      EXPECT_LE(r.face_singularity.cwiseAbs().sum(), r.singular_faces + 4 * n);
    }
  }
}

INSTANTIATE_TEST_SUITE_P(DirectionField, InputFaceIndices, ::testing::Values(1, 2, 4));

// Without flips (an icosphere is Delaunay already, and --no-delaunay), the input faces are the
// intrinsic faces and so are their indices.
TEST(InputFaceIndices, EqualTheIntrinsicOnesWithoutFlips) {
  PrepareOptions o;
  o.intrinsic_delaunay = false;
  const PreparedSurface s =
      prepare_surface(test::as_input(test::jittered(intrinsic::icosphere(5), 0.02)), o);
  ASSERT_EQ(s.flips.flips, 0u);
  const fem::TangentFrames frames = fem::tangent_frames(s.tri);
  for (const int n : {1, 4}) {
    DirectionFieldOptions d;
    d.symmetry = n;
    const DirectionField f = smoothest_field(s.tri, frames, d);
    const Eigen::VectorXi intrinsic_index = face_indices(s.tri, frames, f.u, n);
    const Eigen::VectorXi input_index = input_face_indices(s, frames, f.u, n);
    EXPECT_EQ(input_index, intrinsic_index) << n;
    EXPECT_EQ(total(input_index), 2 * n);
  }
}

// On a plane both triangulations' angular coordinates are exact in space, so a field given in
// space can be put on the intrinsic Delaunay triangulation and on the input triangulation
// independently: the input faces' indices computed from the former (turned through the
// signposts rebuilt for it) must be those of the latter, face by face, although flips took
// most vertices' reference halfedges away (wrong turns show up as ± pairs for n = 2, 4).
TEST(InputFaceIndices, MatchTheInputTriangulationsOwnOnAPlane) {
  const int n_cells = 16;
  // interior vertices jittered in the plane (the boundary stays a square, without obtuse angles
  // at boundary edges: the manifold path)
  const intrinsic::TriangleMesh grid = intrinsic::grid(n_cells, n_cells);
  intrinsic::TriangleMesh m = test::jittered(grid, 0.6 / n_cells, 5);
  m.positions.col(2).setZero();
  for (Index v = 0; v < Index(m.positions.rows()); ++v) {
    const Eigen::RowVector3d p = grid.positions.row(v);
    if (p.head<2>().minCoeff() <= 0.0 || p.head<2>().maxCoeff() >= 1.0) m.positions.row(v) = p;
  }
  PrepareOptions o;
  o.mollify_relative_epsilon = 0.0;
  const PreparedSurface s = prepare_surface(test::as_input(m), o);
  ASSERT_EQ(s.path, intrinsic::SurfacePath::kManifold);
  ASSERT_GT(s.flips.flips, 50u);
  const auto input = intrinsic::IntrinsicTriangulation::from_positions(m.faces, m.positions);
  Index moved = 0;  // vertices whose reference halfedge is no longer the input's
  for (Index v = 0; v < s.tri.n_vertices(); ++v) {
    const Index a = input.vertex_halfedge(v), b = s.tri.vertex_halfedge(v);
    moved += input.head(a) != s.tri.head(b) ||
             input.length(input.edge(a)) != s.tri.length(s.tri.edge(b));
  }
  EXPECT_GT(moved, 20);
  const fem::TangentFrames frames = fem::tangent_frames(s.tri);
  const fem::TangentFrames input_frames = fem::tangent_frames(input);
  const TangentBasis3d basis = tangent_basis_3d(s.input, s.tri, frames);
  const TangentBasis3d input_basis =
      tangent_basis_3d(m.positions, m.faces, Eigen::MatrixX3d(), input, input_frames);
  // index +1 about (0.3, 0.4), −1 about (0.7, 0.55), turning with the position elsewhere
  auto field = [&](const TangentBasis3d& b, Index v, int n) {
    const Eigen::Vector3d p = m.positions.row(v).transpose();
    const double t = std::atan2(p.y() - 0.4, p.x() - 0.3) - std::atan2(p.y() - 0.55, p.x() - 0.7) +
                     2.0 * p.x() * p.y();
    const Eigen::Vector3d x(std::cos(t), std::sin(t), 0.0);
    return std::pow(std::complex<double>(x.dot(b.e1.row(v)), x.dot(b.e2.row(v))), n);
  };
  for (const int n : {1, 2, 4}) {
    Eigen::VectorXcd u(s.tri.n_vertices()), u_input(input.n_vertices());
    for (Index v = 0; v < s.tri.n_vertices(); ++v) u[v] = field(basis, v, n);
    for (Index v = 0; v < input.n_vertices(); ++v) u_input[v] = field(input_basis, v, n);
    const Eigen::VectorXi expected = face_indices(input, input_frames, u_input, n);
    const Eigen::VectorXi got = input_face_indices(s, frames, u, n);
    ASSERT_EQ(got.size(), expected.size()) << n;
    EXPECT_EQ(got, expected) << n;
    // the two singularities inside, and the square's corners (a boundary that turns)
    EXPECT_GE(expected.cwiseAbs().sum(), 2 * n) << n;
  }
}

// Refined with integer coordinates, the input vertices' turn from the input's reference
// halfedge to the refined triangulation's comes from the integers: the same per-face indices as
// with signposts, for a field with singularities nearly everywhere (a wrong turn at one vertex
// changes its faces' indices), on a closed surface with needles and on a plane with boundary.
TEST(InputFaceIndices, IntegerCoordinatesGiveTheSignpostsIndices) {
  intrinsic::TriangleMesh plane = test::jittered(intrinsic::grid(12, 12), 0.4 / 12, 3);
  plane.positions.col(2).setZero();
  const std::vector<std::pair<const char*, intrinsic::TriangleMesh>> meshes = {
      {"jittered uv sphere", test::jittered(intrinsic::uv_sphere(10, 30), 0.05)},
      {"jittered plane", plane}};
  for (const auto& [name, m] : meshes) {
    PrepareOptions o;
    o.refine = SurfaceRefineOptions{};
    o.refine->resolution = 0.7;
    o.refine->correspondence = intrinsic::Correspondence::kSignposts;
    const PreparedSurface sp = prepare_surface(test::as_input(m), o);
    o.refine->correspondence = intrinsic::Correspondence::kInteger;
    const PreparedSurface si = prepare_surface(test::as_input(m), o);
    ASSERT_TRUE(sp.signposts && si.integer) << name;
    ASSERT_EQ(sp.tri.lengths(), si.tri.lengths()) << name;
    const fem::TangentFrames frames = fem::tangent_frames(si.tri);
    Index turned = 0;  // input vertices whose reference halfedge is no longer an input edge
    for (Index v = 0; v < si.n_input_vertices(); ++v) {
      turned += si.integer->normal_coordinate(si.tri.edge(si.tri.vertex_halfedge(v))) >= 0;
    }
    EXPECT_GT(turned, 20) << name;
    std::mt19937 rng(7);
    std::uniform_real_distribution<double> angle(-kPi, kPi);
    for (const int n : {1, 2, 4}) {
      Eigen::VectorXcd u(si.tri.n_vertices());
      for (Index v = 0; v < si.tri.n_vertices(); ++v) u[v] = std::polar(1.0, angle(rng));
      const Eigen::VectorXi a = input_face_indices(sp, frames, u, n);
      const Eigen::VectorXi b = input_face_indices(si, frames, u, n);
      ASSERT_EQ(a.size(), Eigen::Index(m.faces.size())) << name;
      EXPECT_GT(a.cwiseAbs().sum(), Index(m.faces.size()) / 8) << name;  // ~20% singular
      EXPECT_EQ(a, b) << name << ", n = " << n;
    }
  }
}

// The singular input faces sit where the intrinsic singularities are: each within two mean
// edge lengths of a singular intrinsic face (the field is the same; only the faces differ).
TEST(InputFaceIndices, SitNextToTheIntrinsicSingularities) {
  const intrinsic::TriangleMesh m = test::jittered(intrinsic::uv_sphere(16, 48), 0.01);
  const PreparedSurface s = prepare_surface(test::as_input(m));
  ASSERT_GT(s.flips.flips, 100u);  // many references flipped away
  const fem::TangentFrames frames = fem::tangent_frames(s.tri);
  DirectionFieldOptions d;
  d.symmetry = 4;
  const DirectionField f = smoothest_field(s.tri, frames, d);
  const Eigen::VectorXi at_input = input_face_indices(s, frames, f.u, 4);
  const Eigen::VectorXi at_tri = face_indices(s.tri, frames, f.u, 4);
  auto centre = [&](const Triangle& t) {
    return Eigen::Vector3d((m.positions.row(t[0]) + m.positions.row(t[1]) + m.positions.row(t[2])) /
                           3.0);
  };
  std::vector<Eigen::Vector3d> singular;
  for (Index face = 0; face < s.tri.n_faces(); ++face) {
    if (at_tri[face] == 0) continue;
    singular.push_back(
        centre({s.tri.tail(3 * face), s.tri.tail(3 * face + 1), s.tri.tail(3 * face + 2)}));
  }
  ASSERT_FALSE(singular.empty());
  for (std::size_t face = 0; face < m.faces.size(); ++face) {
    if (at_input[Eigen::Index(face)] == 0) continue;
    double nearest = 1e300;
    for (const Eigen::Vector3d& c : singular)
      nearest = std::min(nearest, (c - centre(m.faces[face])).norm());
    EXPECT_LT(nearest, 2.0 * s.input_mean_edge_length) << "input face " << face;
  }
  EXPECT_EQ(total(at_input), 8);
}

// With curves (signposts from the curve insertion, FlipOut flips and inserted Bézier vertices).
TEST(InputFaceIndices, SumToNChiWithCurves) {
  const intrinsic::TriangleMesh m = intrinsic::icosphere(6);
  CurveCondition bezier;
  bezier.vertices = {0, 17, 100, 250};
  bezier.shape = intrinsic::CurveShape::kBezier;
  const CurveSurface s = prepare_curve_surface(test::as_input(m), {bezier});
  EXPECT_GT(s.surface.tri.n_vertices(), s.n_input_vertices());
  for (const int n : {1, 4}) {
    FieldOptions settings;
    settings.symmetry = n;
    const TangentFieldResult r = curve_direction_field(s, settings);
    EXPECT_EQ(total(r.face_singularity), 2 * n) << n;
  }
}

// The CLI's .ply: the per-face property next to the vertex ones, read back by the repo's reader.
TEST(InputFaceIndices, PlyFacePropertyReadsBack) {
  const intrinsic::TriangleMesh m = intrinsic::uv_sphere(10, 30);
  const PreparedSurface s = prepare_surface(test::as_input(m));
  FieldOptions settings;
  settings.symmetry = 2;
  const TangentFieldResult r = direction_field_on(s, settings);
  const std::string path =
      (std::filesystem::temp_directory_path() / "ifem_input_face_indices.ply").string();
  io::write_ply(path, m.positions, m.faces, {{"singularity", r.singularity}},
                {{"singularity", r.face_singularity.cast<double>()}});
  const io::SurfaceInput back = io::read_surface(path);
  std::filesystem::remove(path);
  ASSERT_EQ(back.face_properties.size(), 1u);
  EXPECT_EQ(back.face_properties[0].name, "singularity");
  ASSERT_EQ(back.face_properties[0].values.size(), Eigen::Index(m.faces.size()));
  EXPECT_EQ(back.face_properties[0].values.sum(), 4.0);
  EXPECT_EQ(back.face_properties[0].values, r.face_singularity.cast<double>());
}

}  // namespace
}  // namespace ifem::solvers
