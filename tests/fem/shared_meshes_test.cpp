// The foundation's promise on real data: every mesh in ../shared/data/meshes gives either a
// finite intrinsic Delaunay Laplacian with non-negative weights, or a NonManifoldInput error
// naming the offending edge. Flip invariants are checked on each mesh that builds.
#include <gtest/gtest.h>

#include <cmath>
#include <string>

#include "fem/operators.h"
#include "helpers.h"
#include "intrinsic/core/geometry.h"
#include "intrinsic/io/mesh_io.h"
#include "intrinsic/surface/build_surface.h"
#include "intrinsic/surface/face_analysis.h"

namespace ifem::intrinsic {
namespace {

class SharedMesh : public ::testing::TestWithParam<std::string> {};
// The meshes bundled in tests/data: the same checks from a plain clone.
class BundledMesh : public ::testing::TestWithParam<std::string> {};

// The mesh of ../shared/data named by the test's parameter: skipped when ../shared/data is absent
// (or in a quick run, for a large file); a listed file missing from a present corpus fails.
#define IFEM_SHARED_MESH_PATH(path)                                                         \
  IFEM_REQUIRE_SHARED_DATA();                                                               \
  const auto path = test::shared_data() / "meshes" / GetParam();                            \
  ASSERT_TRUE(std::filesystem::exists(path)) << path << " is listed but not in the corpus"; \
  if (test::skip_in_quick_run(path)) GTEST_SKIP() << "large file skipped (IFEM_TEST_QUICK)"

// Either a finite intrinsic Delaunay Laplacian (flip invariants checked) or a NonManifoldInput
// naming the offending edge.
void expect_idt_or_named_error(const std::filesystem::path& path) {
  const io::SurfaceInput in = io::read_mesh(path.string());
  const FaceListStats st = analyze_faces(in.triangles, static_cast<Index>(in.positions.rows()));
  IntrinsicTriangulation tri;
  try {
    tri = IntrinsicTriangulation::from_positions(in.triangles, in.positions);
  } catch (const NonManifoldInput& e) {
    const std::string msg = e.what();
    // the only acceptable refusals: a nonmanifold edge (named) or a non-orientable gluing
    if (st.nonmanifold_edges > 0) {
      EXPECT_NE(msg.find("incident faces"), std::string::npos) << msg;
      const std::string edge = "(" + std::to_string(st.first_nonmanifold_edge[0]) + "," +
                               std::to_string(st.first_nonmanifold_edge[1]) + ")";
      EXPECT_NE(msg.find("edge " + edge), std::string::npos) << msg;
    } else {
      EXPECT_NE(msg.find("non-orientable"), std::string::npos) << msg;
    }
    return;
  }
  EXPECT_EQ(st.nonmanifold_edges, 0) << "a nonmanifold mesh must not build on the manifold path";
  tri.mollify();
  // boundary edges opposite an obtuse angle cannot flip on the manifold path, so only interior
  // weights are checked here (build_surface then takes the tufted cover: next test)
  test::check_flip_to_delaunay(tri, false);
}

// The automatic path (manifold or tufted cover) gives every mesh a finite Laplacian with
// non-negative weights and a positive mass on every referenced vertex.
void expect_automatic_path_good(const std::filesystem::path& path) {
  const io::SurfaceInput in = io::read_mesh(path.string());
  const SurfaceTriangulation s = build_surface(in.triangles, in.positions);
  s.tri.validate();
  EXPECT_FALSE(s.flips.hit_flip_cap);
  if (s.path == SurfacePath::kTufted) {
    EXPECT_FALSE(s.reason_detail.empty());
    EXPECT_NE(s.reason, PathReason::kEdgeManifoldOrientable);
  }
  const fem::SparseMatrix L = fem::cotan_laplacian(s.tri);
  ASSERT_EQ(L.rows(), in.positions.rows());
  const double scale = L.diagonal().cwiseAbs().maxCoeff();
  ASSERT_TRUE(std::isfinite(scale));
  const Eigen::VectorXd L1 = L * Eigen::VectorXd::Ones(L.rows());
  EXPECT_LE(L1.cwiseAbs().maxCoeff(), 1e-9 * scale);
  EXPECT_LE((fem::SparseMatrix(L.transpose()) - L).cwiseAbs().sum(), 1e-12 * scale * L.rows());
  for (int k = 0; k < L.outerSize(); ++k) {
    for (fem::SparseMatrix::InnerIterator it(L, k); it; ++it) {
      ASSERT_TRUE(std::isfinite(it.value()));
      if (it.row() != it.col()) {
        ASSERT_LE(it.value(), 1e-10 * scale) << "entry (" << it.row() << "," << it.col() << ")";
      }
    }
  }
  const Eigen::VectorXd M = fem::lumped_mass(s.tri);
  ASSERT_TRUE(M.allFinite());
  const FaceListStats st = analyze_faces(in.triangles, static_cast<Index>(in.positions.rows()));
  std::vector<char> referenced(in.positions.rows(), 0);
  for (const Triangle& t : in.triangles) {
    if (t[0] != t[1] && t[1] != t[2] && t[2] != t[0]) {
      referenced[t[0]] = referenced[t[1]] = referenced[t[2]] = 1;
    }
  }
  for (Eigen::Index v = 0; v < M.size(); ++v) {
    if (referenced[v]) {
      ASSERT_GT(M[v], 0.0) << "vertex " << v;
    } else {
      ASSERT_EQ(M[v], 0.0) << "vertex " << v;
    }
  }
  if (st.nonmanifold_edges > 0) {
    EXPECT_EQ(s.path, SurfacePath::kTufted);
  }
}

TEST_P(SharedMesh, IntrinsicDelaunayLaplacianOrNamedError) {
  IFEM_SHARED_MESH_PATH(path);
  expect_idt_or_named_error(path);
}

TEST_P(SharedMesh, AutomaticPathHasNonNegativeWeights) {
  IFEM_SHARED_MESH_PATH(path);
  expect_automatic_path_good(path);
}

TEST_P(BundledMesh, IntrinsicDelaunayLaplacianOrNamedError) {
  expect_idt_or_named_error(test::test_data() / GetParam());
}

TEST_P(BundledMesh, AutomaticPathHasNonNegativeWeights) {
  expect_automatic_path_good(test::test_data() / GetParam());
}

// Every mesh of the corpus, listed so that a missing file is noticed (skipped, by name).
INSTANTIATE_TEST_SUITE_P(
    Corpus, SharedMesh,
    ::testing::Values("3holes.off", "armadillo.obj", "beetle_sutherland.obj", "block.off",
                      "bob_small.ply", "bunny_npm_lowres.obj", "bunny_poly.ply", "camelhead.off",
                      "cgal_all_degen.off", "cgal_degtri_nullface_bis.off",
                      "cgal_fused_vertices.off", "cgal_non_manifold_face_graph.off", "conrod.off",
                      "cow_viewpoint.obj", "fan3.obj", "fandisk.off", "fertility.off",
                      "hourglass_ico.obj", "igea_268k.ply", "lato000_rangescan.ply", "lego.ply",
                      "moebius.obj", "ogre.obj", "pegasus.obj", "platonic_shelf.obj",
                      "rocketship.ply", "spot.obj", "stanford_bunny_scan.obj",
                      "teapot_unwelded.obj", "terrain8k.obj", "tet_with_self_edge.ply",
                      "thingi10k_138207.obj", "thingi10k_49220.obj", "thingi10k_679615.obj",
                      "thingi10k_73342.obj", "thingi10k_90225.obj", "triple_vierbein.obj",
                      "truck.obj"),
    [](const ::testing::TestParamInfo<std::string>& param) {
      std::string n = param.param;
      for (char& c : n) {
        if (!std::isalnum(static_cast<unsigned char>(c))) c = '_';
      }
      return n;
    });

std::string param_name(const ::testing::TestParamInfo<std::string>& param) {
  std::string n = param.param;
  for (char& c : n) {
    if (!std::isalnum(static_cast<unsigned char>(c))) c = '_';
  }
  return n;
}

INSTANTIATE_TEST_SUITE_P(TestData, BundledMesh,
                         ::testing::Values("spot.obj", "bunny_npm_lowres.obj", "fan3.obj",
                                           "tet_with_self_edge.ply", "triple_vierbein.obj",
                                           "soup_icosphere.obj"),
                         param_name);

// Every mesh file bundled in tests/data is in the list above.
TEST(BundledMesh, ListIsComplete) {
  int meshes = 0;
  for (const auto& e : std::filesystem::directory_iterator(test::test_data())) {
    const std::string ext = e.path().extension().string();
    if (ext == ".obj" || ext == ".ply" || ext == ".off" || ext == ".stl") ++meshes;
  }
  EXPECT_EQ(meshes, 6);
}

TEST(SharedMesh, CorpusListIsComplete) {
  IFEM_REQUIRE_SHARED_DATA();
  EXPECT_EQ(test::shared_files("meshes").size(), 38u);
}

}  // namespace
}  // namespace ifem::intrinsic
