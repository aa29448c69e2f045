// Benchmark section "refine": intrinsic Delaunay refinement (signposts, Chew's 2nd algorithm)
// on spot.obj, rocketship.ply, a uv sphere of needle triangles (156k faces), igea_268k.ply and
// generated range scans (range_scan(): 224×224 cells, about 95k faces, depth jumps 0.5 and 2).
// Times exclude reading the file; "build" is the signpost triangulation's construction
// (+ mollification 1e-5, as the CLI does), "refine" includes the initial flips to Delaunay,
// "trace-all" traces every intrinsic edge over the input, "common subd." builds the overlay
// mesh (both once). Then the accurate distance mode (`ifem distance --refine`: edges of about
// 0.4·h, t = ℓ²/4, one correction step) on spot, fandisk, rocketship and conrod (tufted cover):
// refinement, heat precompute and one query.
//
//   ifem_bench refine [--repeat 5] [--min-angle 25] [--off-centers 0|1]
//                     [--data ../shared/data/meshes]
#include <malloc.h>

#include <cstdio>
#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

#include "bench_util.h"
#include "intrinsic/core/geometry.h"
#include "intrinsic/generators/mesh_generators.h"
#include "intrinsic/io/mesh_io.h"
#include "intrinsic/refine/common_subdivision.h"
#include "intrinsic/refine/delaunay_refine.h"
#include "intrinsic/refine/signpost.h"
#include "intrinsic/surface/build_surface.h"
#include "intrinsic/surface/face_analysis.h"
#include "solvers/recipes/pipeline.h"
#include "solvers/scalar/heat_distance.h"

namespace ifem::bench {
namespace {

void run_case(const std::string& name, const std::vector<Triangle>& faces, const Positions& x,
              int repeat, const intrinsic::RefineOptions& opt) {
  std::vector<double> tb, tr, tt, tc;
  intrinsic::RefineReport rep;
  for (int k = 0; k < repeat; ++k) {
    double t0 = seconds_now();
    intrinsic::SignpostTriangulation st(faces, x, intrinsic::kDefaultMollifyEpsilon);
    tb.push_back(seconds_now() - t0);
    t0 = seconds_now();
    rep = intrinsic::delaunay_refine(st, opt);
    tr.push_back(seconds_now() - t0);
    if (k == 0) {  // tracing every edge (the common subdivision's curves), once
      t0 = seconds_now();
      const auto lines = st.traced_edges_3d();
      tt.push_back(seconds_now() - t0);
      t0 = seconds_now();
      const intrinsic::CommonSubdivision cs = intrinsic::common_subdivision(st);
      tc.push_back(seconds_now() - t0);
    }
  }
  std::printf(
      "%-22s %8zu faces  build %7.3f s  refine %7.3f s  trace-all %7.3f s  common subd. %7.3f s"
      "  V %7d -> %7d  min angle %6.2f -> %6.2f  (needles %d, left %d%s)\n",
      name.c_str(), faces.size(), median(tb), median(tr), median(tt), median(tc),
      rep.vertices_before, rep.vertices_after, rep.min_angle_before,
      rep.min_angle_after_excluding_needles, rep.needle_faces, rep.bad_faces_left,
      rep.hit_insertion_cap ? ", CAP" : "");
  std::fflush(stdout);
}

// `ifem distance --refine` on one mesh, through the library pipeline (the manifold path refines
// with signposts, the tufted path the cover itself).
void run_accurate(const std::string& name, const io::SurfaceInput& in, int repeat) {
  solvers::PrepareOptions opt;
  opt.refine = solvers::accurate_distance_refinement();
  std::vector<double> tr, tp, tq;
  Index nv = 0;
  for (int k = 0; k < repeat; ++k) {
    double t0 = seconds_now();
    const solvers::PreparedSurface s = solvers::prepare_surface(in, opt);
    tr.push_back(seconds_now() - t0);
    nv = s.tri.n_vertices();
    t0 = seconds_now();
    const solvers::HeatDistanceSolver solver(s.tri, solvers::distance_options(s));
    tp.push_back(seconds_now() - t0);
    t0 = seconds_now();
    const Eigen::VectorXd d = solver.compute_distance({0});
    tq.push_back(seconds_now() - t0);
  }
  std::printf(
      "%-22s %8zu faces  build+refine %7.3f s  heat precompute %7.3f s  query %7.4f s"
      "  V %7ld -> %7d\n",
      name.c_str(), in.triangles.size(), median(tr), median(tp), median(tq),
      long(in.positions.rows()), nv);
  std::fflush(stdout);
}

// The common subdivision's peak memory (VmHWM after resetting it, minus the RSS before) against
// its bound kSubdivisionBytesPerCrossing × (C + V + F_in), after refinement to the angle bound.
void run_subdivision_memory(const std::string& name, const io::SurfaceInput& in) {
  intrinsic::SignpostTriangulation st(in.triangles, in.positions,
                                      intrinsic::kDefaultMollifyEpsilon);
  intrinsic::delaunay_refine(st);
  malloc_trim(0);  // freed heap back to the system: the RSS below is what is in use
  {
    std::ofstream reset("/proc/self/clear_refs");
    reset << "5";  // resets VmHWM to the current RSS (Linux ≥ 4.0)
  }
  const double before = rss_mib();
  const double t0 = seconds_now();
  const intrinsic::CommonSubdivision cs = intrinsic::common_subdivision(st);
  const double t = seconds_now() - t0;
  const double peak = peak_rss_mib() - before;
  const double n =
      double(cs.crossings) + double(st.intrinsic().n_vertices()) + double(in.triangles.size());
  const double bound = intrinsic::kSubdivisionBytesPerCrossing * n / (1024.0 * 1024.0);
  std::printf(
      "%-22s common subd. %7.3f s  crossings C %9zu  faces %9zu  peak %7.1f MiB  bound %7.1f "
      "MiB  (%.0f bytes per C + V + F_in)\n",
      name.c_str(), t, cs.crossings, cs.faces.size(), peak, bound, peak * 1048576.0 / n);
  std::fflush(stdout);
}

}  // namespace

int refine(int argc, char** argv) {
  const int repeat = static_cast<int>(int_option(argc, argv, "--repeat", 5));
  intrinsic::RefineOptions opt;
  opt.min_angle_degrees = std::stod(string_option(argc, argv, "--min-angle", "25"));
  opt.off_centers = int_option(argc, argv, "--off-centers", 0) != 0;
  const std::string data = string_option(argc, argv, "--data", IFEM_SHARED_MESHES);
  std::printf("refine: min angle %.1f°, %s, median of %d runs\n", opt.min_angle_degrees,
              opt.off_centers ? "off-centers" : "circumcenters", repeat);
  for (const char* file : {"spot.obj", "rocketship.ply", "igea_268k.ply"}) {
    const std::filesystem::path path = std::filesystem::path(data) / file;
    if (!std::filesystem::exists(path)) {
      std::printf("%-22s (missing: %s)\n", file, path.string().c_str());
      continue;
    }
    const io::SurfaceInput in = io::read_mesh(path.string());
    run_case(file, in.triangles, in.positions, repeat, opt);
  }
  const intrinsic::TriangleMesh m = intrinsic::uv_sphere(40, 2000);  // 156,000 faces
  run_case("uv_sphere(40, 2000)", m.faces, m.positions, repeat, opt);
  // generated single-view range scans (about 95k faces, 40+ components, needle rims)
  for (const double jump : {0.5, 2.0}) {
    for (const unsigned long seed : {1UL, 2UL}) {
      intrinsic::RangeScanOptions so;
      so.nx = so.ny = 224;
      so.seed = seed;
      so.depth_jump = jump;
      const intrinsic::TriangleMesh scan = intrinsic::range_scan(so);
      char name[64];
      std::snprintf(name, sizeof name, "range_scan(224,%lu,%.1f)", seed, jump);
      run_case(name, scan.faces, scan.positions, repeat, opt);
    }
  }
  std::printf("common subdivision peak memory vs its bound (angle bound only, once)\n");
  for (const char* file : {"lato000_rangescan.ply", "rocketship.ply"}) {
    const std::filesystem::path path = std::filesystem::path(data) / file;
    if (!std::filesystem::exists(path)) {
      std::printf("%-22s (missing: %s)\n", file, path.string().c_str());
      continue;
    }
    run_subdivision_memory(file, io::read_mesh(path.string()));
  }
  std::printf("accurate distance (ifem distance --refine), median of %d runs\n", repeat);
  for (const char* file : {"spot.obj", "fandisk.off", "rocketship.ply", "conrod.off"}) {
    const std::filesystem::path path = std::filesystem::path(data) / file;
    if (!std::filesystem::exists(path)) {
      std::printf("%-22s (missing: %s)\n", file, path.string().c_str());
      continue;
    }
    run_accurate(file, io::read_mesh(path.string()), repeat);
  }
  return 0;
}

}  // namespace ifem::bench
