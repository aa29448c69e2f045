// Benchmark section "integer": the two correspondences side by side, interleaved in one run:
// flips to intrinsic Delaunay with normal coordinates (NormalCoordinateTriangulation) and with
// signposts (SignpostTriangulation), and the bare IntrinsicTriangulation as the anchor (no
// correspondence kept); then, once with each, tracing every intrinsic edge of the Delaunay
// triangulation over the input and building the common subdivision (the integer one on one
// thread, the signpost one on the default threads). Inputs are mollified (1e-5) as the CLI does;
// times exclude reading the file and building the triangulations (each round starts from a copy).
// Then Delaunay refinement to 25° (no area bound) with each, interleaved, medians and ratio.
// The mesh name "sphere1M" is a generated UV sphere of 1.0M faces (500 × 1000; needles at the
// poles give refinement work).
//
//   ifem_bench integer [--repeat 5] [--data ../shared/data/meshes] [--mesh F[,F...]]
#include <cstdio>
#include <filesystem>
#include <sstream>
#include <string>
#include <vector>

#include "bench_util.h"
#include "intrinsic/generators/mesh_generators.h"
#include "intrinsic/integer/integer_subdivision.h"
#include "intrinsic/integer/normal_coordinates.h"
#include "intrinsic/io/mesh_io.h"
#include "intrinsic/refine/delaunay_refine.h"
#include "intrinsic/refine/signpost.h"

namespace ifem::bench {
namespace {

using intrinsic::NormalCoordinateTriangulation;
using intrinsic::SignpostTriangulation;

// Refinement to 25°, interleaved: medians (s) for signposts and integer coordinates.
void refine_times(const SignpostTriangulation& st0, const NormalCoordinateTriangulation& nc0,
                  int repeat) {
  std::vector<double> t_st, t_nc;
  Index insertions = 0;
  intrinsic::RefineOptions o;
  o.min_angle_degrees = 25.0;
  for (int r = 0; r < repeat; ++r) {
    SignpostTriangulation st = st0;
    double t0 = seconds_now();
    insertions = intrinsic::delaunay_refine(st, o).insertions;
    t_st.push_back(seconds_now() - t0);
    NormalCoordinateTriangulation nc = nc0;
    t0 = seconds_now();
    intrinsic::delaunay_refine(nc, o);
    t_nc.push_back(seconds_now() - t0);
  }
  std::printf(
      "%-22s refine to 25°: %lld insertions  integer %7.3f s  signposts %7.3f s"
      "  integer/signposts %5.2f\n",
      "", static_cast<long long>(insertions), median(t_nc), median(t_st),
      median(t_nc) / median(t_st));
}

void run_mesh(const std::string& path, int repeat) {
  io::SurfaceInput in;
  if (path == "sphere1M") {
    const intrinsic::TriangleMesh m = intrinsic::uv_sphere(500, 1000);
    in.triangles = m.faces;
    in.positions = m.positions;
  } else {
    in = io::read_mesh(path);
  }
  const double eps = intrinsic::kDefaultMollifyEpsilon;
  const SignpostTriangulation st0(in.triangles, in.positions, eps);
  const NormalCoordinateTriangulation nc0(in.triangles, in.positions, eps);
  std::vector<double> t_st, t_nc, t_tri;
  std::size_t flips = 0;
  for (int r = 0; r < repeat; ++r) {
    SignpostTriangulation st = st0;
    double t0 = seconds_now();
    flips = st.flip_to_delaunay().flips;
    t_st.push_back(seconds_now() - t0);
    NormalCoordinateTriangulation nc = nc0;
    t0 = seconds_now();
    const std::size_t f2 = nc.flip_to_delaunay().flips;
    t_nc.push_back(seconds_now() - t0);
    intrinsic::IntrinsicTriangulation tri = nc0.intrinsic();
    t0 = seconds_now();
    tri.flip_to_delaunay();
    t_tri.push_back(seconds_now() - t0);
    if (f2 != flips) std::printf("  (flip counts differ: %zu vs %zu)\n", f2, flips);
  }
  SignpostTriangulation st = st0;
  st.flip_to_delaunay();
  NormalCoordinateTriangulation nc = nc0;
  nc.flip_to_delaunay();
  const Index ne = nc.intrinsic().n_edges();
  std::size_t crossings = 0, points = 0;
  double t0 = seconds_now();
  for (Index e = 0; e < ne; ++e) crossings += nc.trace_edge(e).size();
  const double trace_nc = seconds_now() - t0;
  t0 = seconds_now();
  for (Index e = 0; e < ne; ++e) points += st.trace_edge(e).size();
  const double trace_st = seconds_now() - t0;
  t0 = seconds_now();
  const std::size_t cs_nc = intrinsic::common_subdivision(nc).faces.size();
  const double sub_nc = seconds_now() - t0;
  t0 = seconds_now();
  const std::size_t cs_st = intrinsic::common_subdivision(st).faces.size();
  const double sub_st = seconds_now() - t0;
  std::printf(
      "%-22s %8zu faces  flips %8zu  IDT: integer %7.4f s  signposts %7.4f s  bare %7.4f s"
      "  integer/signposts %5.2f  |  trace all (1 thread): integer %7.3f s  signposts %7.3f s"
      "  (%zu crossings)  |  common subd.: integer %7.3f s (%zu triangles)  signposts %7.3f s"
      " (%zu)\n",
      std::filesystem::path(path).filename().string().c_str(), in.triangles.size(), flips,
      median(t_nc), median(t_st), median(t_tri), median(t_nc) / median(t_st), trace_nc, trace_st,
      crossings, sub_nc, cs_nc, sub_st, cs_st);
  (void)points;
  refine_times(st0, nc0, repeat);
}

}  // namespace

int integer(int argc, char** argv) {
  const int repeat = static_cast<int>(int_option(argc, argv, "--repeat", 5));
  const std::string data = string_option(argc, argv, "--data", IFEM_SHARED_MESHES);
  const std::string list = string_option(argc, argv, "--mesh", "rocketship.ply,igea_268k.ply");
  std::stringstream ss(list);
  std::string name;
  while (std::getline(ss, name, ',')) {
    const std::filesystem::path p =
        std::filesystem::path(name).is_absolute() || std::filesystem::exists(name)
            ? std::filesystem::path(name)
            : std::filesystem::path(data) / name;
    if (name == "sphere1M") {
      run_mesh(name, repeat);
      continue;
    }
    if (!std::filesystem::exists(p)) {
      std::printf("%-22s (absent, skipped)\n", name.c_str());
      continue;
    }
    run_mesh(p.string(), repeat);
  }
  return 0;
}

}  // namespace ifem::bench
