// Benchmark section "integer-crosscheck": Delaunay refinement with the two correspondences on
// every mesh of a directory, as a markdown table (mesh × angle: success, time and agreement).
// Per mesh and minimum angle (25°, 30°; no area bound): refine with signposts and with integer
// coordinates (inputs mollified as the CLI does), time each, and compare where both succeed:
// the same insertions, max |Δ length| over the edges, the common subdivisions' vertex and face
// counts, and the largest distance between the two locations of an intrinsic vertex on the
// input, and, as the exact test of which locations are right, the path-length defect of each:
// every intrinsic edge is a straight path through the input faces, so the 3D polyline through
// its located ends and traced crossings has the edge's length; the largest |polyline − length|
// over the edges, relative to the mean edge length (mollification alone leaves about 1e-5), and
// each common subdivision's area partition error (its pieces summed per input face against the
// face's 3D area, relative to the mean face area; 1e-12 is the tests' bound). Meshes the
// triangulation refuses (not edge-manifold / orientable) are listed as such. --generated adds
// the generated adversarial set (intrinsic/generators/mesh_generators.h) at the ctests' sizes and
// larger; --sphere1M the 1.0M-face UV sphere of `ifem_bench integer` (500 × 1000, needles at the
// poles: issue 33's "1M-face refinement"; a few GB, about a minute per angle).
//
//   ifem_bench integer-crosscheck [DIR] [--max-faces 300000] [--angles 25,30] [--generated]
//                                 [--sphere1M]
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <exception>
#include <filesystem>
#include <sstream>
#include <string>
#include <utility>
#include <vector>

#include "bench_util.h"
#include "intrinsic/generators/mesh_generators.h"
#include "intrinsic/integer/crosscheck.h"
#include "intrinsic/integer/integer_subdivision.h"
#include "intrinsic/integer/normal_coordinates.h"
#include "intrinsic/io/mesh_io.h"
#include "intrinsic/refine/common_subdivision.h"
#include "intrinsic/refine/delaunay_refine.h"
#include "intrinsic/refine/signpost.h"

namespace ifem::bench {
namespace {

using intrinsic::NormalCoordinateTriangulation;
using intrinsic::SignpostTriangulation;

std::string short_error(const std::string& what) {
  return what.size() > 48 ? what.substr(0, 45) + "..." : what;
}

// max over edges of |polyline length − edge length| / mean edge length.
double defect(const SignpostTriangulation& st) {
  const auto& tri = st.intrinsic();
  double worst = 0.0, mean = 0.0;
  for (Index e = 0; e < tri.n_edges(); ++e) mean += tri.length(e) / tri.n_edges();
  for (Index e = 0; e < tri.n_edges(); ++e) {
    const std::vector<intrinsic::SurfacePoint> path = st.trace_edge(e);
    double len = 0.0;
    for (std::size_t i = 1; i < path.size(); ++i) {
      len += (st.position(path[i]) - st.position(path[i - 1])).norm();
    }
    worst = std::max(worst, std::abs(len - tri.length(e)));
  }
  return worst / mean;
}

double defect(const NormalCoordinateTriangulation& nc) {
  const auto& tri = nc.intrinsic();
  const intrinsic::CommonSubdivision cs = intrinsic::common_subdivision(nc);
  double worst = 0.0, mean = 0.0;
  for (Index e = 0; e < tri.n_edges(); ++e) mean += tri.length(e) / tri.n_edges();
  for (Index e = 0; e < tri.n_edges(); ++e) {
    const Index h = tri.edge_halfedge(e);
    Eigen::Vector3d last = cs.positions.row(tri.tail(h));
    double len = 0.0;
    for (const intrinsic::InputCrossing& c : nc.trace_edge(e)) {
      const Eigen::Vector3d x = nc.crossing_position(c);
      len += (x - last).norm();
      last = x;
    }
    len += (Eigen::Vector3d(cs.positions.row(tri.head(h))) - last).norm();
    worst = std::max(worst, std::abs(len - tri.length(e)));
  }
  return worst / mean;
}

void row(const std::string& name, std::size_t faces, double angle, const SignpostTriangulation& s0,
         const NormalCoordinateTriangulation& n0) {
  SignpostTriangulation st = s0;
  NormalCoordinateTriangulation nc = n0;
  intrinsic::RefineOptions options;
  options.min_angle_degrees = angle;
  const intrinsic::RefineCrosscheck c = intrinsic::crosscheck_refine(s0, n0, options, &st, &nc);
  auto cell = [](const intrinsic::RefineRun& o) {
    char buf[96];
    if (!o.ok) return "fails: " + short_error(o.error);
    std::snprintf(buf, sizeof buf, "%.3f s + %.3f s", o.seconds, o.subdivision_seconds);
    return std::string(buf);
  };
  std::string agree = "—";
  if (c.signposts.ok && c.integer.ok) {
    char buf[240];
    std::snprintf(buf, sizeof buf,
                  "%s; max Δℓ %.1e; subd. V %lld/%lld F %lld/%lld; max Δx %.1e; defect %.1e/%.1e; "
                  "area %.0e/%.0e",
                  c.same_insertions ? "same insertions" : "DIFFERENT", c.max_length_difference,
                  static_cast<long long>(c.signposts.subdivision_vertices),
                  static_cast<long long>(c.integer.subdivision_vertices),
                  static_cast<long long>(c.signposts.subdivision_faces),
                  static_cast<long long>(c.integer.subdivision_faces), c.max_vertex_distance,
                  defect(st), defect(nc), c.signposts.area_partition_error,
                  c.integer.area_partition_error);
    agree = buf;
  }
  const intrinsic::RefineRun& r = c.integer.ok ? c.integer : c.signposts;
  std::printf("| %s | %zu | %.0f° | %lld | %s | %s | %s |\n", name.c_str(), faces, angle,
              static_cast<long long>(r.report.insertions), cell(c.signposts).c_str(),
              cell(c.integer).c_str(), agree.c_str());
  std::fflush(stdout);
}

// The generated adversarial inputs: the ctests' (IntegerCrosscheck.*) and larger ones.
void generated_rows(const std::vector<double>& angles) {
  std::vector<std::pair<std::string, intrinsic::TriangleMesh>> inputs = {
      {"needle_fan(44)", intrinsic::needle_fan(44)},
      {"needle_fan(80, 0.02)", intrinsic::needle_fan(80, 0.02)},
      {"needle_soup(3)", intrinsic::needle_soup(3)},
      {"needle_soup(30)", intrinsic::needle_soup(30)},
      {"nearly_coincident_grid(6, 10, 1e-6, 3)", intrinsic::nearly_coincident_grid(6, 10, 1e-6, 3)},
      {"nearly_coincident_grid(6, 10, 1e-9, 3)", intrinsic::nearly_coincident_grid(6, 10, 1e-9, 3)},
      {"nearly_coincident_grid(30, 400, 1e-9, 5)",
       intrinsic::nearly_coincident_grid(30, 400, 1e-9, 5)}};
  for (const unsigned long seed : {1ul, 2ul}) {
    intrinsic::RangeScanOptions scan;
    scan.nx = scan.ny = 16;
    scan.objects = 5;
    scan.islands = 3;
    scan.seed = seed;
    inputs.emplace_back("range_scan(16², seed " + std::to_string(seed) + ")",
                        intrinsic::range_scan(scan));
  }
  inputs.emplace_back("range_scan(100², default)", intrinsic::range_scan({}));
  const double eps = intrinsic::kDefaultMollifyEpsilon;
  for (const auto& [name, m] : inputs) {
    const SignpostTriangulation s0(m.faces, m.positions, eps);
    const NormalCoordinateTriangulation n0(m.faces, m.positions, eps);
    for (const double angle : angles) row(name, m.faces.size(), angle, s0, n0);
  }
}

}  // namespace

int integer_crosscheck(int argc, char** argv) {
  std::string dir = IFEM_SHARED_MESHES;
  if (argc >= 2 && argv[1][0] != '-') dir = argv[1];
  const auto max_faces = static_cast<std::size_t>(int_option(argc, argv, "--max-faces", 300000));
  const std::string angle_list = string_option(argc, argv, "--angles", "25,30");
  std::vector<double> angles;
  std::stringstream ss(angle_list);
  for (std::string a; std::getline(ss, a, ',');) angles.push_back(std::stod(a));
  std::vector<std::filesystem::path> files;
  if (!std::filesystem::is_directory(dir)) {
    std::printf("%s: not a directory (skipped)\n", dir.c_str());
    return 0;
  }
  for (const auto& f : std::filesystem::directory_iterator(dir)) {
    const std::string ext = f.path().extension().string();
    if (ext == ".obj" || ext == ".off" || ext == ".ply" || ext == ".stl") files.push_back(f.path());
  }
  std::sort(files.begin(), files.end());
  std::printf(
      "| mesh | faces | angle | insertions | signposts (refine + subd.) | integer "
      "(refine + subd.) | agreement |\n|---|---|---|---|---|---|---|\n");
  const double eps = intrinsic::kDefaultMollifyEpsilon;
  for (const auto& path : files) {
    const std::string name = path.filename().string();
    try {
      const io::SurfaceInput in = io::read_mesh(path.string());
      if (in.triangles.size() > max_faces) {
        std::printf("| %s | %zu | | | over --max-faces | | |\n", name.c_str(), in.triangles.size());
        continue;
      }
      const SignpostTriangulation s0(in.triangles, in.positions, eps);
      const NormalCoordinateTriangulation n0(in.triangles, in.positions, eps);
      for (const double angle : angles) row(name, in.triangles.size(), angle, s0, n0);
    } catch (const std::exception& e) {
      std::printf("| %s | | | | not used: %s | | |\n", name.c_str(), short_error(e.what()).c_str());
    }
  }
  if (has_flag(argc, argv, "--generated")) generated_rows(angles);
  if (has_flag(argc, argv, "--sphere1M")) {
    const intrinsic::TriangleMesh m = intrinsic::uv_sphere(500, 1000);
    const SignpostTriangulation s0(m.faces, m.positions, eps);
    const NormalCoordinateTriangulation n0(m.faces, m.positions, eps);
    for (const double angle : angles) row("uv_sphere(500, 1000)", m.faces.size(), angle, s0, n0);
  }
  return 0;
}

}  // namespace ifem::bench
