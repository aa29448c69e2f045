// Benchmark section "transfer": point location both ways and function transfer after
// refinement to 25° (no area bound), with signposts and integer coordinates, interleaved:
// building the PointLocator (common subdivision + both coordinates per piece), locating
// --points random input points on the intrinsic triangulation and as many intrinsic points on
// the input, and an L2 transfer input → intrinsic with the locator built (mixed mass assembly +
// factorization + solve) and end to end (locator included). Medians and minima (s), ratio
// integer / signposts of the medians.
//
//   ifem_bench transfer [--repeat 5] [--points 100000] [--data ../shared/data/meshes]
//                       [--mesh igea_268k.ply]
#include <cstdio>
#include <random>
#include <string>
#include <vector>

#include "bench_util.h"
#include "fem/attribute_transfer.h"
#include "intrinsic/io/mesh_io.h"
#include "intrinsic/refine/delaunay_refine.h"

namespace ifem::bench {
namespace {

using intrinsic::CorrespondenceView;
using intrinsic::PointLocator;
using intrinsic::SurfacePoint;

std::vector<SurfacePoint> random_points(const intrinsic::IntrinsicTriangulation& t, long n,
                                        unsigned seed) {
  std::mt19937 rng(seed);
  std::uniform_int_distribution<Index> face(0, t.n_faces() - 1);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  std::vector<SurfacePoint> out(static_cast<std::size_t>(n));
  for (SurfacePoint& p : out) {
    const Eigen::Vector3d b(u(rng), u(rng), u(rng));
    p = {face(rng), b / b.sum()};
  }
  return out;
}

void report(const char* what, const InterleavedTimes& t) {
  std::printf("  %-34s integer %8.4f s (min %8.4f)  signposts %8.4f s (min %8.4f)  ratio %5.2f\n",
              what, t.median[0], t.min[0], t.median[1], t.min[1], t.median[0] / t.median[1]);
}

}  // namespace

int transfer(int argc, char** argv) {
  const int repeat = int(int_option(argc, argv, "--repeat", 5));
  const long n_points = int_option(argc, argv, "--points", 100000);
  const std::string data = string_option(argc, argv, "--data", IFEM_SHARED_MESHES);
  const std::string mesh = string_option(argc, argv, "--mesh", "igea_268k.ply");
  print_load_average();
  const io::SurfaceInput in = io::read_mesh(data + "/" + mesh);
  const double eps = intrinsic::kDefaultMollifyEpsilon;
  intrinsic::SignpostTriangulation st(in.triangles, in.positions, eps);
  intrinsic::NormalCoordinateTriangulation nc(in.triangles, in.positions, eps);
  intrinsic::RefineOptions o;
  o.min_angle_degrees = 25.0;
  intrinsic::delaunay_refine(st, o);
  intrinsic::delaunay_refine(nc, o);
  const CorrespondenceView views[2] = {nc, st};
  std::printf("%s: %d input vertices, %d faces; refined to 25°: %d vertices\n", mesh.c_str(),
              int(st.n_input_vertices()), int(st.input().n_faces()),
              int(st.intrinsic().n_vertices()));
  const PointLocator loc[2] = {PointLocator(views[0]), PointLocator(views[1])};
  std::printf("  pieces: integer %d, signposts %d\n", int(loc[0].n_pieces()),
              int(loc[1].n_pieces()));
  const auto in_pts = random_points(st.input(), n_points, 1);
  const auto int_pts = random_points(st.intrinsic(), n_points, 2);
  const Eigen::VectorXd f = in.positions.col(2).array().sin();
  auto both = [&](auto&& body) {
    return std::vector<std::function<void()>>{[&] { body(0); }, [&] { body(1); }};
  };
  report("PointLocator (subdivision + coords)",
         time_interleaved(repeat, both([&](int i) { PointLocator l(views[i]); })));
  report(("input -> intrinsic, " + std::to_string(n_points) + " points").c_str(),
         time_interleaved(repeat, both([&](int i) { loc[i].input_to_intrinsic(in_pts); })));
  report(("intrinsic -> input, " + std::to_string(n_points) + " points").c_str(),
         time_interleaved(repeat, both([&](int i) { loc[i].intrinsic_to_input(int_pts); })));
  report("l2 transfer, locator given",
         time_interleaved(repeat, both([&](int i) {
                            fem::transfer(views[i], f, fem::TransferMethod::kL2, false, &loc[i]);
                          })));
  report("l2 transfer, end to end",
         time_interleaved(
             repeat, both([&](int i) { fem::transfer(views[i], f, fem::TransferMethod::kL2); })));
  return 0;
}

}  // namespace ifem::bench
