// Point location both ways (intrinsic::PointLocator) and function transfer (fem::transfer), for
// signposts and integer coordinates, against known truths: on a flat mesh positions are linear
// on both triangulations, so a located point's position read on the intrinsic side is the
// input point's, and linear functions transfer exactly by both methods; L2 transfer preserves
// ∫ f dA; locations round-trip; located intrinsic vertices are where the correspondence puts
// them; bad input is refused with the reason.
#include "fem/attribute_transfer.h"

#include <gtest/gtest.h>

#include <random>
#include <string>
#include <vector>

#include "helpers.h"
#include "intrinsic/core/errors.h"
#include "intrinsic/core/geometry.h"
#include "intrinsic/generators/mesh_generators.h"
#include "intrinsic/refine/delaunay_refine.h"

namespace ifem::fem {
namespace {

using intrinsic::CorrespondenceView;
using intrinsic::NormalCoordinateTriangulation;
using intrinsic::PointLocator;
using intrinsic::SignpostTriangulation;
using intrinsic::SurfacePoint;
using intrinsic::TriangleMesh;

// One refinement setting: min angle, and a max area as a fraction of the mean face area (0:
// none).
struct Setting {
  double angle, area_fraction;
};

const Setting kSettings[] = {{20.0, 0.5}, {28.0, 0.0}, {25.0, 0.15}};

intrinsic::RefineOptions options(const Setting& s, const TriangleMesh& m) {
  intrinsic::RefineOptions o;
  o.min_angle_degrees = s.angle;
  const auto t = intrinsic::IntrinsicTriangulation::from_positions(m.faces, m.positions);
  o.max_area = s.area_fraction * intrinsic::total_area(t) / double(t.n_faces());
  return o;
}

// Both representations refined the same way (same triangulation).
struct Pair {
  SignpostTriangulation st;
  NormalCoordinateTriangulation nc;
  Pair(const TriangleMesh& m, const Setting& s)
      : st(m.faces, m.positions, 1e-6), nc(m.faces, m.positions, 1e-6) {
    intrinsic::delaunay_refine(st, options(s, m));
    intrinsic::delaunay_refine(nc, options(s, m));
  }
};

TriangleMesh flat() { return ifem::test::flat_square(6, 0.3, 5); }
TriangleMesh curved() {
  TriangleMesh m = ifem::test::jittered(intrinsic::icosphere(2), 0.05, 7);
  m.positions.col(0) *= 2.0;
  return m;
}

// Random points on the faces of t, plus every face's corners and side midpoints.
std::vector<SurfacePoint> sample(const intrinsic::IntrinsicTriangulation& t, int per_face,
                                 unsigned seed) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  std::vector<SurfacePoint> out;
  for (Index f = 0; f < t.n_faces(); ++f) {
    for (int i = 0; i < per_face; ++i) {
      Eigen::Vector3d b(u(rng), u(rng), u(rng));
      out.push_back({f, b / b.sum()});
    }
    for (int k = 0; k < 3; ++k) {
      out.push_back({f, Eigen::Vector3d::Unit(k)});
      out.push_back({f, 0.5 * (Eigen::Vector3d::Unit(k) + Eigen::Vector3d::Unit((k + 1) % 3))});
    }
  }
  return out;
}

// Position on the input of intrinsic points, read through the intrinsic vertex positions (exact
// on a flat mesh, where positions are linear on the intrinsic faces).
Eigen::Vector3d intrinsic_position(const CorrespondenceView& v, const Positions& x,
                                   const SurfacePoint& p) {
  return intrinsic::point_position(v.intrinsic(), x, p);
}

void check_flat_location(const CorrespondenceView& view) {
  const PointLocator loc(view);
  const Positions x = view.vertex_positions();
  const std::vector<SurfacePoint> pts = sample(view.input(), 4, 1);
  const std::vector<SurfacePoint> on_int = loc.input_to_intrinsic(pts);
  const std::vector<SurfacePoint> back = loc.intrinsic_to_input(on_int);
  for (std::size_t i = 0; i < pts.size(); ++i) {
    const Eigen::Vector3d p =
        intrinsic::point_position(view.input(), view.input_positions(), pts[i]);
    ASSERT_LT((intrinsic_position(view, x, on_int[i]) - p).norm(), 1e-12) << "point " << i;
    ASSERT_LT((intrinsic::point_position(view.input(), view.input_positions(), back[i]) - p).norm(),
              1e-12)
        << "point " << i;
  }
  // and from the intrinsic side
  const std::vector<SurfacePoint> ipts = sample(view.intrinsic(), 3, 2);
  const std::vector<SurfacePoint> on_in = loc.intrinsic_to_input(ipts);
  for (std::size_t i = 0; i < ipts.size(); ++i) {
    const Eigen::Vector3d p = intrinsic_position(view, x, ipts[i]);
    ASSERT_LT(
        (intrinsic::point_position(view.input(), view.input_positions(), on_in[i]) - p).norm(),
        1e-12)
        << "intrinsic point " << i;
  }
}

TEST(PointLocator, FlatMeshPositionsAgreeBothWays) {
  for (const Setting& s : kSettings) {
    const Pair pair(flat(), s);
    ASSERT_GT(pair.st.intrinsic().n_vertices(), pair.st.n_input_vertices());
    check_flat_location(pair.st);
    check_flat_location(pair.nc);
  }
}

// Curved: round trips, and intrinsic vertices located where the correspondence places them.
void check_curved_location(const CorrespondenceView& view) {
  const PointLocator loc(view);
  const std::vector<SurfacePoint> pts = sample(view.input(), 3, 3);
  const std::vector<SurfacePoint> back = loc.intrinsic_to_input(loc.input_to_intrinsic(pts));
  const Positions& x = view.input_positions();
  for (std::size_t i = 0; i < pts.size(); ++i) {
    ASSERT_LT((intrinsic::point_position(view.input(), x, back[i]) -
               intrinsic::point_position(view.input(), x, pts[i]))
                  .norm(),
              1e-12)
        << "point " << i;
  }
  std::vector<SurfacePoint> corners;
  const auto& tri = view.intrinsic();
  for (Index f = 0; f < tri.n_faces(); ++f) {
    for (int k = 0; k < 3; ++k) corners.push_back({f, Eigen::Vector3d::Unit(k)});
  }
  const std::vector<SurfacePoint> at = loc.intrinsic_to_input(corners);
  const Positions vx = view.vertex_positions();
  for (std::size_t i = 0; i < corners.size(); ++i) {
    const Index v = tri.tail(3 * corners[i].face + int(i % 3));
    ASSERT_LT((intrinsic::point_position(view.input(), x, at[i]) - vx.row(v).transpose()).norm(),
              1e-9)
        << "vertex " << v;
  }
}

TEST(PointLocator, CurvedRoundTripAndVertexLocations) {
  for (const Setting& s : kSettings) {
    const Pair pair(curved(), s);
    ASSERT_GT(pair.st.intrinsic().n_vertices(), pair.st.n_input_vertices());
    check_curved_location(pair.st);
    check_curved_location(pair.nc);
  }
}

TEST(PointLocator, RefusesBadPointsWithTheReason) {
  const Pair pair(flat(), kSettings[0]);
  const PointLocator loc{CorrespondenceView(pair.nc)};
  auto message = [&](SurfacePoint p, bool from_input) {
    try {
      from_input ? loc.input_to_intrinsic({p}) : loc.intrinsic_to_input({p});
    } catch (const InvalidInput& e) {
      return std::string(e.what());
    }
    return std::string("no error");
  };
  EXPECT_NE(message({-1, Eigen::Vector3d(1, 0, 0)}, true).find("is not a face"), std::string::npos);
  EXPECT_NE(message({100000, Eigen::Vector3d(1, 0, 0)}, false).find("is not a face"),
            std::string::npos);
  EXPECT_NE(message({0, Eigen::Vector3d(1.5, -0.5, 0)}, true).find("barycentric"),
            std::string::npos);
  EXPECT_NE(message({0, Eigen::Vector3d(0.5, 0.2, 0)}, false).find("summing to 1"),
            std::string::npos);
}

Eigen::VectorXd linear(const Positions& x) {
  return (0.3 + 1.7 * x.col(0).array() - 0.6 * x.col(1).array()).matrix();
}

void check_linear_exact(const CorrespondenceView& view) {
  const PointLocator loc(view);
  const Eigen::VectorXd f_in = linear(view.input_positions());
  const Eigen::VectorXd f_int = linear(view.vertex_positions());
  for (TransferMethod m : {TransferMethod::kPointwise, TransferMethod::kL2}) {
    EXPECT_LT((transfer(view, f_in, m, false, &loc) - f_int).lpNorm<Eigen::Infinity>(), 1e-10)
        << to_string(m) << " to intrinsic";
    EXPECT_LT((transfer(view, f_int, m, true, &loc) - f_in).lpNorm<Eigen::Infinity>(), 1e-10)
        << to_string(m) << " to input";
  }
}

TEST(Transfer, LinearFunctionOnAFlatMeshIsExactBothMethodsBothWays) {
  for (const Setting& s : kSettings) {
    const Pair pair(flat(), s);
    check_linear_exact(pair.st);
    check_linear_exact(pair.nc);
  }
}

double integral(const intrinsic::IntrinsicTriangulation& t, const Eigen::VectorXd& u) {
  return Eigen::VectorXd::Ones(u.size()).dot(galerkin_mass(t) * u);
}

TEST(Transfer, L2PreservesTheIntegralAndBothRepresentationsAgree) {
  for (const Setting& s : kSettings) {
    const Pair pair(curved(), s);
    const Eigen::VectorXd f = pair.st.input_positions().col(2).array().sin() + 2.0;
    Eigen::VectorXd first;
    for (const CorrespondenceView view :
         {CorrespondenceView(pair.st), CorrespondenceView(pair.nc)}) {
      const PointLocator loc(view);
      const Eigen::VectorXd u = transfer(view, f, TransferMethod::kL2, false, &loc);
      const double in = integral(view.input(), f);
      EXPECT_NEAR(integral(view.intrinsic(), u), in, 1e-12 * std::abs(in));
      const Eigen::VectorXd g = u.array().square();
      const Eigen::VectorXd back = transfer(view, g, TransferMethod::kL2, true, &loc);
      EXPECT_NEAR(integral(view.input(), back), integral(view.intrinsic(), g),
                  1e-12 * std::abs(integral(view.intrinsic(), g)));
      if (first.size() == 0) {
        first = u;
      } else {
        EXPECT_LT((u - first).lpNorm<Eigen::Infinity>(), 1e-9);
      }
    }
  }
}

TEST(Transfer, PointwiseIsTheIdentityAtInputVertices) {
  const Pair pair(curved(), kSettings[1]);
  for (const CorrespondenceView view : {CorrespondenceView(pair.st), CorrespondenceView(pair.nc)}) {
    const Eigen::VectorXd f = Eigen::VectorXd::LinSpaced(view.n_input_vertices(), -1.0, 3.0);
    const Eigen::VectorXd u = transfer(view, f, TransferMethod::kPointwise);
    EXPECT_EQ(u.head(f.size()), f);
    EXPECT_EQ(transfer(view, u, TransferMethod::kPointwise, true), f);
  }
}

TEST(Transfer, RefusesBadInputWithTheReason) {
  const Pair pair(flat(), kSettings[0]);
  const CorrespondenceView view(pair.st);
  auto message = [&](const Eigen::VectorXd& v, bool back) {
    try {
      transfer(view, v, TransferMethod::kL2, back);
    } catch (const InvalidInput& e) {
      return std::string(e.what());
    }
    return std::string("no error");
  };
  const Index n_in = view.n_input_vertices();
  EXPECT_NE(message(Eigen::VectorXd::Zero(n_in + 1), false).find("expected one per input vertex"),
            std::string::npos);
  EXPECT_NE(message(Eigen::VectorXd::Zero(n_in), true).find("expected one per intrinsic vertex"),
            std::string::npos);
  Eigen::VectorXd bad = Eigen::VectorXd::Zero(n_in);
  bad[3] = std::nan("");
  EXPECT_NE(message(bad, false).find("value 3 is not a finite"), std::string::npos);
  EXPECT_THROW(parse_transfer_method("cubic"), InvalidInput);
  EXPECT_EQ(parse_transfer_method("l2"), TransferMethod::kL2);
  EXPECT_EQ(parse_transfer_method(to_string(TransferMethod::kPointwise)),
            TransferMethod::kPointwise);
}

}  // namespace
}  // namespace ifem::fem
