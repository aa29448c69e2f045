// Exact geodesic distance (intrinsic/geodesic/exact_distance.h) against known truth: Euclidean
// distance on flat domains (convex, around the reflex corner of an L, around the corners of a
// hole), the pruning of one window by another where it must and must not cut, the analytic distance
// on a cone of total angle > 2π (a saddle's shadow), the exact references of tests/data/reference
// and ../shared/data/reference (CGAL's exact code; MANIFEST.md), invariance under intrinsic
// Delaunay flips, the tufted cover of a nonmanifold book, paths whose length is the distance,
// the memory budget and bad sources.
#include "intrinsic/geodesic/exact_distance.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <utility>

#include "helpers.h"
#include "intrinsic/core/errors.h"
#include "intrinsic/core/geometry.h"
#include "intrinsic/generators/mesh_generators.h"
#include "intrinsic/io/mesh_io.h"
#include "intrinsic/surface/tufted_cover.h"

namespace ifem::intrinsic {
namespace {

// 3D position of a surface point of a triangulation built by from_positions (no flips).
Eigen::Vector3d position(const IntrinsicTriangulation& tri, const Positions& x,
                         const SurfacePoint& p) {
  Eigen::Vector3d q = Eigen::Vector3d::Zero();
  for (int k = 0; k < 3; ++k) q += p.bary[k] * x.row(tri.tail(3 * p.face + k)).transpose();
  return q;
}

// Length of the path back from v, measured in 3D (straight segments inside faces).
double path_length(const ExactDistance& d, const Positions& x, Index v) {
  const std::vector<SurfacePoint> path = d.path_to_source(v);
  double len = 0.0;
  for (std::size_t i = 1; i < path.size(); ++i) {
    len += (position(*d.tri, x, path[i]) - position(*d.tri, x, path[i - 1])).norm();
  }
  return len;
}

TEST(ExactDistance, FlatSquareIsEuclidean) {
  for (unsigned seed : {1u, 2u}) {
    const TriangleMesh m = test::flat_square(12, 0.35, seed);
    const auto tri = IntrinsicTriangulation::from_positions(m.faces, m.positions);
    const Index src = Index(m.positions.rows() / 2 + 3);
    const ExactDistance d = exact_distance(tri, std::vector<Index>{src});
    for (Index v = 0; v < tri.n_vertices(); ++v) {
      const double e = (m.positions.row(v) - m.positions.row(src)).norm();
      ASSERT_NEAR(d.distance[v], e, 1e-12) << "vertex " << v;
      ASSERT_NEAR(path_length(d, m.positions, v), e, 1e-12) << "path from " << v;
    }
    // A source inside a face, and one on an edge.
    for (const Eigen::Vector3d& b :
         {Eigen::Vector3d(0.2, 0.3, 0.5), Eigen::Vector3d(0.4, 0.6, 0)}) {
      const SurfacePoint p{7, b};
      const Eigen::Vector3d at = position(tri, m.positions, p);
      const ExactDistance dp = exact_distance(tri, std::vector<SurfacePoint>{p});
      for (Index v = 0; v < tri.n_vertices(); ++v) {
        const double e = (m.positions.row(v).transpose() - at).norm();
        ASSERT_NEAR(dp.distance[v], e, 1e-12) << "vertex " << v;
        ASSERT_NEAR(path_length(dp, m.positions, v), e, 1e-12) << "path from " << v;
      }
    }
  }
}

// Unit square less (1/2, 1]²: a path that would enter the missing quarter bends at (1/2, 1/2).
TEST(ExactDistance, FlatLShapeBendsAtTheReflexCorner) {
  const TriangleMesh m = test::flat_l_shape(16, 0.3, 3);
  const auto tri = IntrinsicTriangulation::from_positions(m.faces, m.positions);
  const Eigen::Vector2d c(0.5, 0.5);
  int bent = 0;
  auto above = [](double a, double b, double* lo, double* hi) {
    if (a > 0.5 && b > 0.5) {
      *lo = 0, *hi = 1;
    } else if (a > 0.5) {
      *lo = 0, *hi = (a - 0.5) / (a - b);
    } else if (b > 0.5) {
      *lo = (0.5 - a) / (b - a), *hi = 1;
    } else {
      *lo = 1, *hi = 0;
    }
  };
  for (Index src : {Index(0), Index(m.positions.rows() - 1), Index(40)}) {
    const Eigen::Vector2d s = m.positions.row(src).head<2>();
    const ExactDistance d = exact_distance(tri, std::vector<Index>{src});
    for (Index v = 0; v < tri.n_vertices(); ++v) {
      const Eigen::Vector2d p = m.positions.row(v).head<2>();
      // The open intervals of t where x(t) > 1/2 and where y(t) > 1/2 overlap: s→p is blocked.
      double xl, xh, yl, yh;
      above(s.x(), p.x(), &xl, &xh);
      above(s.y(), p.y(), &yl, &yh);
      const bool blocked = std::max(xl, yl) < std::min(xh, yh) - 1e-12;
      const double e = blocked ? (s - c).norm() + (c - p).norm() : (s - p).norm();
      bent += blocked;
      ASSERT_NEAR(d.distance[v], e, 1e-12) << "source " << src << " vertex " << v;
      ASSERT_NEAR(path_length(d, m.positions, v), e, 1e-12) << "path from " << v;
    }
  }
  EXPECT_GT(bent, 50);  // the test reached behind the corner
}

// prune_window_by() on the unit edge [0, 1]: windows {b0, b1, ix, iy, σ, h, parent}.
TEST(ExactDistance, PruneWindowByAnotherOnlyWhereProven) {
  using W = ExactDistance::Window;
  const auto len = [](const W& w, double x) { return w.sigma + std::hypot(x - w.ix, w.iy); };
  // Must not prune: `other` (σ' = 0 < σ = 1) is shorter at both ends of w but longer in its
  // middle, where w's path is the shortest: nothing is cut.
  const W w{0.0, 1.0, 0.5, -0.1, 1.0, 0, 0}, far{0.0, 1.0, 0.5, -1.3, 0.0, 0, 0};
  ASSERT_LT(len(far, 0.0), len(w, 0.0));
  ASSERT_LT(len(far, 1.0), len(w, 1.0));
  ASSERT_GT(len(far, 0.5), len(w, 0.5));
  EXPECT_EQ(prune_window_by(far, w), std::make_pair(0.0, 1.0));
  // σ' ≥ σ and shorter at both ends: shorter all along (convex), nothing is left.
  const W u{0.0, 1.0, 0.5, -1.0, 0.0, 0, 0}, near{0.0, 1.0, 0.5, -0.5, 0.3, 0, 0};
  for (double x = 0.0; x <= 1.0; x += 0.125) ASSERT_LT(len(near, x), len(u, x));
  const auto [a0, a1] = prune_window_by(near, u);
  EXPECT_LE(a1, a0);
  // Shorter on one side only: cut at the crossing (found here by bisection), never beyond the
  // other window's own interval.
  for (const double sigma : {0.0, 0.1, 0.25}) {
    const W left{0.0, 1.0, 0.0, -1.0, 0.0, 0, 0}, right{0.0, 1.0, 1.0, -1.0, sigma, 0, 0};
    double lo = 0.0, hi = 1.0;
    for (int i = 0; i < 100; ++i) {
      const double mid = 0.5 * (lo + hi);
      (len(right, mid) <= len(left, mid) ? hi : lo) = mid;
    }
    const auto [c0, c1] = prune_window_by(right, left);
    EXPECT_EQ(c0, 0.0);
    EXPECT_NEAR(c1, hi, 1e-12) << "sigma " << sigma;
    EXPECT_LE(len(right, c1), len(left, c1) * (1.0 + 1e-15)) << "the cut point is proven";
    W part = right;
    part.b0 = 0.75;  // the other window covers [0.75, 1] only
    const auto [p0, p1] = prune_window_by(part, left);
    EXPECT_EQ(p0, 0.0);
    EXPECT_NEAR(p1, std::max(hi, 0.75), 1e-12) << "sigma " << sigma;
    // and the other way round: σ' < σ, nothing is cut
    if (sigma > 0.0) {
      EXPECT_EQ(prune_window_by(left, right), std::make_pair(0.0, 1.0));
    }
  }
}

// point_beats_window(): a vertex that beats both ends of a window beats all of it only when its
// distance is at least the window's σ; below σ the window may win between the ends.
TEST(ExactDistance, PointBeatsWindowOnlyWhereItBeatsAllOfIt) {
  using W = ExactDistance::Window;
  const auto len = [](const W& w, double x) { return w.sigma + std::hypot(x - w.ix, w.iy); };
  const auto pt = [](double px, double py, double d, double x) {
    return d + std::hypot(x - px, py);
  };
  // A long edge [0, 200], w's image just below its middle (σ = 1), the vertex 10 above the
  // middle at distance 0.4: shorter at both ends, longer in the middle.
  const W w{0.0, 200.0, 100.0, -0.01, 1.0, 0, 0};
  ASSERT_LT(pt(100.0, 10.0, 0.4, 0.0), len(w, 0.0));
  ASSERT_LT(pt(100.0, 10.0, 0.4, 200.0), len(w, 200.0));
  ASSERT_GT(pt(100.0, 10.0, 0.4, 100.0), len(w, 100.0));
  EXPECT_FALSE(point_beats_window(100.0, 10.0, 0.4, w, 1e-12));
  // d < σ and shorter everywhere (the vertex lies between the image and the edge).
  const W u{0.0, 1.0, 0.5, -1.0, 1.0, 0, 0};
  EXPECT_TRUE(point_beats_window(0.5, -0.5, 0.2, u, 1e-12));
  // d ≥ σ: both ends are enough (convex).
  const W z{0.0, 1.0, 0.5, -1.0, 0.0, 0, 0};
  EXPECT_TRUE(point_beats_window(0.5, -0.5, 0.3, z, 1e-12));
  EXPECT_FALSE(point_beats_window(0.5, -0.5, 0.6, z, 1e-12));
  // Random configurations: a true answer is never contradicted along the interval.
  std::srand(7);
  const auto uni = [](double a, double b) {
    return a + (b - a) * (std::rand() / double(RAND_MAX));
  };
  int yes = 0, no_below_sigma = 0;
  for (int k = 0; k < 4000; ++k) {
    const W r{uni(0.0, 0.4), uni(0.6, 1.0), uni(-1.0, 2.0), uni(-1.0, -0.001), uni(0.0, 2.0), 0, 0};
    const double px = uni(-1.0, 2.0), py = uni(-3.0, 3.0), d = uni(0.0, 2.0);
    const bool beats = point_beats_window(px, py, d, r, 1e-12);
    bool everywhere = true;
    for (int i = 0; i <= 400; ++i) {
      const double x = r.b0 + (r.b1 - r.b0) * i / 400.0;
      everywhere = everywhere && pt(px, py, d, x) <= len(r, x);
    }
    if (beats) {
      ++yes;
      ASSERT_TRUE(everywhere) << "case " << k;
    }
    const bool ends = pt(px, py, d, r.b0) < len(r, r.b0) * (1 - 1e-12) &&
                      pt(px, py, d, r.b1) < len(r, r.b1) * (1 - 1e-12);
    if (ends && !everywhere && d < r.sigma) ++no_below_sigma;
  }
  EXPECT_GT(yes, 200);
  EXPECT_GT(no_below_sigma, 0);  // the case both-ends-only gets wrong does occur
}

// Open square (0.4, 0.6)² (the hole below): true when the segment a→b passes through it.
bool through_hole(const Eigen::Vector2d& a, const Eigen::Vector2d& b) {
  double lo = 0.0, hi = 1.0;
  for (int k = 0; k < 2; ++k) {
    const double d = b[k] - a[k];
    if (d == 0.0) {
      if (!(a[k] > 0.4 && a[k] < 0.6)) return false;
      continue;
    }
    const double t0 = (0.4 - a[k]) / d, t1 = (0.6 - a[k]) / d;
    lo = std::max(lo, std::min(t0, t1));
    hi = std::min(hi, std::max(t0, t1));
  }
  return lo < hi - 1e-12;
}

// The unit square less the hole (0.4, 0.6)², a 20×20 grid: the four corners of the hole are
// pseudo-sources at different distances whose windows cross the same edges as the source's and
// each other's, in both orders (a farther one pushed first, a nearer one first), which is where
// pruning one window by another on its edge may cut only what the other beats. Truth: shortest
// paths in the visibility graph of the source and the hole's corners.
TEST(ExactDistance, FlatSquareWithAHoleBendsAtItsCorners) {
  const int n = 20;
  Positions x((n + 1) * (n + 1), 3);
  for (int j = 0; j <= n; ++j) {
    for (int i = 0; i <= n; ++i) x.row(j * (n + 1) + i) << double(i) / n, double(j) / n, 0.0;
  }
  std::vector<std::array<Index, 3>> faces;
  for (int j = 0; j < n; ++j) {
    for (int i = 0; i < n; ++i) {
      if (i >= 8 && i < 12 && j >= 8 && j < 12) continue;
      const Index a = j * (n + 1) + i, b = a + 1, c = a + n + 2, d = a + n + 1;
      if ((i + j) % 2 == 0) {
        faces.push_back({a, b, c});
        faces.push_back({a, c, d});
      } else {
        faces.push_back({a, b, d});
        faces.push_back({b, c, d});
      }
    }
  }
  const auto tri = IntrinsicTriangulation::from_positions(faces, x);
  const std::vector<Eigen::Vector2d> corners = {{0.4, 0.4}, {0.6, 0.4}, {0.6, 0.6}, {0.4, 0.6}};
  int bent = 0;
  for (const Index src : {Index(0), Index(2 * (n + 1) + 10), Index(15 * (n + 1) + 3),
                          Index(10 * (n + 1) + 20), Index(13 * (n + 1) + 12)}) {
    const Eigen::Vector2d s = x.row(src).head<2>();
    // Distances from s to the corners through the visibility graph (4 rounds of relaxation).
    std::vector<double> dc(4);
    for (int k = 0; k < 4; ++k) {
      dc[k] = through_hole(s, corners[k]) ? 1e300 : (s - corners[k]).norm();
    }
    for (int round = 0; round < 4; ++round) {
      for (int a = 0; a < 4; ++a) {
        for (int b = 0; b < 4; ++b) {
          if (!through_hole(corners[a], corners[b])) {
            dc[b] = std::min(dc[b], dc[a] + (corners[a] - corners[b]).norm());
          }
        }
      }
    }
    const ExactDistance d = exact_distance(tri, std::vector<Index>{src});
    for (Index v = 0; v < tri.n_vertices(); ++v) {
      if (tri.vertex_halfedge(v) == kInvalidIndex) continue;  // inside the hole
      const Eigen::Vector2d p = x.row(v).head<2>();
      double e = through_hole(s, p) ? 1e300 : (s - p).norm();
      bent += e > 1e299;
      for (int k = 0; k < 4; ++k) {
        if (!through_hole(corners[k], p)) e = std::min(e, dc[k] + (corners[k] - p).norm());
      }
      ASSERT_NEAR(d.distance[v], e, 1e-12) << "source " << src << " vertex " << v;
      ASSERT_NEAR(path_length(d, x, v), e, 1e-12) << "path from " << v;
    }
  }
  EXPECT_GT(bent, 100);  // the test reached behind the hole
}

// A flat cone of total angle 2.5π (a saddle at the apex), rings of m vertices, built from
// lengths alone. Points at polar (r, θ) with angular separation φ (the shorter way round) from
// the source: the law of cosines when φ < π, else r_s + r through the apex (its shadow).
TEST(ExactDistance, SaddleConeShadow) {
  const double theta = 2.5 * kPi;
  const int m = 40, rings = 6;
  auto vid = [&](int ring, int i) { return Index(1 + (ring - 1) * m + (i % m)); };
  auto polar = [&](Index v) {
    if (v == 0) return Eigen::Vector2d(0, 0);
    return Eigen::Vector2d(double((v - 1) / m + 1), theta * ((v - 1) % m) / m);
  };
  auto dist = [&](Index a, Index b) {
    const Eigen::Vector2d pa = polar(a), pb = polar(b);
    double dth = std::abs(pa.y() - pb.y());
    dth = std::min(dth, theta - dth);
    return std::sqrt(
        std::max(0.0, pa.x() * pa.x() + pb.x() * pb.x() - 2 * pa.x() * pb.x() * std::cos(dth)));
  };
  std::vector<Triangle> faces;
  for (int i = 0; i < m; ++i) faces.push_back({0, vid(1, i), vid(1, i + 1)});
  for (int r = 1; r < rings; ++r) {
    for (int i = 0; i < m; ++i) {
      faces.push_back({vid(r, i), vid(r + 1, i), vid(r + 1, i + 1)});
      faces.push_back({vid(r, i), vid(r + 1, i + 1), vid(r, i + 1)});
    }
  }
  Eigen::MatrixX3d lengths(faces.size(), 3);
  for (std::size_t f = 0; f < faces.size(); ++f) {
    for (int s = 0; s < 3; ++s) lengths(f, s) = dist(faces[f][s], faces[f][(s + 1) % 3]);
  }
  const Index nv = 1 + rings * m;
  const auto tri = IntrinsicTriangulation::from_side_lengths(faces, nv, lengths);
  for (Index src : {vid(2, 0), vid(4, 7)}) {
    const ExactDistance d = exact_distance(tri, std::vector<Index>{src});
    int shadow = 0;
    for (Index v = 0; v < nv; ++v) {
      const Eigen::Vector2d ps = polar(src), pv = polar(v);
      double phi = std::abs(ps.y() - pv.y());
      phi = std::min(phi, theta - phi);
      const double e = phi < kPi ? dist(src, v) : ps.x() + pv.x();
      shadow += phi >= kPi;
      ASSERT_NEAR(d.distance[v], e, 1e-12 * rings) << "source " << src << " vertex " << v;
    }
    EXPECT_GT(shadow, 20);
  }
}

// Three unit squares ("pages") sharing the spine x = 0, 0 ≤ y ≤ 1: a nonmanifold edge fan. On
// the tufted cover, a path from page a to page b unfolds into the plane (−x_a, y_a), (x_b, y_b):
// straight when it crosses the spine, else through the nearer spine end.
TEST(ExactDistance, TuftedCoverOfANonmanifoldBook) {
  const int n = 6;
  TriangleMesh m;
  std::vector<Eigen::Vector3d> pts;
  std::vector<Eigen::Vector3i> page_xy;  // page, i, j
  auto id = [&](int page, int i, int j) {
    if (i == 0) return Index(j);  // spine vertices shared
    return Index((n + 1) + page * n * (n + 1) + (i - 1) * (n + 1) + j);
  };
  const Eigen::Vector3d dirs[3] = {
      {1, 0, 0}, {-0.5, 0.8660254037844386, 0}, {-0.5, -0.8660254037844386, 0}};
  for (int j = 0; j <= n; ++j)
    pts.push_back(Eigen::Vector3d(0, 0, double(j) / n)), page_xy.push_back({-1, 0, j});
  for (int p = 0; p < 3; ++p) {
    for (int i = 1; i <= n; ++i) {
      for (int j = 0; j <= n; ++j) {
        pts.push_back(dirs[p].normalized() * (double(i) / n) +
                      Eigen::Vector3d(0, 0, double(j) / n));
        page_xy.push_back({p, i, j});
      }
    }
    for (int i = 0; i < n; ++i) {
      for (int j = 0; j < n; ++j) {
        m.faces.push_back({id(p, i, j), id(p, i + 1, j), id(p, i + 1, j + 1)});
        m.faces.push_back({id(p, i, j), id(p, i + 1, j + 1), id(p, i, j + 1)});
      }
    }
  }
  m.positions.resize(Eigen::Index(pts.size()), 3);
  for (std::size_t k = 0; k < pts.size(); ++k) m.positions.row(k) = pts[k].transpose();
  const IntrinsicTriangulation cover = tufted_cover(m.faces, m.positions);
  const Index src = id(0, 4, 1);
  const ExactDistance d = exact_distance(cover, std::vector<Index>{src});
  const Eigen::Vector2d s(4.0 / n, 1.0 / n);
  for (Index v = 0; v < Index(pts.size()); ++v) {
    const Eigen::Vector3i q = page_xy[v];
    const Eigen::Vector2d p(double(q[1]) / n, double(q[2]) / n);
    double e;
    if (q[0] == 0 || q[0] == -1) {
      e = (s - p).norm();
    } else {
      const Eigen::Vector2d a(-s.x(), s.y());
      const double t = a.x() / (a.x() - p.x());  // where a → p crosses x = 0
      const double y = a.y() + t * (p.y() - a.y());
      e = (y >= 0 && y <= 1)
              ? (a - p).norm()
              : std::min((a - Eigen::Vector2d(0, 0)).norm() + p.norm(),
                         (a - Eigen::Vector2d(0, 1)).norm() + (p - Eigen::Vector2d(0, 1)).norm());
    }
    ASSERT_NEAR(d.distance[v], e, 1e-12) << "vertex " << v << " page " << q[0];
  }
}

TEST(ExactDistance, SameAfterDelaunayFlipsAndSeveralSources) {
  const TriangleMesh m = test::jittered(icosphere(6), 0.15);
  auto tri = IntrinsicTriangulation::from_positions(m.faces, m.positions);
  const std::vector<Index> src{0, 100, 250};
  const ExactDistance before = exact_distance(tri, src);
  const FlipReport fr = tri.flip_to_delaunay();
  EXPECT_GT(fr.flips, 10u);
  const ExactDistance after = exact_distance(tri, src);
  for (Index v = 0; v < tri.n_vertices(); ++v) {
    ASSERT_NEAR(before.distance[v], after.distance[v], 1e-12) << "vertex " << v;
    double one = std::numeric_limits<double>::infinity();
    if (v < 3) {  // the minimum over single-source runs (a few vertices: cost)
      for (Index s : src) {
        one = std::min(one, exact_distance(tri, std::vector<Index>{s}).distance[v]);
      }
      ASSERT_NEAR(after.distance[v], one, 1e-12) << "vertex " << v;
    }
    const Index k = after.nearest_source(v);
    ASSERT_GE(k, 0);
  }
}

// Against the exact references (CGAL's exact code): every edge-manifold reference mesh up to
// 12k vertices (the bundled ones always, ../shared/data's when present), 1e-9 relative; on the
// references of repaired (cut-apart) meshes the tufted cover is at most the reference.
TEST(ExactDistance, ReferenceMeshes) {
  int bundled = 0, shared = 0;
  for (const test::ReferenceCase& ref : test::reference_cases()) {
    ASSERT_FALSE(ref.mesh.empty()) << ref.exact << ": no mesh " << ref.stem;
    // CI time: one source per shared mesh (both with IFEM_TEST_LARGE, which adds the large ones)
    const bool large = std::getenv("IFEM_TEST_LARGE") != nullptr;
    if (!ref.bundled && !large && ref.src != 0) continue;
    const io::SurfaceInput in = io::read_mesh(ref.mesh.string());
    if (in.positions.rows() > 12000 && !large) continue;
    const Eigen::VectorXd exact = io::read_values(ref.exact.string());
    ASSERT_EQ(exact.size(), in.positions.rows());
    IntrinsicTriangulation tri;
    bool manifold = true;
    try {
      tri = IntrinsicTriangulation::from_positions(in.triangles, in.positions);
    } catch (const NonManifoldInput&) {
      manifold = false;
      tri = tufted_cover(in.triangles, in.positions);
    }
    const ExactDistance d = exact_distance(tri, std::vector<Index>{Index(ref.src)});
    double worst = 0.0;
    int checked = 0;
    for (Index v = 0; v < exact.size(); ++v) {
      if (!std::isfinite(exact[v])) continue;
      const double scale = std::max(exact[v], 1e-300);
      const double rel = (d.distance[v] - exact[v]) / scale;
      worst = std::max(worst, manifold ? std::abs(rel) : rel);
      ++checked;
    }
    std::printf("%-22s src %6d V %6d windows %9zu  %s max rel %.2e\n", ref.stem.c_str(),
                int(ref.src), int(exact.size()), d.windows, manifold ? "exact" : "tufted<=", worst);
    EXPECT_GT(checked, exact.size() / 2) << ref.exact;
    EXPECT_LE(worst, 1e-9) << ref.exact;
    ++(ref.bundled ? bundled : shared);
  }
  test::expect_references_checked(bundled, shared);
}

TEST(ExactDistance, PathLengthEqualsDistanceOnBunny) {
  const io::SurfaceInput in = io::read_mesh((test::test_data() / "bunny_npm_lowres.obj").string());
  const auto tri = IntrinsicTriangulation::from_positions(in.triangles, in.positions);
  const ExactDistance d = exact_distance(tri, std::vector<Index>{5});
  for (Index v = 0; v < tri.n_vertices(); v += 7) {
    ASSERT_NEAR(path_length(d, in.positions, v), d.distance[v], 1e-9 * (1 + d.distance[v]))
        << "vertex " << v;
  }
}

// keep_paths = false: the same distances and windows, no store, and the path calls refuse.
TEST(ExactDistance, WithoutPathsSameDistancesNoStore) {
  const io::SurfaceInput in = io::read_mesh((test::test_data() / "bunny_npm_lowres.obj").string());
  const auto tri = IntrinsicTriangulation::from_positions(in.triangles, in.positions);
  ExactDistanceOptions o;
  o.keep_paths = false;
  const ExactDistance with = exact_distance(tri, std::vector<Index>{5, 900});
  const ExactDistance without = exact_distance(tri, std::vector<Index>{5, 900}, o);
  EXPECT_EQ(with.windows, without.windows);
  EXPECT_GT(with.window_store.size(), 1000u);
  EXPECT_TRUE(without.window_store.empty());
  for (Index v = 0; v < tri.n_vertices(); ++v) ASSERT_EQ(with.distance[v], without.distance[v]);
  EXPECT_THROW((void)without.path_to_source(7), InvalidInput);
  EXPECT_THROW((void)without.nearest_source(7), InvalidInput);
  // the budget bounds the windows queued at once: far fewer than all of them
  o.max_memory_bytes = double(with.windows) * kExactWindowBytes / 4;
  EXPECT_NO_THROW(exact_distance(tri, std::vector<Index>{5, 900}, o));
  o.keep_paths = true;
  EXPECT_THROW(exact_distance(tri, std::vector<Index>{5, 900}, o), InvalidInput);
}

TEST(ExactDistance, UnreachableComponentIsInfinite) {
  TriangleMesh a = test::flat_square(4, 0.0, 1), b = a;
  const Index na = Index(a.positions.rows());
  a.positions.conservativeResize(2 * na, 3);
  a.positions.bottomRows(na) = b.positions;
  for (const Triangle& t : b.faces) a.faces.push_back({t[0] + na, t[1] + na, t[2] + na});
  const auto tri = IntrinsicTriangulation::from_positions(a.faces, a.positions);
  const ExactDistance d = exact_distance(tri, std::vector<Index>{0});
  EXPECT_TRUE(std::isfinite(d.distance[na - 1]));
  EXPECT_TRUE(std::isinf(d.distance[na]));
  EXPECT_TRUE(d.path_to_source(na).empty());
  EXPECT_EQ(d.nearest_source(na), -1);
}

TEST(ExactDistance, RefusesOverTheMemoryBudgetWithTheFigure) {
  const TriangleMesh m = icosphere(8);
  const auto tri = IntrinsicTriangulation::from_positions(m.faces, m.positions);
  ExactDistanceOptions o;
  o.max_memory_bytes = 20000;
  try {
    exact_distance(tri, std::vector<Index>{0}, o);
    FAIL() << "no refusal";
  } catch (const InvalidInput& e) {
    const std::string what = e.what();
    EXPECT_NE(what.find("more than 312 windows"), std::string::npos) << what;
    EXPECT_NE(what.find("--memory-budget"), std::string::npos) << what;
  }
  o.max_memory_bytes = 1e9;
  EXPECT_NO_THROW(exact_distance(tri, std::vector<Index>{0}, o));
}

TEST(ExactDistance, RejectsBadSources) {
  const TriangleMesh m = test::flat_square(3, 0.0, 1);
  const auto tri = IntrinsicTriangulation::from_positions(m.faces, m.positions);
  using V = std::vector<Index>;
  using P = std::vector<SurfacePoint>;
  EXPECT_THROW(exact_distance(tri, V{}), InvalidInput);
  EXPECT_THROW(exact_distance(tri, V{-1}), InvalidInput);
  EXPECT_THROW(exact_distance(tri, V{tri.n_vertices()}), InvalidInput);
  EXPECT_THROW(exact_distance(tri, P{SurfacePoint{}}), InvalidInput);
  EXPECT_THROW(exact_distance(tri, P{SurfacePoint{0, Eigen::Vector3d(0.5, 0.6, -0.1)}}),
               InvalidInput);
  EXPECT_THROW(exact_distance(tri, P{SurfacePoint{0, Eigen::Vector3d(0.5, 0.6, 0.1)}}),
               InvalidInput);
  EXPECT_THROW(exact_distance(tri, P{SurfacePoint{0, Eigen::Vector3d(NAN, 0.6, 0.4)}}),
               InvalidInput);
  ExactDistanceOptions o;
  o.max_memory_bytes = -1;
  EXPECT_THROW(exact_distance(tri, V{0}, o), InvalidInput);
  const ExactDistance d = exact_distance(tri, V{0});
  EXPECT_THROW(d.path_to_source(-1), InvalidInput);
}

}  // namespace
}  // namespace ifem::intrinsic
