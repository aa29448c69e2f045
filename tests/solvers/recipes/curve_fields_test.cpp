// Direction fields aligned to curves (solvers/recipes/curve_fields.h): on a flat cylinder a
// straight curve makes the field parallel to it everywhere; on a flat disk a loop through equally
// spaced points of a circle holds the field tangent to the circle there, exactly; bad input.
#include "solvers/recipes/curve_fields.h"

#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <cmath>
#include <complex>
#include <random>
#include <string>
#include <vector>

#include "intrinsic/core/errors.h"
#include "solvers/test_util.h"

namespace ifem::solvers {
namespace {

using Complex = std::complex<double>;
using intrinsic::kPi;

// A prism tube of `around` sides and `rows` rows of rectangles (each split along a diagonal),
// radius 1, height 2: intrinsically a flat cylinder whose boundary vertices have angle π, so
// its connection is trivial. The interior rows but the middle one are moved along the tube's
// axis at random, which keeps every vertex on its generator line, hence the surface the same flat
// cylinder. Vertex (i, j) is j·around + i.
io::SurfaceInput flat_tube(int around, int rows) {
  io::SurfaceInput in;
  in.positions.resize(around * (rows + 1), 3);
  std::mt19937 rng(3);
  std::uniform_real_distribution<double> jitter(-0.3, 0.3);
  for (int j = 0; j <= rows; ++j) {
    for (int i = 0; i < around; ++i) {
      const double t = 2.0 * kPi * i / around;
      const bool moved = j > 0 && j < rows && j != rows / 2;
      const double z = 2.0 * (j + (moved ? jitter(rng) : 0.0)) / rows;
      in.positions.row(j * around + i) << std::cos(t), std::sin(t), z;
    }
  }
  auto id = [around](int i, int j) { return Index(j * around + (i % around)); };
  for (int j = 0; j < rows; ++j) {
    for (int i = 0; i < around; ++i) {
      in.triangles.push_back({id(i, j), id(i + 1, j), id(i + 1, j + 1)});
      in.triangles.push_back({id(i, j), id(i + 1, j + 1), id(i, j + 1)});
    }
  }
  return in;
}

// A flat disk of radius 1: a centre and `rings` concentric rings, ring k with 6k equally spaced
// vertices at radius k / rings, consecutive rings zipped into triangles by angle. Ring k's
// vertex j is 1 + 3k(k − 1) + j.
io::SurfaceInput flat_disk(int rings) {
  io::SurfaceInput in;
  auto first = [](int k) { return k == 0 ? Index(0) : Index(1 + 3 * k * (k - 1)); };
  auto count = [](int k) { return k == 0 ? 1 : 6 * k; };
  in.positions.resize(first(rings + 1), 3);
  for (int k = 0; k <= rings; ++k) {
    for (int j = 0; j < count(k); ++j) {
      const double t = 2.0 * kPi * j / count(k), r = double(k) / rings;
      in.positions.row(first(k) + j) << r * std::cos(t), r * std::sin(t), 0.0;
    }
  }
  for (int k = 1; k <= rings; ++k) {
    const int mi = count(k - 1), mo = count(k);
    auto inner = [&](int a) { return first(k - 1) + a % mi; };
    auto outer = [&](int b) { return first(k) + b % mo; };
    for (int a = 0, b = 0; a < mi || b < mo;) {
      // advance on the ring whose next vertex comes first counter-clockwise
      if (b < mo && (a == mi || (b + 1) * mi <= (a + 1) * mo)) {
        in.triangles.push_back({inner(a), outer(b), outer(b + 1)});
        ++b;
      } else {
        in.triangles.push_back({inner(a), outer(b), inner(a + 1)});
        ++a;
      }
    }
  }
  return in;
}

CurveSurfaceOptions exact() {
  CurveSurfaceOptions o;
  o.mollify_relative_epsilon = 0.0;
  return o;
}

CurveCondition curve(std::vector<Index> vertices, intrinsic::CurveShape shape) {
  CurveCondition c;
  c.vertices = std::move(vertices);
  c.shape = shape;
  return c;
}

// The largest change of the field along an edge relative to parallel transport (0: parallel).
double max_parallel_defect(const intrinsic::IntrinsicTriangulation& tri,
                           const fem::TangentFrames& frames, const Eigen::VectorXd& angle, int n) {
  double worst = 0.0;
  for (Index h = 0; h < tri.n_halfedges(); ++h) {
    const Complex ui = std::polar(1.0, n * angle[tri.tail(h)]);
    const Complex uj = std::polar(1.0, n * angle[tri.head(h)]);
    worst = std::max(worst, std::abs(uj - std::pow(frames.transport[h], n) * ui));
  }
  return worst;
}

// The largest difference, in the n-th power, between the field and the curve's direction at the
// curve's vertices (the curve's halfedges' directions at their tails).
double max_off_curve(const CurveSurface& s, const fem::TangentFrames& frames,
                     const Eigen::VectorXd& angle, int n) {
  double worst = 0.0;
  const intrinsic::CurveChain ch = intrinsic::curve_chain(s.surface.tri, s.network, 0);
  for (std::size_t i = 0; i < ch.edges.size(); ++i) {
    const Index h = ch.left_halfedges[i];
    const double along = frames.halfedge_angle[h];
    worst = std::max(
        worst, std::abs(std::polar(1.0, n * angle[ch.vertices[i]]) - std::polar(1.0, n * along)));
  }
  return worst;
}

struct TubeCase {
  const char* name;
  bool around;  // a loop around the tube (else a path along a generator line)
};

class StraightCurveOnAFlatTube : public ::testing::TestWithParam<TubeCase> {};

// Nothing but the curve holds the field, and the cylinder's connection is trivial: the field
// is the curve's direction carried everywhere, parallel (to the solver's rounding).
TEST_P(StraightCurveOnAFlatTube, FieldIsParallelToTheCurveEverywhere) {
  const int around = 12, rows = 8;
  std::vector<Index> ids;
  if (GetParam().around) {
    for (int i = 0; i < around; i += 3) ids.push_back(Index(rows / 2 * around + i));
  } else {
    ids = {0, Index(rows * around)};
  }
  const auto shape =
      GetParam().around ? intrinsic::CurveShape::kLoop : intrinsic::CurveShape::kPath;
  const CurveSurface s =
      prepare_curve_surface(flat_tube(around, rows), {curve(ids, shape)}, exact());
  const intrinsic::CurveChain ch = intrinsic::curve_chain(s.surface.tri, s.network, 0);
  ASSERT_EQ(ch.edges.size(), std::size_t(GetParam().around ? around : rows));
  ASSERT_EQ(s.surface.tri.n_vertices(), s.n_input_vertices());  // nothing inserted
  const fem::TangentFrames frames = fem::tangent_frames(s.surface.tri);
  for (const int n : {1, 2, 4}) {
    FieldOptions settings;
    settings.symmetry = n;
    const TangentFieldResult r = curve_direction_field(s, settings);
    EXPECT_EQ(r.constrained, Index(GetParam().around ? around : rows + 1)) << n;
    EXPECT_LT(max_parallel_defect(s.surface.tri, frames, r.angle, n), 1e-10) << n;
    EXPECT_LT(max_off_curve(s, frames, r.angle, n), 1e-12) << n;
    EXPECT_EQ(r.singular_faces, 0) << n;
    EXPECT_EQ(r.total_index, 0) << n;  // χ = 0
    EXPECT_LT(r.energy, 1e-12) << n;   // rounding (~1e-16); a turn of 1e-3 rad per edge: ~1e-4
  }
  // n = 1 points the way the curve runs: reversed, every vector turns around
  std::vector<Index> reversed(ids.rbegin(), ids.rend());
  const CurveSurface back =
      prepare_curve_surface(flat_tube(around, rows), {curve(reversed, shape)}, exact());
  const TangentFieldResult forward = curve_direction_field(s, {});
  const TangentFieldResult backward = curve_direction_field(back, {});
  EXPECT_LT((forward.vectors + backward.vectors).cwiseAbs().maxCoeff(), 1e-9);
}

INSTANTIATE_TEST_SUITE_P(CurveFields, StraightCurveOnAFlatTube,
                         ::testing::Values(TubeCase{"generator", false}, TubeCase{"ring", true}),
                         [](const ::testing::TestParamInfo<TubeCase>& p) {
                           return std::string(p.param.name);
                         });

// A loop through the equally spaced vertices of a circle: at each, the mean of the chord leaving
// and the continuation of the chord arriving is the circle's tangent (by symmetry), and the 3D
// vectors are exact on a planar mesh. The rest of the disk follows smoothly.
TEST(CurveFields, CircleHoldsTheFieldTangentAtItsVertices) {
  const int rings = 8, k = 5;  // the loop runs through ring 5's 30 vertices
  io::SurfaceInput in = flat_disk(rings);
  const Eigen::MatrixX3d P = in.positions;
  std::vector<Index> ids;
  for (int j = 0; j < 6 * k; j += 2) ids.push_back(Index(1 + 3 * k * (k - 1) + j));
  const CurveSurface s =
      prepare_curve_surface(std::move(in), {curve(ids, intrinsic::CurveShape::kLoop)}, exact());
  const intrinsic::CurveChain ch = intrinsic::curve_chain(s.surface.tri, s.network, 0);
  ASSERT_EQ(ch.vertices.size(), ids.size() + 1);  // straight chords between the given vertices
  for (const int n : {1, 2, 4}) {
    FieldOptions settings;
    settings.symmetry = n;
    const TangentFieldResult r = curve_direction_field(s, settings);
    double worst = 0.0;
    for (const Index v : ids) {
      const Eigen::Vector3d x = r.vectors.row(v).transpose();
      const Eigen::Vector3d tangent(-P(v, 1), P(v, 0), 0.0);  // counter-clockwise
      const double turn = std::atan2(tangent.cross(x).z(), tangent.dot(x));
      worst = std::max(worst, std::abs(std::polar(1.0, n * turn) - 1.0));
      if (n == 1) {
        EXPECT_GT(tangent.dot(x), 0.0) << "the loop runs counter-clockwise";
      }
      EXPECT_NEAR(x.norm(), 1.0, 1e-12);
    }
    EXPECT_LT(worst, 1e-9) << n;
    EXPECT_EQ(r.total_index, n) << n;  // the disk's boundary is free: the field is smooth
  }
}

TEST(CurveFields, CombinesWithDirectionsAndTheBoundary) {
  const CurveSurface s = prepare_curve_surface(
      flat_disk(6),
      {curve({Index(1 + 3 * 3 * 2), Index(1 + 3 * 3 * 2 + 3)}, intrinsic::CurveShape::kPath)},
      exact());
  FieldOptions settings;
  settings.symmetry = 4;
  settings.align_boundary = true;
  settings.constraints = {{0, Eigen::Vector3d(1, 1, 0), ""}};
  const TangentFieldResult r = curve_direction_field(s, settings);
  const intrinsic::CurveChain ch = intrinsic::curve_chain(s.surface.tri, s.network, 0);
  EXPECT_EQ(r.constrained, Index(36 + 1 + ch.vertices.size()));  // boundary, vertex 0, curve
  // the held direction at the centre: a diagonal, one arm of the cross
  const double t = std::atan2(r.vectors(0, 1), r.vectors(0, 0));
  EXPECT_LT(std::abs(std::polar(1.0, 4 * (t - kPi / 4)) - 1.0), 1e-9);
}

TEST(CurveFields, CurveConstraintsOnePerEdgeEnd) {
  const CurveSurface s =
      prepare_curve_surface(flat_disk(4), {curve({1, 4}, intrinsic::CurveShape::kPath)}, exact());
  const fem::TangentFrames frames = fem::tangent_frames(s.surface.tri);
  const std::vector<DirectionConstraint> held = curve_constraints(s.surface.tri, s.network, frames);
  const intrinsic::CurveChain ch = intrinsic::curve_chain(s.surface.tri, s.network, 0);
  EXPECT_EQ(held.size(), 2 * ch.edges.size());
  const fem::TangentFrames wrong = fem::tangent_frames(test::make_tri(intrinsic::icosphere(2)));
  EXPECT_THROW(curve_constraints(s.surface.tri, s.network, wrong), InvalidInput);
}

TEST(CurveFields, BadInputIsRefusedWithTheReason) {
  // a point cloud: no faces to draw curves on
  io::SurfaceInput cloud = flat_disk(3);
  cloud.triangles.clear();
  try {
    prepare_curve_surface(cloud, {curve({0, 1}, intrinsic::CurveShape::kPath)});
    FAIL() << "a point cloud was accepted";
  } catch (const InvalidInput& e) {
    EXPECT_NE(std::string(e.what()).find("curves need a triangle mesh"), std::string::npos)
        << e.what();
  }
  // three triangles on one edge: not edge-manifold, no signposts
  io::SurfaceInput fan;
  fan.positions.resize(5, 3);
  fan.positions << 0, 0, 0, 1, 0, 0, 0, 1, 0, 0, -1, 0, 0, 0, 1;
  fan.triangles = {{0, 1, 2}, {1, 0, 3}, {0, 1, 4}};
  try {
    prepare_curve_surface(fan, {curve({2, 3}, intrinsic::CurveShape::kPath)});
    FAIL() << "a nonmanifold mesh was accepted";
  } catch (const InvalidInput& e) {
    EXPECT_NE(std::string(e.what()).find("edge-manifold, orientable mesh"), std::string::npos)
        << e.what();
  }
  // a vertex out of range, named
  try {
    prepare_curve_surface(flat_disk(2), {curve({0, 99}, intrinsic::CurveShape::kPath)});
    FAIL() << "a vertex out of range was accepted";
  } catch (const InvalidInput& e) {
    EXPECT_NE(std::string(e.what()).find("99"), std::string::npos) << e.what();
  }
}

}  // namespace
}  // namespace ifem::solvers
