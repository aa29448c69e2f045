// Shared helpers for the test suites: small meshes built in code, and access to the shared
// corpus (../shared/data), which tests skip cleanly when it is absent.
#pragma once

#include <filesystem>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "intrinsic/mesh_generators.h"
#include "intrinsic/triangulation.h"

namespace ifem::test {

inline std::filesystem::path shared_data() { return IFEM_SHARED_DATA; }
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

#define IFEM_REQUIRE_SHARED_DATA()                                                   \
  do {                                                                               \
    if (!std::filesystem::is_directory(::ifem::test::shared_data() / "meshes")) {    \
      GTEST_SKIP() << "../shared/data is absent: " << ::ifem::test::shared_data();   \
    }                                                                                \
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

}  // namespace ifem::test
