// Shared helpers for the test suites: small meshes built in code, and access to the shared
// corpus (../shared/data), which tests skip cleanly when it is absent.
#pragma once

#include <gtest/gtest.h>

#include <algorithm>
#include <cstdlib>
#include <filesystem>
#include <initializer_list>
#include <regex>
#include <string>
#include <vector>

#include "intrinsic/core/errors.h"
#include "intrinsic/core/geometry.h"
#include "intrinsic/core/triangulation.h"
#include "intrinsic/generators/mesh_generators.h"

namespace ifem::test {

/// ../shared/data as configured, or the environment's IFEM_SHARED_DATA when set (point it at a
/// folder that does not exist to run the suite as from a plain clone).
inline std::filesystem::path shared_data() {
  const char* env = std::getenv("IFEM_SHARED_DATA");
  return env && *env ? std::filesystem::path(env) : std::filesystem::path(IFEM_SHARED_DATA);
}
inline std::filesystem::path test_data() { return IFEM_TEST_DATA; }

/// All files in ../shared/data/<sub>, sorted; empty when the folder is absent.
inline std::vector<std::filesystem::path> shared_files(const std::string& sub) {
  std::vector<std::filesystem::path> out;
  const auto dir = shared_data() / sub;
  if (!std::filesystem::is_directory(dir)) return out;
  for (const auto& entry : std::filesystem::directory_iterator(dir)) {
    if (entry.is_regular_file()) out.push_back(entry.path());
  }
  std::sort(out.begin(), out.end());
  return out;
}

/// True when ../shared/data is there (its meshes folder): tests that need it skip otherwise,
/// and tests that loop over it must then check at least one file.
inline bool has_shared_data() { return std::filesystem::is_directory(shared_data() / "meshes"); }

/// One exact-distance reference: `<stem>.src<N>.exact.txt`, CGAL's heat-method baseline
/// `<stem>.src<N>.cgal-heat.txt` beside it, and the mesh `<stem>.*` they were computed on.
struct ReferenceCase {
  std::string stem;
  std::string src_text;  // N as in the file name
  long src = 0;
  std::filesystem::path exact, cgal_heat, mesh;
  bool bundled = false;  // from tests/data/reference (always there), not ../shared/data
};

/// The references of tests/data/reference (meshes in tests/data; always present, so every
/// reference test checks these from a plain clone), then those of ../shared/data/reference
/// (meshes in ../shared/data/meshes) when it is present, minus the ones already bundled.
/// A reference whose mesh is missing is listed with an empty `mesh`: callers fail on it.
inline std::vector<ReferenceCase> reference_cases() {
  static const std::regex name(R"((.+)\.src(\d+)\.exact\.txt)");
  std::vector<ReferenceCase> out;
  auto add_from = [&](const std::filesystem::path& ref_dir, const std::filesystem::path& mesh_dir,
                      bool bundled) {
    if (!std::filesystem::is_directory(ref_dir)) return;
    std::vector<std::filesystem::path> files, meshes;
    for (const auto& e : std::filesystem::directory_iterator(ref_dir)) files.push_back(e.path());
    for (const auto& e : std::filesystem::directory_iterator(mesh_dir)) {
      if (e.is_regular_file()) meshes.push_back(e.path());
    }
    std::sort(files.begin(), files.end());
    for (const auto& p : files) {
      std::smatch mt;
      const std::string fname = p.filename().string();
      if (!std::regex_match(fname, mt, name)) continue;
      const bool dup = std::any_of(out.begin(), out.end(), [&](const ReferenceCase& c) {
        return c.exact.filename() == p.filename();
      });
      if (dup) continue;
      ReferenceCase c;
      c.stem = mt[1].str();
      c.src_text = mt[2].str();
      c.src = std::stol(c.src_text);
      c.exact = p;
      c.cgal_heat = ref_dir / (c.stem + ".src" + c.src_text + ".cgal-heat.txt");
      for (const auto& m : meshes) {
        if (m.stem().string() == c.stem) c.mesh = m;
      }
      c.bundled = bundled;
      out.push_back(c);
    }
  };
  add_from(test_data() / "reference", test_data(), true);
  if (has_shared_data()) add_from(shared_data() / "reference", shared_data() / "meshes", false);
  return out;
}

/// Fails the test unless a loop over reference_cases() checked every bundled reference and, when
/// ../shared/data is present, at least one of its own: a reference test never passes on nothing.
inline void expect_references_checked(int bundled_checked, int shared_checked) {
  int bundled = 0;
  for (const ReferenceCase& c : reference_cases()) bundled += c.bundled ? 1 : 0;
  EXPECT_GT(bundled, 0) << "tests/data/reference has no *.exact.txt";
  EXPECT_EQ(bundled_checked, bundled) << "bundled references checked";
  if (has_shared_data()) {
    EXPECT_GT(shared_checked, 0) << "../shared/data is present, but none of its references was "
                                    "checked";
  }
}

/// True when the run asked to be quick (IFEM_TEST_QUICK set, as CI does for its sanitizer run,
/// where everything is 3–5× slower) and the file is one of the corpus's large ones (> 1 MB).
/// Loops over ../shared/data skip such files; every small and degenerate file still runs.
inline bool skip_in_quick_run(const std::filesystem::path& file) {
  const char* quick = std::getenv("IFEM_TEST_QUICK");
  if (!quick || !*quick || std::string(quick) == "0") return false;
  std::error_code ec;
  const auto size = std::filesystem::file_size(file, ec);
  return !ec && size > (1u << 20);
}

/// Expects `o.validate()` to throw InvalidInput whose message names `field` (docs/decisions.md,
/// "Every options struct has validate()").
template <class Options>
void expect_rejected(const Options& o, const std::string& field) {
  try {
    o.validate();
    ADD_FAILURE() << "accepted bad " << field;
  } catch (const InvalidInput& e) {
    EXPECT_NE(std::string(e.what()).find(field), std::string::npos) << e.what();
  }
}

/// expect_rejected() on default Options with `member` set to each of `values` in turn.
template <class Options, class T, class V>
void expect_each_rejected(T Options::*member, std::initializer_list<V> values,
                          const std::string& field) {
  for (const V& v : values) {
    Options o;
    o.*member = v;
    expect_rejected(o, field);
  }
}

#define IFEM_REQUIRE_SHARED_DATA()                                                 \
  do {                                                                             \
    if (!::ifem::test::has_shared_data()) {                                        \
      GTEST_SKIP() << "../shared/data is absent: " << ::ifem::test::shared_data(); \
    }                                                                              \
  } while (0)

/// A flat quad (unit square) split along the diagonal 0–2: with vertex 1 pulled in so that the
/// 0–2 diagonal is the non-Delaunay one.
inline intrinsic::TriangleMesh skewed_quad() {
  intrinsic::TriangleMesh m;
  m.positions.resize(4, 3);
  m.positions << 0, 0, 0,  //
      1, 0, 0,             //
      1.2, 1, 0,           //
      0, 0.3, 0;
  m.faces = {{0, 1, 2}, {0, 2, 3}};
  return m;
}

/// A flat polygon made of the unit cells of the (n+1)×(n+1) lattice on [0, 1]² for which
/// keep(i, j) holds (cell (i, j) = [i/n, (i+1)/n] × [j/n, (j+1)/n]), each split along its
/// diagonal (i, j)–(i+1, j+1), the vertices of no kept cell dropped. Interior vertices move by
/// up to `jitter`/n in x and y; boundary vertices other than the corners slide along their side
/// by up to `jitter`/n, so the sides stay straight and every boundary vertex keeps angle sum π
/// but the corners. Deterministic in seed.
template <class Keep>
intrinsic::TriangleMesh flat_lattice_polygon(int n, double jitter, unsigned seed, Keep keep) {
  auto kept = [&](int i, int j) { return i >= 0 && j >= 0 && i < n && j < n && keep(i, j); };
  std::vector<Index> id((n + 1) * (n + 1), kInvalidIndex);
  std::vector<Eigen::Vector3d> p;
  unsigned s = seed;
  auto rnd = [&]() {
    s = s * 1664525u + 1013904223u;
    return 2.0 * ((s >> 8) / double(1u << 24) - 0.5);
  };
  for (int j = 0; j <= n; ++j) {
    for (int i = 0; i <= n; ++i) {
      const bool c[4] = {kept(i - 1, j - 1), kept(i, j - 1), kept(i - 1, j), kept(i, j)};
      const int cells = c[0] + c[1] + c[2] + c[3];
      if (cells == 0) continue;
      Eigen::Vector3d x(double(i) / n, double(j) / n, 0.0);
      const double dx = jitter * rnd() / n, dy = jitter * rnd() / n;
      if (cells == 4) {
        x += Eigen::Vector3d(dx, dy, 0.0);
      } else if (cells == 2 && c[0] == c[2] && c[1] == c[3]) {  // on a vertical side
        x.y() += dy;
      } else if (cells == 2 && c[0] == c[1] && c[2] == c[3]) {  // on a horizontal side
        x.x() += dx;
      }
      id[j * (n + 1) + i] = static_cast<Index>(p.size());
      p.push_back(x);
    }
  }
  intrinsic::TriangleMesh m;
  m.positions.resize(static_cast<Eigen::Index>(p.size()), 3);
  for (std::size_t v = 0; v < p.size(); ++v) m.positions.row(v) = p[v].transpose();
  auto at = [&](int i, int j) { return id[j * (n + 1) + i]; };
  for (int j = 0; j < n; ++j) {
    for (int i = 0; i < n; ++i) {
      if (!kept(i, j)) continue;
      m.faces.push_back({at(i, j), at(i + 1, j), at(i + 1, j + 1)});
      m.faces.push_back({at(i, j), at(i + 1, j + 1), at(i, j + 1)});
    }
  }
  return m;
}

/// The jittered flat unit square (flat_lattice_polygon): 4 corners of angle π/2, n + 1
/// vertices per side.
inline intrinsic::TriangleMesh flat_square(int n, double jitter, unsigned seed) {
  return flat_lattice_polygon(n, jitter, seed, [](int, int) { return true; });
}

/// The jittered flat L: the unit square less its top-right quarter (n even), 5 corners of
/// angle π/2 and one of 3π/2 at (1/2, 1/2).
inline intrinsic::TriangleMesh flat_l_shape(int n, double jitter, unsigned seed) {
  return flat_lattice_polygon(n, jitter, seed,
                              [n](int i, int j) { return i < n / 2 || j < n / 2; });
}

/// Jitters a mesh's vertex positions by a deterministic pseudo-random amount (relative size
/// `amount` of the mesh's scale), to produce non-Delaunay triangulations.
inline intrinsic::TriangleMesh jittered(intrinsic::TriangleMesh m, double amount,
                                        unsigned seed = 1) {
  unsigned s = seed;
  auto rnd = [&]() {
    s = s * 1664525u + 1013904223u;
    return (s >> 8) / double(1u << 24) - 0.5;
  };
  for (Eigen::Index i = 0; i < m.positions.rows(); ++i) {
    for (int k = 0; k < 3; ++k) m.positions(i, k) += amount * rnd();
  }
  return m;
}

/// Length of a 3D polyline: the sum of its segments' lengths.
inline double polyline_length(const std::vector<Eigen::Vector3d>& line) {
  double s = 0.0;
  for (std::size_t i = 1; i < line.size(); ++i) s += (line[i] - line[i - 1]).norm();
  return s;
}

/// Flips `tri` to intrinsic Delaunay in place and checks what flips must preserve: validity,
/// total area and every vertex angle sum and angle defect (1e-9 relative), Gauss–Bonnet
/// (Σ defects = 2πχ, boundary terms included), α + β ≤ π(1 + 1e-12) on every interior edge,
/// and non-negative cotan weights on interior edges (on every edge if `all_weights`).
inline void check_flip_to_delaunay(intrinsic::IntrinsicTriangulation& tri, bool all_weights) {
  using namespace intrinsic;
  tri.validate();
  const double area0 = total_area(tri);
  const Eigen::VectorXd sums0 = vertex_angle_sums(tri);
  const Eigen::VectorXd defects0 = angle_defects(tri);
  const FlipReport rep = tri.flip_to_delaunay();
  EXPECT_FALSE(rep.hit_flip_cap);
  tri.validate();
  EXPECT_NEAR(total_area(tri), area0, 1e-9 * area0);
  const Eigen::VectorXd sums = vertex_angle_sums(tri);
  EXPECT_LE((sums - sums0).cwiseAbs().maxCoeff(),
            1e-9 * std::max(1.0, sums0.cwiseAbs().maxCoeff()));
  const Eigen::VectorXd defects = angle_defects(tri);
  EXPECT_LE((defects - defects0).cwiseAbs().maxCoeff(), 1e-9 * 2 * kPi);
  EXPECT_NEAR(defects.sum(), 2 * kPi * euler_characteristic(tri),
              1e-9 * 2 * kPi * std::max<Index>(1, tri.n_vertices()));
  const Eigen::VectorXd w = cotan_weights(tri);
  const double w_tol = -1e-10 * w.cwiseAbs().maxCoeff();
  for (Index e = 0; e < tri.n_edges(); ++e) {
    if (tri.is_boundary_edge(e)) {
      if (all_weights) {
        ASSERT_GE(w[e], w_tol) << "boundary edge " << e;
      }
      continue;
    }
    const Index h = tri.edge_halfedge(e);
    const double a = corner_angle(tri, IntrinsicTriangulation::prev(h));
    const double b = corner_angle(tri, IntrinsicTriangulation::prev(tri.twin(h)));
    ASSERT_LE(a + b, kPi * (1 + 1e-12)) << "edge " << e;
    ASSERT_GE(w[e], w_tol) << "edge " << e;
  }
}

}  // namespace ifem::test
