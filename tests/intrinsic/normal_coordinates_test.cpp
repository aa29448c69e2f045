// Normal coordinates against signposts: both representations are driven by the same calls (so
// their intrinsic triangulations are identical), and the integers must equal what the
// signpost tracer counts, the traced crossings must sit where the signposts put them, and every
// input edge must come back as a connected sequence of crossings.
#include "intrinsic/integer/normal_coordinates.h"

#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <map>
#include <random>
#include <string>
#include <utility>
#include <vector>

#include "helpers.h"
#include "intrinsic/core/geometry.h"
#include "intrinsic/generators/mesh_generators.h"
#include "intrinsic/integer/crosscheck.h"
#include "intrinsic/integer/integer_subdivision.h"
#include "intrinsic/io/mesh_io.h"
#include "intrinsic/refine/delaunay_refine.h"
#include "intrinsic/refine/signpost.h"

namespace ifem::intrinsic {
namespace {

using T = IntrinsicTriangulation;

double mesh_scale(const IntrinsicTriangulation& input) {
  double s = 0.0;
  for (Index e = 0; e < input.n_edges(); ++e) s = std::max(s, input.length(e));
  return s;
}

double distance_to_segment(const Eigen::Vector3d& p, const Eigen::Vector3d& a,
                           const Eigen::Vector3d& b) {
  const Eigen::Vector3d ab = b - a;
  const double t = std::clamp((p - a).dot(ab) / ab.squaredNorm(), 0.0, 1.0);
  return (p - (a + t * ab)).norm();
}

// n(e) equals the number of input sides the signpost trace of e crosses, and each crossing
// lies where the signpost trace puts it; an edge with n = −1 lies along its input edge.
// Checks every `stride`-th edge.
void expect_matches_signposts(const NormalCoordinateTriangulation& nc,
                              const SignpostTriangulation& st, double rel_tol, Index stride = 1) {
  const IntrinsicTriangulation& tri = nc.intrinsic();
  ASSERT_EQ(tri.tails(), st.intrinsic().tails());
  const double tol = rel_tol * mesh_scale(nc.input());
  for (Index e = 0; e < tri.n_edges(); e += stride) {
    const Index h = tri.edge_halfedge(e);
    const std::vector<SurfacePoint> path = st.trace_halfedge(h);
    const int n = nc.normal_coordinate(e);
    if (n < 0) {
      const Index ie = nc.input_edge_along(h);
      ASSERT_NE(ie, kInvalidIndex) << "edge " << e;
      const Index ih = nc.input().edge_halfedge(ie);
      const Eigen::Vector3d a = nc.input_positions().row(nc.input().tail(ih));
      const Eigen::Vector3d b = nc.input_positions().row(nc.input().head(ih));
      for (const SurfacePoint& p : path) {
        ASSERT_LT(distance_to_segment(st.position(p), a, b), tol) << "edge " << e;
      }
      continue;
    }
    ASSERT_GE(path.size(), 2u);
    // the crossings the signposts found, less those at an end (a trace leaving a vertex that
    // lies on an input edge may first step over that edge, at rounding level)
    std::vector<Eigen::Vector3d> found;
    // (the signposts locate such a vertex within a few 1e-9: a looser tolerance there)
    const Eigen::Vector3d first = st.position(path.front()), last = st.position(path.back());
    auto end_tol = [&](Index v) {
      return v >= nc.n_input_vertices() && !nc.spokes(v).empty() ? 1e-6 * tol / rel_tol : tol;
    };
    const double tol_first = end_tol(tri.tail(h)), tol_last = end_tol(tri.head(h));
    for (std::size_t i = 1; i + 1 < path.size(); ++i) {
      const Eigen::Vector3d y = st.position(path[i]);
      if ((y - first).norm() > tol_first && (y - last).norm() > tol_last) found.push_back(y);
    }
    ASSERT_EQ(static_cast<int>(found.size()), n)
        << "edge " << e << " (" << tri.tail(h) << ", " << tri.head(h) << "), path " << path.size()
        << ", input vertices " << nc.n_input_vertices() << ", spokes "
        << nc.spokes(tri.tail(h)).size() << " " << nc.spokes(tri.head(h)).size() << ", to ends "
        << (found.empty() ? -1.0 : (found[0] - first).norm()) << " "
        << (found.empty() ? -1.0 : (found[0] - last).norm()) << ", length " << tri.length(e);
    const std::vector<InputCrossing> crossings = nc.trace_edge(e);
    ASSERT_EQ(static_cast<int>(crossings.size()), n);
    double last_t = 0.0;
    for (int i = 0; i < n; ++i) {
      const InputCrossing& c = crossings[i];
      EXPECT_GT(c.t, last_t) << "edge " << e;
      last_t = c.t;
      const Eigen::Vector3d x = nc.crossing_position(c);
      const Eigen::Vector3d& y = found[i];
      ASSERT_LT((x - y).norm(), tol) << "edge " << e << " crossing " << i;
      const SurfacePoint sp = nc.crossing_point(c);
      ASSERT_LT((st.position(sp) - x).norm(), tol);
    }
  }
}

// Every input edge is recovered: its crossings (over all intrinsic edges), sorted along it,
// are distinct, consecutive ones lie on two sides of one intrinsic face (or are separated by
// a vertex on the input edge), and an input edge that no intrinsic edge runs along is crossed.
void expect_input_edges_recovered(const NormalCoordinateTriangulation& nc) {
  const IntrinsicTriangulation& tri = nc.intrinsic();
  struct Hit {
    double at;
    Index edge;
  };
  std::vector<std::vector<Hit>> hits(nc.input().n_edges());
  std::vector<std::vector<double>> stops(nc.input().n_edges());  // vertices on the input edge
  std::vector<char> along(nc.input().n_edges(), 0);
  for (Index e = 0; e < tri.n_edges(); ++e) {
    const Index h = tri.edge_halfedge(e);
    if (nc.normal_coordinate(e) < 0) along[nc.input_edge_along(h)] = 1;
    for (const InputCrossing& c : nc.trace_edge(e)) hits[c.input_edge].push_back({c.input_t, e});
  }
  for (Index v = nc.n_input_vertices(); v < tri.n_vertices(); ++v) {
    for (const InputSpoke& s : nc.spokes(v)) stops[s.input_edge].push_back(s.at);
  }
  auto share_face = [&](Index e1, Index e2) {
    for (const Index h : {tri.edge_halfedge(e1), tri.twin(tri.edge_halfedge(e1))}) {
      if (h == kInvalidIndex) continue;
      for (int k = 0; k < 3; ++k) {
        if (tri.edge(3 * T::face(h) + k) == e2) return true;
      }
    }
    return false;
  };
  for (Index ie = 0; ie < nc.input().n_edges(); ++ie) {
    auto& list = hits[ie];
    if (!along[ie]) {
      ASSERT_FALSE(list.empty()) << "input edge " << ie << " lost";
    }
    std::sort(list.begin(), list.end(), [](const Hit& a, const Hit& b) { return a.at < b.at; });
    for (std::size_t i = 0; i < list.size(); ++i) {
      ASSERT_GT(list[i].at, 0.0);
      ASSERT_LT(list[i].at, 1.0);
      if (i == 0) continue;
      ASSERT_GE(list[i].at, list[i - 1].at - 1e-12) << "input edge " << ie;
      const bool stop_between = std::any_of(stops[ie].begin(), stops[ie].end(), [&](double s) {
        return s > list[i - 1].at && s < list[i].at;
      });
      // crossings at the same place up to rounding (an input edge passing a vertex inserted
      // on it, or within rounding of it): their order along the input edge is the one that
      // chains them through shared faces
      for (std::size_t j = i + 1;
           !stop_between && j < list.size() && list[j].at - list[i].at < 1e-12 &&
           !share_face(list[i - 1].edge, list[i].edge);
           ++j) {
        if (share_face(list[i - 1].edge, list[j].edge)) std::swap(list[i], list[j]);
      }
      if (!stop_between && !share_face(list[i - 1].edge, list[i].edge)) {
        for (std::size_t j = (i > 3 ? i - 3 : 0); j < std::min(list.size(), i + 3); ++j) {
          const Index hh = tri.edge_halfedge(list[j].edge);
          std::cout << j << " at " << std::setprecision(17) << list[j].at << " e " << list[j].edge
                    << " (" << tri.tail(hh) << "," << tri.head(hh) << ") n "
                    << nc.normal_coordinate(list[j].edge) << "\n";
        }
        for (double st : stops[ie]) std::cout << "stop " << st << "\n";
        const Index ih = nc.input().edge_halfedge(ie);
        std::cout << "input edge " << nc.input().tail(ih) << " " << nc.input().head(ih) << "\n";
      }
      if (!stop_between) {
        ASSERT_TRUE(share_face(list[i - 1].edge, list[i].edge))
            << "input edge " << ie << ": crossings " << i - 1 << ", " << i << " not adjacent";
      }
    }
  }
}

// Random flips, insertions in faces and edge splits applied to both representations. With
// IFEM_NC_DEBUG set in the environment, the signpost comparison runs after every operation
// (finds the first operation that goes wrong).
// kinds: bit 0 flips, bit 1 insertions in faces, bit 2 edge splits.
void random_operations(NormalCoordinateTriangulation& nc, SignpostTriangulation& st, int n_ops,
                       unsigned seed, int kinds, bool check_each = false) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  for (int op = 0; op < n_ops; ++op) {
    const IntrinsicTriangulation& tri = nc.intrinsic();
    const int kind = static_cast<int>(rng() % 4);
    if (!(kinds & (1 << std::max(kind - 1, 0)))) continue;
    if (kind <= 1) {  // flips: twice as often
      const Index e = static_cast<Index>(rng() % tri.n_edges());
      const bool a = nc.flip_edge(e), b = st.flip_edge(e);
      ASSERT_EQ(a, b);
    } else if (kind == 2) {
      const Index f = static_cast<Index>(rng() % tri.n_faces());
      Eigen::Vector3d bary(0.2 + unit(rng), 0.2 + unit(rng), 0.2 + unit(rng));
      bary /= bary.sum();
      ASSERT_EQ(nc.insert_vertex(f, bary), st.insert_vertex(f, bary));
    } else {
      const Index e = static_cast<Index>(rng() % tri.n_edges());
      if (!tri.can_split_edge(e)) continue;
      const double t = 0.25 + 0.5 * unit(rng);
      ASSERT_EQ(nc.split_edge(e, t), st.split_edge(e, t));
    }
    ASSERT_NO_THROW(nc.validate()) << "after operation " << op;
    if (check_each) {
      SCOPED_TRACE("after operation " + std::to_string(op) + " kind " + std::to_string(kind));
      expect_matches_signposts(nc, st, 1e-8);
      if (::testing::Test::HasFailure()) return;
    }
  }
}

void run_random(const TriangleMesh& mesh, int n_ops, unsigned seed, double rel_tol = 1e-9,
                int kinds = 7) {
  NormalCoordinateTriangulation nc(mesh.faces, mesh.positions);
  SignpostTriangulation st(mesh.faces, mesh.positions);
  random_operations(nc, st, n_ops, seed, kinds, std::getenv("IFEM_NC_DEBUG") != nullptr);
  if (::testing::Test::HasFailure()) return;
  Index crossed = 0;  // the operations moved edges off the input: something to check
  for (Index e = 0; e < nc.intrinsic().n_edges(); ++e) crossed += nc.normal_coordinate(e) > 0;
  EXPECT_GT(crossed, 5);
  {
    SCOPED_TRACE("after the random operations");
    expect_matches_signposts(nc, st, rel_tol);
    expect_input_edges_recovered(nc);
  }
  // then Delaunay: the same flips, still in agreement
  const FlipReport a = nc.flip_to_delaunay();
  const FlipReport b = st.flip_to_delaunay();
  EXPECT_EQ(a.flips, b.flips);
  nc.validate();
  SCOPED_TRACE("after Delaunay flipping");
  expect_matches_signposts(nc, st, rel_tol);
  expect_input_edges_recovered(nc);
}

TEST(NormalCoordinates, StartAsInput) {
  const TriangleMesh m = test::jittered(icosphere(2), 0.05, 3);
  NormalCoordinateTriangulation nc(m.faces, m.positions);
  nc.validate();
  for (Index e = 0; e < nc.intrinsic().n_edges(); ++e) {
    EXPECT_EQ(nc.normal_coordinate(e), -1);
    EXPECT_EQ(nc.input_edge_along(nc.intrinsic().edge_halfedge(e)), e);
  }
  std::size_t spokes = 0;
  for (Index v = 0; v < nc.n_input_vertices(); ++v) spokes += nc.spokes(v).size();
  EXPECT_EQ(spokes, 2u * static_cast<std::size_t>(nc.input().n_edges()));
}

// One flip on a flat square of two triangles: the new diagonal crosses the old one, once.
TEST(NormalCoordinates, OneFlipCrossesTheOldDiagonal) {
  Positions x(4, 3);
  x << 0, 0, 0, 1, 0, 0, 1, 1, 0, 0, 1, 0;
  const std::vector<Triangle> f = {{0, 1, 2}, {0, 2, 3}};
  NormalCoordinateTriangulation nc(f, x);
  Index diag = kInvalidIndex;
  for (Index e = 0; e < nc.intrinsic().n_edges(); ++e) {
    if (!nc.intrinsic().is_boundary_edge(e)) diag = e;
  }
  ASSERT_TRUE(nc.flip_edge(diag));
  EXPECT_EQ(nc.normal_coordinate(diag), 1);
  const auto c = nc.trace_edge(diag);
  ASSERT_EQ(c.size(), 1u);
  EXPECT_NEAR(c[0].t, 0.5, 1e-14);
  EXPECT_NEAR(c[0].input_t, 0.5, 1e-14);
  ASSERT_TRUE(nc.flip_edge(diag));  // back: along the input diagonal again
  EXPECT_EQ(nc.normal_coordinate(diag), -1);
  nc.validate();
}

TEST(NormalCoordinates, RandomFlipsIcosphere) {
  run_random(test::jittered(icosphere(2), 0.04, 1), 150, 1, 1e-9, 1);
}

TEST(NormalCoordinates, RandomInsertionsIcosphere) {
  run_random(test::jittered(icosphere(2), 0.04, 1), 100, 1, 1e-9, 3);
}

TEST(NormalCoordinates, RandomSplitsIcosphere) {
  run_random(test::jittered(icosphere(2), 0.04, 1), 100, 1, 1e-9, 5);
}

TEST(NormalCoordinates, RandomOperationsIcosphere) {
  for (const unsigned seed : {1u, 2u, 3u}) {
    SCOPED_TRACE("seed " + std::to_string(seed));
    run_random(test::jittered(icosphere(2), 0.04, seed), 150, seed, 1e-8);
  }
}

TEST(NormalCoordinates, RandomOperationsFlatSquareWithBoundary) {
  for (const unsigned seed : {4u, 5u}) {
    SCOPED_TRACE("seed " + std::to_string(seed));
    run_random(test::flat_square(6, 0.3, seed), 150, seed, 1e-8);
  }
}

TEST(NormalCoordinates, RandomOperationsTestData) {
  for (const char* name : {"bunny_npm_lowres.obj"}) {
    SCOPED_TRACE(name);
    const io::SurfaceInput in = io::read_mesh((test::test_data() / name).string());
    run_random({in.positions, in.triangles}, 120, 7, 1e-8);
  }
}

// Needles: a strongly non-Delaunay input whose Delaunay flipping moves many edges far.
TEST(NormalCoordinates, NeedleMeshDelaunayAgreesWithSignposts) {
  const TriangleMesh m = needle_fan(60);
  NormalCoordinateTriangulation nc(m.faces, m.positions);
  SignpostTriangulation st(m.faces, m.positions);
  const FlipReport a = nc.flip_to_delaunay();
  const FlipReport b = st.flip_to_delaunay();
  EXPECT_GT(a.flips, 0u);
  EXPECT_EQ(a.flips, b.flips);
  EXPECT_EQ(nc.intrinsic().lengths(), st.intrinsic().lengths());
  nc.validate();
  expect_matches_signposts(nc, st, 1e-9);
  expect_input_edges_recovered(nc);
}

// The common subdivision from the integers partitions both triangulations: its triangles'
// areas sum, per input face, to that face's area and, per intrinsic face, to that face's area
// (1e-12 relative to the mean face area).
void expect_area_partition(const NormalCoordinateTriangulation& nc) {
  const CommonSubdivision cs = common_subdivision(nc);
  const IntrinsicTriangulation& tri = nc.intrinsic();
  const Positions& x = nc.input_positions();
  std::vector<double> by_input(nc.input().n_faces(), 0.0), by_intrinsic(tri.n_faces(), 0.0);
  double total = 0.0;
  for (std::size_t i = 0; i < cs.faces.size(); ++i) {
    const Triangle& t = cs.faces[i];
    const Eigen::Vector3d a = cs.positions.row(t[0]), b = cs.positions.row(t[1]),
                          c = cs.positions.row(t[2]);
    const double area = 0.5 * (b - a).cross(c - a).norm();
    by_input[cs.input_face[i]] += area;
    by_intrinsic[cs.intrinsic_face[i]] += area;
  }
  std::vector<double> input_area(nc.input().n_faces());
  for (Index f = 0; f < nc.input().n_faces(); ++f) {
    const Eigen::Vector3d a = x.row(nc.input().tail(3 * f)), b = x.row(nc.input().tail(3 * f + 1)),
                          c = x.row(nc.input().tail(3 * f + 2));
    input_area[f] = 0.5 * (b - a).cross(c - a).norm();
    total += input_area[f];
  }
  const double tol = 1e-12 * total / static_cast<double>(nc.input().n_faces());
  for (Index f = 0; f < nc.input().n_faces(); ++f) {
    ASSERT_NEAR(by_input[f], input_area[f], tol) << "input face " << f;
  }
  for (Index g = 0; g < tri.n_faces(); ++g) {
    ASSERT_NEAR(by_intrinsic[g], face_area(tri, g), tol) << "intrinsic face " << g;
  }
  std::size_t crossings = 0;
  for (Index e = 0; e < tri.n_edges(); ++e) crossings += std::max(0, nc.normal_coordinate(e));
  EXPECT_EQ(cs.crossings, crossings);
}

// The two overlays agree: the area of every (intrinsic face, input face) piece is the same
// from the integers as from the signposts (1e-9 relative to the mean face area).
void expect_same_overlay(const NormalCoordinateTriangulation& nc, const SignpostTriangulation& st) {
  auto pieces = [](const CommonSubdivision& cs) {
    std::map<std::pair<Index, Index>, double> out;
    for (std::size_t i = 0; i < cs.faces.size(); ++i) {
      const Triangle& t = cs.faces[i];
      const Eigen::Vector3d a = cs.positions.row(t[0]), b = cs.positions.row(t[1]),
                            c = cs.positions.row(t[2]);
      out[{cs.intrinsic_face[i], cs.input_face[i]}] += 0.5 * (b - a).cross(c - a).norm();
    }
    return out;
  };
  const auto a = pieces(common_subdivision(nc)), b = pieces(common_subdivision(st));
  double total = 0.0;
  for (const auto& [key, area] : b) total += area;
  const double tol = 1e-9 * total / static_cast<double>(nc.input().n_faces());
  for (const auto& [key, area] : a) {
    const auto it = b.find(key);
    const double other = it == b.end() ? 0.0 : it->second;
    EXPECT_NEAR(area, other, tol) << "intrinsic face " << key.first << ", input face "
                                  << key.second;
  }
  for (const auto& [key, area] : b) {
    if (a.find(key) == a.end()) {
      EXPECT_LT(area, tol) << "piece missing from the integers";
    }
  }
}

// Every intrinsic vertex is located where the signposts locate it (3D, 1e-8 of the mesh size:
// signpost locations of inserted vertices carry a few 1e-9).
void expect_same_locations(const NormalCoordinateTriangulation& nc,
                           const SignpostTriangulation& st) {
  const std::vector<SurfacePoint> loc = vertex_locations(nc);
  const double tol = 1e-8 * mesh_scale(nc.input());
  for (Index v = 0; v < nc.intrinsic().n_vertices(); ++v) {
    ASSERT_NE(loc[v].face, kInvalidIndex) << "vertex " << v;
    EXPECT_NEAR(loc[v].bary.sum(), 1.0, 1e-12);
    EXPECT_LT((st.position(loc[v]) - st.position(st.vertex_location(v))).norm(), tol)
        << "vertex " << v;
  }
}

TEST(NormalCoordinates, CommonSubdivisionPartitionsAreas) {
  const std::vector<TriangleMesh> meshes = {test::jittered(icosphere(2), 0.04, 8),
                                            test::flat_square(6, 0.3, 9)};
  for (std::size_t i = 0; i < meshes.size(); ++i) {
    SCOPED_TRACE("mesh " + std::to_string(i));
    NormalCoordinateTriangulation nc(meshes[i].faces, meshes[i].positions);
    SignpostTriangulation st(meshes[i].faces, meshes[i].positions);
    expect_area_partition(nc);  // the input itself
    // on the square, no random flips: flipping an edge at a straight boundary vertex (angle π)
    // may pass the convexity test at rounding level and leave a flat triangle
    random_operations(nc, st, 150, 10 + static_cast<unsigned>(i), i == 0 ? 7 : 6);
    expect_area_partition(nc);
    expect_same_overlay(nc, st);
    expect_same_locations(nc, st);
    nc.flip_to_delaunay();
    st.flip_to_delaunay();
    expect_area_partition(nc);
    expect_same_overlay(nc, st);
  }
}

// Two vertices inserted within rounding of an input edge (the square's diagonal 0–2, crossed by
// the flipped diagonal 1–3), at fractions `at` and 1 − `at` along it; flipping 1–3 joins them by
// an edge along the input edge. Where the integers count them on two sides, that edge crosses
// the input edge once, at a point the intersection of the two nearly parallel lines does not
// fix: the crossing must still lie on both (D-300: on needle_soup(3) it was put at t = 5.7, off
// the edge, and the common subdivision's pieces overlapped by 5e-2 of a face).
TEST(NormalCoordinates, CrossingOfAnEdgeAlongAnInputEdgeStaysOnBoth) {
  Positions x(4, 3);
  x << 0, 0, 0, 1, 0, 0, 1, 1, 0, 0, 1, 0;
  const std::vector<Triangle> faces = {{0, 1, 2}, {0, 2, 3}};  // input diagonal 0–2
  int crossed = 0;
  // fractions at which the lines' intersection fell off the edge (t = -9.4, -11.8, -1.1, 1.7)
  for (const double off : {0.0, 1e-17, -1e-16}) {
    for (const int i : {7, 10, 14, 36}) {
      const double at = 0.05 + 0.01 * i + 1e-3 * std::sqrt(double(i));
      SCOPED_TRACE(testing::Message() << "off " << off << " at " << at);
      NormalCoordinateTriangulation nc(faces, x);
      const IntrinsicTriangulation& tri = nc.intrinsic();
      auto edge_between = [&](Index a, Index b) {
        for (Index e = 0; e < tri.n_edges(); ++e) {
          const Index h = tri.edge_halfedge(e);
          if (std::minmax(tri.tail(h), tri.head(h)) == std::minmax(a, b)) return e;
        }
        return kInvalidIndex;
      };
      const Index diagonal = edge_between(0, 2);
      ASSERT_TRUE(nc.flip_edge(diagonal));  // now 1–3
      // the points (at + off, at) and (1 − at, 1 − at − off), in the faces holding them
      auto insert_at = [&](double px, double py) {
        for (Index f = 0; f < tri.n_faces(); ++f) {
          Eigen::Vector2d c[3];
          for (int k = 0; k < 3; ++k) c[k] = x.row(tri.tail(3 * f + k)).head<2>().transpose();
          const Eigen::Matrix2d m = (Eigen::Matrix2d() << c[1] - c[0], c[2] - c[0]).finished();
          const Eigen::Vector2d b = m.inverse() * (Eigen::Vector2d(px, py) - c[0]);
          if (b.minCoeff() > 0.0 && b.sum() < 1.0) {
            return nc.insert_vertex(f, Eigen::Vector3d(1.0 - b.sum(), b[0], b[1]));
          }
        }
        return kInvalidIndex;
      };
      const Index v = insert_at(at + off, at), w = insert_at(1.0 - at, 1.0 - at - off);
      ASSERT_NE(v, kInvalidIndex);
      ASSERT_NE(w, kInvalidIndex);
      ASSERT_TRUE(nc.flip_edge(diagonal));  // 1–3 becomes v–w, along the input diagonal
      ASSERT_EQ(edge_between(v, w), diagonal);
      nc.validate();
      const std::vector<InputCrossing> c = nc.trace_edge(diagonal);
      if (!c.empty()) {
        ++crossed;
        ASSERT_EQ(c.size(), 1u);
        EXPECT_GE(c[0].t, 0.0);
        EXPECT_LE(c[0].t, 1.0);
        // between the two vertices along the diagonal
        EXPECT_GE(c[0].input_t, at - 1e-12);
        EXPECT_LE(c[0].input_t, 1.0 - at + 1e-12);
      }
      expect_area_partition(nc);
      expect_input_edges_recovered(nc);
    }
  }
  // Since D-305 a vertex inserted within rounding of an input edge lies on it, so v–w runs along
  // the diagonal and crosses nothing; before it, these offsets counted v and w on opposite sides
  // and the crossing's position came from two lines parallel within rounding (D-300's guard).
  EXPECT_EQ(crossed, 0);
}

// A vertex inserted in a mollified sliver (the intrinsic face is much fatter than the 3D one):
// the common subdivision puts it where its location says, inside the 3D triangle, so the
// pieces tile the input face (D-300: a rigid map of the mollified layout onto the face's plane
// put it 2e-4 outside, and the pieces' areas overshot the face's 4000-fold), and where the
// signposts locate it.
TEST(NormalCoordinates, VertexInAMollifiedSliverLiesInItsInputFace) {
  Positions x(4, 3);
  x << 0, 0, 0, 1, 0, 0, 0.5, 1e-7, 0, 0.5, -1.0, 0.2;
  const std::vector<Triangle> faces = {{0, 1, 2}, {1, 0, 3}};
  for (const Eigen::Vector3d& bary :
       {Eigen::Vector3d(1.0 / 3, 1.0 / 3, 1.0 / 3), Eigen::Vector3d(0.1, 0.2, 0.7)}) {
    NormalCoordinateTriangulation nc(faces, x, kDefaultMollifyEpsilon);
    SignpostTriangulation st(faces, x, kDefaultMollifyEpsilon);
    ASSERT_NE(nc.input().lengths(), IntrinsicTriangulation::from_positions(faces, x).lengths());
    const Index v = nc.insert_vertex(0, bary);
    ASSERT_EQ(st.insert_vertex(0, bary), v);
    nc.flip_to_delaunay();
    st.flip_to_delaunay();
    const CommonSubdivision cs = common_subdivision(nc);
    std::vector<double> sum(2, 0.0);
    for (std::size_t i = 0; i < cs.faces.size(); ++i) {
      const Triangle& t = cs.faces[i];
      const Eigen::Vector3d a = cs.positions.row(t[0]), b = cs.positions.row(t[1]),
                            c = cs.positions.row(t[2]);
      sum[cs.input_face[i]] += 0.5 * (b - a).cross(c - a).norm();
    }
    for (Index f = 0; f < 2; ++f) {
      const Eigen::Vector3d a = x.row(faces[f][0]), b = x.row(faces[f][1]), c = x.row(faces[f][2]);
      EXPECT_NEAR(sum[f], 0.5 * (b - a).cross(c - a).norm(), 1e-15) << "input face " << f;
    }
    const SurfacePoint loc = vertex_locations(nc)[v];
    EXPECT_EQ(loc.face, 0);
    EXPECT_GE(loc.bary.minCoeff(), 0.0);
    Eigen::Vector3d p = Eigen::Vector3d::Zero();
    for (int k = 0; k < 3; ++k) p += loc.bary[k] * Eigen::Vector3d(x.row(faces[0][k]));
    EXPECT_LT((Eigen::Vector3d(cs.positions.row(v)) - p).norm(), 1e-15);
    EXPECT_LT((st.position(st.vertex_location(v)) - p).norm(), 1e-9);
  }
}

// Two flat fans of two triangles sharing only their centre (a vertex with two boundary fans, as
// in range scans): its spokes are listed fan after fan.
// Delaunay refinement on the integers makes the same calls as on signposts (one algorithm,
// two hosts): the same insertions and bit-identical lengths, valid integers, and a common
// subdivision that partitions both triangulations. Varied: the angle bound, an area bound.
// Refinement on both representations: the same insertions and lengths, and the integers
// stay exact where circumcenters land on (or within rounding of) input edges — the needle
// fan's symmetry axis is an input edge, and boundary splits put vertices on input edges.
// With compare_traces, the integers also equal the signpost traces (expect_matches_signposts).
void expect_refine_agrees(const TriangleMesh& m, double angle, double area,
                          bool compare_traces = false) {
  SCOPED_TRACE(testing::Message() << "angle " << angle << " area " << area);
  NormalCoordinateTriangulation nc(m.faces, m.positions);
  SignpostTriangulation st(m.faces, m.positions);
  RefineOptions o;
  o.min_angle_degrees = angle;
  o.max_area = area;
  const RefineReport a = delaunay_refine(nc, o), b = delaunay_refine(st, o);
  EXPECT_GT(a.insertions, area > 0.0 || angle >= 30.0 ? 3 : -1);  // needle fan below 30°: none
  EXPECT_EQ(a.insertions, b.insertions);
  EXPECT_EQ(a.edge_splits + a.boundary_splits, b.edge_splits + b.boundary_splits);
  EXPECT_EQ(nc.intrinsic().lengths(), st.intrinsic().lengths());
  EXPECT_GE(a.min_angle_after_excluding_needles, angle - 1e-9);
  nc.validate();
  expect_area_partition(nc);
  expect_input_edges_recovered(nc);
  if (compare_traces) expect_matches_signposts(nc, st, 1e-9);
}

TEST(NormalCoordinates, DelaunayRefineAgreesWithSignposts) {
  const TriangleMesh m = needle_fan(44);
  for (const double angle : {20.0, 28.0, 30.0}) {
    for (const double area : {0.01, 0.002, 0.0}) expect_refine_agrees(m, angle, area);
  }
}

// Exactly symmetric inputs put new vertices on input edges up to rounding: on needle_fan(n), n
// even, the axis is the input edge 0–n/2 and circumcenters land on it (insertions in a face);
// in a grid of rectangles the flipped diagonal's midpoint is the input diagonal's (splits).
// The new vertex must then lie on that input edge, not on a side chosen per count (D-305).
TEST(NormalCoordinates, RefineOnTheSymmetryAxisOfANeedleFan) {
  expect_refine_agrees(needle_fan(40), 20.0, 0.01, true);  // at the second insertion
  for (const int n : {30, 40, 64}) {
    SCOPED_TRACE(testing::Message() << "needle_fan(" << n << ")");
    expect_refine_agrees(needle_fan(n), 25.0, 0.002, true);
  }
}

TEST(NormalCoordinates, RefineAnExactlySymmetricGrid) {
  expect_refine_agrees(grid(8, 3, 1.0, 0.5), 28.0, 0.002, true);
  expect_refine_agrees(grid(10, 10), 30.0, 0.001, true);
}

// Random meshes: a jittered sphere and a jittered grid with boundary, several seeds.
TEST(NormalCoordinates, DelaunayRefineAgreesOnRandomMeshes) {
  for (const unsigned seed : {1u, 2u, 3u}) {
    SCOPED_TRACE(testing::Message() << "seed " << seed);
    expect_refine_agrees(test::jittered(icosphere(1), 0.15, seed), 28.0, 0.05);
    expect_refine_agrees(test::jittered(grid(6, 5), 0.3, seed), 30.0, 0.0);
  }
}

// angle_from_input_halfedge() (D-330): the angle at an input vertex from an input halfedge to an
// intrinsic one, from the integers, is the signposts' difference of directions (modulo Θ at an
// interior vertex), for every intrinsic halfedge leaving an input vertex and every input
// halfedge there, after a refinement that leaves input vertices with only inserted neighbours;
// on a closed surface with needles and on a jittered grid with boundary.
TEST(NormalCoordinates, AngleFromInputHalfedgeIsTheSignpostsTurn) {
  const std::vector<TriangleMesh> meshes = {test::jittered(uv_sphere(8, 24), 0.05, 2),
                                            test::jittered(grid(7, 6), 0.3, 4)};
  for (const TriangleMesh& m : meshes) {
    NormalCoordinateTriangulation nc(m.faces, m.positions);
    SignpostTriangulation st(m.faces, m.positions);
    RefineOptions o;
    o.min_angle_degrees = 28.0;
    o.max_area = 0.2 * total_area(nc.input()) / double(m.faces.size());
    ASSERT_EQ(delaunay_refine(nc, o).insertions, delaunay_refine(st, o).insertions);
    const IntrinsicTriangulation& tri = nc.intrinsic();
    const IntrinsicTriangulation& input = nc.input();
    double worst = 0.0;
    Index checked = 0, crossing = 0, inside = 0;
    for (Index h = 0; h < tri.n_halfedges(); ++h) {
      const Index v = tri.tail(h);
      if (v >= nc.n_input_vertices()) continue;
      const int n = nc.normal_coordinate(tri.edge(h));
      crossing += n > 0;
      inside += n == 0;
      for (Index g = 0; g < input.n_halfedges(); ++g) {
        if (input.tail(g) != v) continue;
        double want = st.halfedge_direction(h) - st.input_halfedge_direction(g);
        const double theta = st.vertex_angle_sum(v);
        if (!st.is_boundary_vertex(v)) want -= theta * std::round(want / theta);
        double got = nc.angle_from_input_halfedge(h, g);
        if (!st.is_boundary_vertex(v)) got -= theta * std::round((got - want) / theta);
        worst = std::max(worst, std::abs(got - want));
        ++checked;
      }
    }
    EXPECT_GT(crossing, 20);  // directions from a first crossing
    EXPECT_GT(inside, 5);     // and from inside a wedge (n = 0)
    EXPECT_GT(checked, 500);
    EXPECT_LT(worst, 1e-9);
    EXPECT_THROW(nc.angle_from_input_halfedge(tri.n_halfedges(), 0), InvalidInput);
  }
}

// Constrained refinement (a curve of input edges across a grid, EdgeConstraints): both
// representations make the same insertions and lengths, every constrained edge (the curve's
// pieces after splits) runs along the input edge it came from (n = −1), and the common
// subdivision still partitions the areas.
TEST(NormalCoordinates, ConstrainedRefineAgreesWithSignposts) {
  const int nx = 8;
  for (const double angle : {25.0, 30.0}) {
    SCOPED_TRACE(testing::Message() << "angle " << angle);
    const TriangleMesh flat = grid(nx, nx);
    const TriangleMesh m = test::jittered(flat, 0.04, 5);
    NormalCoordinateTriangulation nc(m.faces, m.positions);
    SignpostTriangulation st(m.faces, m.positions);
    const IntrinsicTriangulation& tri = nc.intrinsic();
    auto on_row = [&](Index v) { return std::abs(flat.positions(v, 1) - 0.5) < 1e-12; };
    std::vector<char> fa(tri.n_edges(), 0), fb;
    std::vector<Index> from(tri.n_edges(), kInvalidIndex);  // the input edge a piece came from
    for (Index e = 0; e < tri.n_edges(); ++e) {
      const Index h = tri.edge_halfedge(e);
      if (on_row(tri.tail(h)) && on_row(tri.head(h))) fa[e] = 1, from[e] = e;
    }
    ASSERT_EQ(std::count(fa.begin(), fa.end(), 1), nx);
    fb = fa;
    EdgeConstraints ca, cb;
    ca.flags = &fa;
    cb.flags = &fb;
    ca.on_split = [&](Index e, Index new_edge, Index, double) {
      from.resize(std::max<std::size_t>(from.size(), new_edge + 1), kInvalidIndex);
      from[new_edge] = from[e];
    };
    RefineOptions o;
    o.min_angle_degrees = angle;
    o.max_area = 0.01;
    const RefineReport a = delaunay_refine(nc, o, &ca), b = delaunay_refine(st, o, &cb);
    EXPECT_GT(a.constrained_splits + a.conforming_splits, 0);
    EXPECT_EQ(a.insertions, b.insertions);
    EXPECT_EQ(a.constrained_splits, b.constrained_splits);
    EXPECT_EQ(fa, fb);
    EXPECT_EQ(tri.lengths(), st.intrinsic().lengths());
    nc.validate();
    Index pieces = 0;
    for (Index e = 0; e < tri.n_edges(); ++e) {
      if (!is_flagged(&fa, e)) continue;
      ++pieces;
      ASSERT_EQ(nc.normal_coordinate(e), -1) << "constrained edge " << e;
      EXPECT_EQ(nc.input_edge_along(tri.edge_halfedge(e)), from[e]) << "constrained edge " << e;
    }
    EXPECT_GT(pieces, nx);
    expect_area_partition(nc);
    expect_input_edges_recovered(nc);
  }
}

// Cross-check on the bundled meshes (the shared corpus: ifem_bench integer-crosscheck):
// refinement to 25° and 30° with both representations gives the same insertions and lengths,
// the same locations of the intrinsic vertices on the input, and integers that partition the
// areas.
TEST(NormalCoordinates, RefineCrossCheckOnBundledMeshes) {
  for (const char* name : {"spot.obj", "bunny_npm_lowres.obj"}) {
    const io::SurfaceInput in = io::read_mesh((test::test_data() / name).string());
    for (const double angle : {25.0, 30.0}) {
      SCOPED_TRACE(testing::Message() << name << " angle " << angle);
      NormalCoordinateTriangulation nc(in.triangles, in.positions, kDefaultMollifyEpsilon);
      SignpostTriangulation st(in.triangles, in.positions, kDefaultMollifyEpsilon);
      RefineOptions o;
      o.min_angle_degrees = angle;
      const RefineReport a = delaunay_refine(nc, o), b = delaunay_refine(st, o);
      EXPECT_GT(a.insertions, 3);
      EXPECT_EQ(a.insertions, b.insertions);
      EXPECT_EQ(nc.intrinsic().lengths(), st.intrinsic().lengths());
      nc.validate();
      const std::vector<SurfacePoint> loc = vertex_locations(nc);
      const double tol = 1e-9 * mesh_scale(nc.input());
      for (Index v = nc.n_input_vertices(); v < nc.intrinsic().n_vertices(); ++v) {
        ASSERT_LT((st.position(loc[v]) - st.position(st.vertex_location(v))).norm(), tol)
            << "vertex " << v;
      }
      expect_area_partition(nc);
    }
  }
}

TEST(NormalCoordinates, VertexWithTwoBoundaryFans) {
  Positions x(7, 3);
  x << 0, 0, 0, 1, -0.5, 0, 1.2, 0.3, 0, 0.4, 1, 0, -1, 0.5, 0, -1.2, -0.3, 0, -0.4, -1, 0;
  const std::vector<Triangle> f = {{0, 1, 2}, {0, 2, 3}, {0, 4, 5}, {0, 5, 6}};
  NormalCoordinateTriangulation nc(f, x);
  SignpostTriangulation st(f, x);
  ASSERT_EQ(nc.spokes(0).size(), 6u);
  random_operations(nc, st, 60, 21, 6);
  EXPECT_GT(nc.intrinsic().n_vertices(), 10);
  nc.flip_to_delaunay();
  nc.validate();
  expect_input_edges_recovered(nc);
  expect_area_partition(nc);
}

// Two closed spheres pinched at one vertex (two closed fans there): roundabouts wrap within
// each fan. Random operations, then the invariants (no signposts: they keep one fan per vertex).
TEST(NormalCoordinates, PinchedVertexWithTwoClosedFans) {
  const TriangleMesh a = test::jittered(icosphere(1), 0.05, 31);
  TriangleMesh m = a;
  const Index n = static_cast<Index>(a.positions.rows());
  m.positions.conservativeResize(2 * n - 1, 3);
  auto id = [n](Index v) { return v == 0 ? 0 : n + v - 1; };  // vertex 0 shared
  for (Index v = 1; v < n; ++v) {
    m.positions.row(id(v)) = a.positions.row(v) + Eigen::RowVector3d(0.0, 0.0, 0.3 * (v % 2));
  }
  for (const Triangle& t : a.faces) m.faces.push_back({id(t[0]), id(t[1]), id(t[2])});
  NormalCoordinateTriangulation nc(m.faces, m.positions);
  SignpostTriangulation st(m.faces, m.positions);
  ASSERT_EQ(nc.spokes(0).size(), 10u);
  random_operations(nc, st, 200, 32, 7);
  nc.flip_to_delaunay();
  nc.validate();
  Index crossed = 0;
  for (Index e = 0; e < nc.intrinsic().n_edges(); ++e) crossed += nc.normal_coordinate(e) > 0;
  EXPECT_GT(crossed, 5);
  expect_input_edges_recovered(nc);
  expect_area_partition(nc);
}

// Real scans and CAD meshes of ../shared (mollified, as the CLI does): Delaunay flipping with
// both representations, the integers valid and equal to the signpost counts on a sample of
// about 3000 edges per mesh, and the same overlay pieces (spot, fandisk).
TEST(NormalCoordinates, SharedMeshesDelaunayAgreesWithSignposts) {
  IFEM_REQUIRE_SHARED_DATA();
  for (const char* name : {"rocketship.ply", "spot.obj", "fandisk.off"}) {
    const auto path = test::shared_data() / "meshes" / name;
    if (!std::filesystem::exists(path)) continue;
    SCOPED_TRACE(name);
    const io::SurfaceInput in = io::read_mesh(path.string());
    NormalCoordinateTriangulation nc(in.triangles, in.positions, kDefaultMollifyEpsilon);
    SignpostTriangulation st(in.triangles, in.positions, kDefaultMollifyEpsilon);
    EXPECT_EQ(nc.flip_to_delaunay().flips, st.flip_to_delaunay().flips);
    ASSERT_NO_THROW(nc.validate());
    const Index stride = std::max<Index>(1, nc.intrinsic().n_edges() / 3000);
    expect_matches_signposts(nc, st, 1e-8, stride);
    // the two overlays (about 2 s on rocketship's 56k faces: smaller meshes only)
    if (nc.input().n_faces() < 20000) expect_same_overlay(nc, st);
  }
}

// Moving inserted vertices inside their flat stars (move_inserted_vertex): the same moves as on
// signposts, to the same points (given as the same combination of the two layouts' ring
// vertices: the layouts differ by a rotation), after random insertions, splits (vertices on
// input edges, which the move takes off them) and flips. The recounted integers are valid,
// equal the signpost traces, recover every input edge and partition the areas.
TEST(NormalCoordinates, MoveInsertedVertexAgreesWithSignposts) {
  const std::vector<TriangleMesh> meshes = {test::jittered(icosphere(1), 0.1, 3),
                                            test::flat_square(5, 0.3, 4)};
  for (std::size_t i = 0; i < meshes.size(); ++i) {
    SCOPED_TRACE("mesh " + std::to_string(i));
    NormalCoordinateTriangulation nc(meshes[i].faces, meshes[i].positions);
    SignpostTriangulation st(meshes[i].faces, meshes[i].positions);
    random_operations(nc, st, 120, 30 + static_cast<unsigned>(i), i == 0 ? 7 : 6);
    ASSERT_FALSE(::testing::Test::HasFailure());
    std::mt19937 rng(7);
    std::uniform_real_distribution<double> unit(0.05, 0.45);
    Index moved = 0, off_input_edges = 0;
    for (int round = 0; round < 3; ++round) {
      for (Index v = nc.n_input_vertices(); v < nc.intrinsic().n_vertices(); ++v) {
        std::vector<Index> hs, hs_st;
        std::vector<Eigen::Vector2d> ring, ring_st;
        const bool a = inserted_vertex_star(nc.intrinsic(), v, nc.n_input_vertices(), &hs, &ring);
        ASSERT_EQ(a,
                  inserted_vertex_star(st.intrinsic(), v, st.n_input_vertices(), &hs_st, &ring_st))
            << "vertex " << v;
        if (!a) continue;
        ASSERT_EQ(hs, hs_st);
        const std::size_t k = static_cast<std::size_t>(rng() % ring.size());
        const double wa = unit(rng), wb = unit(rng);
        const std::size_t k1 = (k + 1) % ring.size();
        const bool on_edge = !nc.spokes(v).empty();
        const bool ma = nc.move_inserted_vertex(v, wa * ring[k] + wb * ring[k1]);
        ASSERT_EQ(ma, st.move_inserted_vertex(v, wa * ring_st[k] + wb * ring_st[k1]));
        moved += ma ? 1 : 0;
        off_input_edges += ma && on_edge ? 1 : 0;
        ASSERT_NO_THROW(nc.validate()) << "after moving vertex " << v;
      }
    }
    EXPECT_GT(moved, 10);
    EXPECT_GT(off_input_edges, 0);
    const std::vector<double>& la = nc.intrinsic().lengths();
    const std::vector<double>& lb = st.intrinsic().lengths();
    for (std::size_t e = 0; e < la.size(); ++e) ASSERT_NEAR(la[e], lb[e], 1e-12 * lb[e]);
    expect_matches_signposts(nc, st, 1e-8);
    expect_input_edges_recovered(nc);
    expect_area_partition(nc);
    EXPECT_EQ(nc.flip_to_delaunay().flips, st.flip_to_delaunay().flips);
    expect_matches_signposts(nc, st, 1e-8);
  }
}

// Every intrinsic edge is a straight path over the input: on an unmollified input, the 3D
// polyline through its ends (as the common subdivision places them) and its traced crossings has
// the edge's length (1e-9 of the mesh size). Wrong integers put crossings on other input edges
// or vertices in other faces, which lengthens the polyline; this holds where signpost traces
// cannot be compared (near a needle fan's tip they miss crossings at rounding level).
void expect_straight_paths(const NormalCoordinateTriangulation& nc) {
  const IntrinsicTriangulation& tri = nc.intrinsic();
  const CommonSubdivision cs = common_subdivision(nc);
  const double tol = 1e-9 * mesh_scale(nc.input());
  for (Index e = 0; e < tri.n_edges(); ++e) {
    const Index h = tri.edge_halfedge(e);
    Eigen::Vector3d last = cs.positions.row(tri.tail(h));
    double length = 0.0;
    for (const InputCrossing& c : nc.trace_edge(e)) {
      const Eigen::Vector3d y = nc.crossing_position(c);
      length += (y - last).norm();
      last = y;
    }
    length += (Eigen::Vector3d(cs.positions.row(tri.head(h))) - last).norm();
    ASSERT_NEAR(length, tri.length(e), tol) << "edge " << e;
  }
}

// ODT relaxation after refinement (relax_inserted_vertices, one algorithm over both
// representations): the same moves, rejections and splits, the same triangulation after its
// Delaunay flips (edge lengths to 1e-9 relative), integers equal to the signpost traces, every
// intrinsic edge a straight path over the input, every input edge recovered, the common
// subdivision partitioning the areas.
// Varied: the mesh (a needle fan, a jittered sphere, a jittered grid with boundary), passes
// {1 (without the min-angle guard), 3} and max_edge_length {0, 0.7 × the mean edge}.
void expect_relax_agrees(const TriangleMesh& m, double angle, int iterations, bool split) {
  SCOPED_TRACE(testing::Message() << "iterations " << iterations << " split " << split);
  NormalCoordinateTriangulation nc(m.faces, m.positions);
  SignpostTriangulation st(m.faces, m.positions);
  RefineOptions o;
  o.min_angle_degrees = angle;
  o.max_area = total_area(nc.intrinsic()) / 150.0;  // vertices inside the needle fan too
  delaunay_refine(nc, o);
  delaunay_refine(st, o);
  RelaxOptions r;
  r.iterations = iterations;
  r.keep_min_angle = iterations > 1;  // one unguarded pass: every star moves
  if (split) r.max_edge_length = 0.7 * mean_edge_length(nc.intrinsic());
  const RelaxReport a = relax_inserted_vertices(nc, r), b = relax_inserted_vertices(st, r);
  if (!r.keep_min_angle) {
    EXPECT_GT(a.moved, 0);
  }
  EXPECT_EQ(a.moved, b.moved);
  EXPECT_EQ(a.rejected, b.rejected);
  EXPECT_EQ(a.skipped_boundary, b.skipped_boundary);
  EXPECT_EQ(a.splits, b.splits);
  EXPECT_EQ(a.flips, b.flips);
  if (split) {
    EXPECT_GT(a.splits, 0);
  }
  const std::vector<double>& la = nc.intrinsic().lengths();
  const std::vector<double>& lb = st.intrinsic().lengths();
  ASSERT_EQ(la.size(), lb.size());
  for (std::size_t e = 0; e < la.size(); ++e) ASSERT_NEAR(la[e], lb[e], 1e-9 * lb[e]);
  ASSERT_NO_THROW(nc.validate());
  expect_matches_signposts(nc, st, 1e-8);
  expect_straight_paths(nc);
  expect_input_edges_recovered(nc);
  expect_area_partition(nc);
}

TEST(NormalCoordinates, RelaxAgreesWithSignposts) {
  // the exactly symmetric needle_fan(40): vertices on its symmetry axis, an input edge (D-305)
  const TriangleMesh meshes[] = {needle_fan(40), test::jittered(icosphere(1), 0.15, 2),
                                 test::jittered(grid(6, 5), 0.3, 3)};
  for (std::size_t i = 0; i < std::size(meshes); ++i) {
    SCOPED_TRACE("mesh " + std::to_string(i));
    for (const int iterations : {1, 3}) {
      for (const bool split : {false, true}) {
        expect_relax_agrees(meshes[i], 25.0, iterations, split);
      }
    }
  }
}

}  // namespace
}  // namespace ifem::intrinsic

namespace ifem::intrinsic {
namespace {

// Refinement to 30° of one input with both representations (crosscheck_refine, mollified as
// the CLI does): both succeed (integer coordinates at least), make the same insertions with
// bit-identical lengths, place every intrinsic vertex at the same point (1e-6 of the mean edge
// length), and each common subdivision partitions the input faces' areas (1e-12 relative to the
// mean face area).
RefineCrosscheck expect_crosscheck(const std::string& name, const TriangleMesh& m,
                                   bool signposts_must_succeed = true) {
  SCOPED_TRACE(name);
  const SignpostTriangulation s0(m.faces, m.positions, kDefaultMollifyEpsilon);
  const NormalCoordinateTriangulation n0(m.faces, m.positions, kDefaultMollifyEpsilon);
  RefineOptions o;
  o.min_angle_degrees = 30.0;
  const RefineCrosscheck c = crosscheck_refine(s0, n0, o);
  std::printf("| %s | %zu | %s | %s | %lld | %s | Δℓ %.1e, Δx %.1e, area %.1e / %.1e |\n",
              name.c_str(), m.faces.size(), c.signposts.ok ? "ok" : c.signposts.error.c_str(),
              c.integer.ok ? "ok" : c.integer.error.c_str(),
              static_cast<long long>(c.integer.report.insertions), c.agree() ? "agree" : "DIFFER",
              c.max_length_difference, c.max_vertex_distance, c.signposts.area_partition_error,
              c.integer.area_partition_error);
  EXPECT_TRUE(c.integer.ok) << c.integer.error;
  if (signposts_must_succeed) {
    EXPECT_TRUE(c.signposts.ok) << c.signposts.error;
  }
  if (c.integer.ok) {
    EXPECT_LT(c.integer.area_partition_error, 1e-12);
  }
  if (c.signposts.ok) {
    EXPECT_LT(c.signposts.area_partition_error, 1e-12);
  }
  if (c.signposts.ok && c.integer.ok) {
    EXPECT_TRUE(c.same_insertions);
    EXPECT_EQ(c.max_length_difference, 0.0);
    EXPECT_LT(c.max_vertex_distance, 1e-6 * c.mean_length);  // the same locations
    EXPECT_TRUE(c.agree());
  }
  return c;
}

// The generated adversarial set (intrinsic/generators/mesh_generators.h): needle fans, stacked
// needle soups with coincident rims, vertices nearly coincident with input vertices (relative
// gaps 1e-6 and 1e-9), and range scans (many components, boundary, needle rims). The needle
// soup and the nearly coincident grids are the inputs on which the integer common subdivision
// did not partition the input faces before D-300 (errors 1e-7..5e-2).
TEST(IntegerCrosscheck, GeneratedAdversarialInputsRefineAndAgree) {
  std::printf("| input | faces | signposts | integer | insertions | agreement | |\n");
  EXPECT_GT(expect_crosscheck("needle fan 44", needle_fan(44)).integer.report.insertions, 0);
  expect_crosscheck("needle fan 80 × 0.02", needle_fan(80, 0.02));
  expect_crosscheck("needle soup 3", needle_soup(3));
  for (const double gap : {1e-6, 1e-9}) {
    const RefineCrosscheck c = expect_crosscheck("nearly coincident, gap " + std::to_string(gap),
                                                 nearly_coincident_grid(6, 10, gap, 3));
    EXPECT_GT(c.integer.report.insertions, 0);
  }
  for (const unsigned long seed : {1ul, 2ul}) {
    RangeScanOptions scan;
    scan.nx = scan.ny = 16;
    scan.objects = 5;
    scan.islands = 3;
    scan.seed = seed;
    const TriangleMesh m = range_scan(scan);
    const RefineCrosscheck c = expect_crosscheck("range scan seed " + std::to_string(seed), m);
    EXPECT_GT(c.integer.report.insertions, 0);
  }
}

// The generators' promises the cross-check relies on.
TEST(IntegerCrosscheck, GeneratorsMakeWhatTheySay) {
  const TriangleMesh fan = needle_fan(20, 0.05);
  EXPECT_EQ(fan.faces.size(), 18u);
  EXPECT_THROW(needle_fan(3), InvalidInput);
  const TriangleMesh soup = needle_soup(4);
  EXPECT_EQ(soup.faces.size(), 48u);
  EXPECT_EQ(soup.positions.rows(), 56);
  const double gap = 1e-9;
  const TriangleMesh g = nearly_coincident_grid(5, 7, gap, 2);
  EXPECT_EQ(g.faces.size(), 50u + 14u);
  EXPECT_EQ(g.positions.rows(), 36 + 7);
  for (Index v = 36; v < 43; ++v) {  // each added vertex within gap × (cell size) of a corner
    double nearest = 1.0;
    for (Index w = 0; w < 36; ++w)
      nearest = std::min(nearest, (g.positions.row(v) - g.positions.row(w)).norm());
    EXPECT_LT(nearest, gap);
    EXPECT_GT(nearest, 0.0);
  }
  EXPECT_THROW(nearly_coincident_grid(5, 7, 0.0), InvalidInput);
}

// Every edge-manifold orientable mesh of ../shared/data/meshes up to 4,000 faces (a size cap
// that keeps the test to a few seconds): refinement to 30° with integer coordinates succeeds,
// agrees with signposts where they succeed, and partitions the areas. Meshes the
// triangulation refuses (not edge-manifold / orientable) are listed, not counted.
TEST(IntegerCrosscheck, SharedMeshesSweep) {
  IFEM_REQUIRE_SHARED_DATA();
  std::vector<std::filesystem::path> files;
  for (const auto& f : std::filesystem::directory_iterator(test::shared_data() / "meshes")) {
    const std::string ext = f.path().extension().string();
    if (ext == ".obj" || ext == ".off" || ext == ".ply" || ext == ".stl") files.push_back(f.path());
  }
  std::sort(files.begin(), files.end());
  int checked = 0;
  std::printf("| mesh | faces | signposts | integer | insertions | agreement | |\n");
  for (const auto& path : files) {
    const std::string name = path.filename().string();
    io::SurfaceInput in;
    try {
      in = io::read_mesh(path.string());
    } catch (const std::exception& e) {
      std::printf("| %s | not read: %s |\n", name.c_str(), e.what());
      continue;
    }
    if (in.triangles.empty() || in.triangles.size() > 4000) continue;
    try {  // refused inputs: not edge-manifold, not orientable
      const SignpostTriangulation probe(in.triangles, in.positions, kDefaultMollifyEpsilon);
    } catch (const std::exception& e) {
      std::printf("| %s | %zu | not used: %s |\n", name.c_str(), in.triangles.size(), e.what());
      continue;
    }
    expect_crosscheck(name, {in.positions, in.triangles}, false);
    ++checked;
  }
  EXPECT_GT(checked, 0) << "no mesh of " << test::shared_data() / "meshes"
                        << " was checked";
}

}  // namespace
}  // namespace ifem::intrinsic
