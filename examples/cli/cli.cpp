#include "cli.h"

#include <cctype>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <sstream>
#include <utility>

#include "intrinsic/core/errors.h"
#include "intrinsic/surface/build_surface.h"
#ifdef IFEM_HAVE_PCL
#include "pointcloud/pcl_adapter.h"
#endif

namespace ifem::cli {

const std::set<std::string> kSurfaceFlags = {"no-delaunay", "tufted", "pointcloud", "quiet"};
const std::set<std::string> kSurfaceOptions = {"mollify", "knn"};
const char* const kSurfaceHelp =
    "Surface options (any command that reads a mesh or point cloud):\n"
    "  --mollify F     relative mollification margin: the smallest uniform length δ is added to\n"
    "                  every edge so each triangle satisfies a+b−c ≥ F·(mean edge length)\n"
    "                  (default 1e-5; 0 repairs only strict violations)\n"
    "  --no-delaunay   keep the input triangulation (no intrinsic edge flips)\n"
    "  --tufted        force the tufted cover even on an edge-manifold mesh\n"
    "  --pointcloud    treat the input as a point cloud even if it has faces\n"
    "  --knn K         neighbours per point for point clouds (default 30)\n"
    "  --quiet         no progress lines on stderr\n";

Args::Args(int argc, char** argv, const std::set<std::string>& flags,
           const std::set<std::string>& options) {
  for (int i = 0; i < argc; ++i) {
    std::string a = argv[i];
    if (a == "-o") a = "--output";
    if (a == "-k") a = "--k";
    if (a == "-h") a = "--help";
    if (a.size() > 2 && a.compare(0, 2, "--") == 0) {
      std::string key = a.substr(2), value;
      const auto eq = key.find('=');
      const bool inline_value = eq != std::string::npos;
      if (inline_value) {
        value = key.substr(eq + 1);
        key = key.substr(0, eq);
      }
      if (key == "help" || flags.count(key)) {
        if (inline_value) throw InvalidInput("option --" + key + " takes no value");
        values_[key] = "";
      } else if (options.count(key)) {
        if (!inline_value) {
          if (i + 1 >= argc) throw InvalidInput("option --" + key + " needs a value");
          value = argv[++i];
        }
        values_[key] = value;
      } else {
        throw InvalidInput("unknown option --" + key + " (see --help)");
      }
    } else {
      positional_.push_back(a);
    }
  }
}

std::string Args::get(const std::string& key, const std::string& fallback) const {
  const auto it = values_.find(key);
  return it == values_.end() ? fallback : it->second;
}

double Args::get_double(const std::string& key, double fallback) const {
  if (!has(key)) return fallback;
  const std::string s = get(key);
  char* end = nullptr;
  const double v = std::strtod(s.c_str(), &end);
  if (s.empty() || *end != '\0') throw InvalidInput("--" + key + ": '" + s + "' is not a number");
  return v;
}

long Args::get_int(const std::string& key, long fallback) const {
  if (!has(key)) return fallback;
  const std::string s = get(key);
  char* end = nullptr;
  const long v = std::strtol(s.c_str(), &end, 10);
  if (s.empty() || *end != '\0') throw InvalidInput("--" + key + ": '" + s + "' is not an integer");
  return v;
}

std::vector<long> Args::get_int_list(const std::string& key) const {
  std::vector<long> out;
  std::stringstream ss(get(key));
  std::string item;
  while (std::getline(ss, item, ',')) {
    char* end = nullptr;
    const long v = std::strtol(item.c_str(), &end, 10);
    if (item.empty() || *end != '\0') {
      throw InvalidInput("--" + key + ": '" + item + "' is not an integer");
    }
    out.push_back(v);
  }
  return out;
}

double now_seconds() {
  return std::chrono::duration<double>(std::chrono::steady_clock::now().time_since_epoch()).count();
}

void progress(const Args& args, const std::string& line) {
  if (!args.has("quiet")) std::fprintf(stderr, "ifem: %s\n", line.c_str());
}

// .pcd goes through the optional PCL adapter; everything else through io::read_surface.
static io::SurfaceInput read_input(const std::string& file) {
  std::string ext = file.size() >= 4 ? file.substr(file.size() - 4) : "";
  for (char& c : ext) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  if (ext != ".pcd") return io::read_surface(file);
#ifdef IFEM_HAVE_PCL
  pointcloud::PclPoints pts = pointcloud::read_pcd(file);
  io::SurfaceInput in;
  in.positions = std::move(pts.positions);
  if (pts.has_normals()) in.normals = std::move(pts.normals);
  in.format = "pcd";
  if (pts.dropped_non_finite > 0) {
    std::fprintf(stderr, "ifem: %s: dropped %d points with non-finite coordinates\n", file.c_str(),
                 pts.dropped_non_finite);
  }
  return in;
#else
  throw IoError(file +
                ": this ifem was built without PCL: .pcd needs the PCL adapter "
                "(install libpcl-dev and reconfigure with -DIFEM_WITH_PCL=ON)");
#endif
}

PreparedSurface prepare_surface(const std::string& file, const Args& args) {
  PreparedSurface s;
  double t0 = now_seconds();
  s.input = read_input(file);
  s.seconds_load = now_seconds() - t0;
  const Index nv = static_cast<Index>(s.input.positions.rows());
  progress(args, "read " + file + ": " + std::to_string(nv) + " vertices, " +
                     std::to_string(s.input.n_polygons) + " faces (" + s.input.format + ")");
  s.stats = intrinsic::analyze_faces(s.input.triangles, nv);
  const double eps = args.get_double("mollify", intrinsic::kDefaultMollifyEpsilon);
  t0 = now_seconds();

  // ---- point cloud: no faces, or --pointcloud
  if (!s.input.has_faces() || args.has("pointcloud")) {
    pointcloud::Options opt;
    opt.k = static_cast<int>(args.get_int("knn", 30));
    opt.mollify_relative_epsilon = eps;
    opt.intrinsic_delaunay = !args.has("no-delaunay");
    const bool with_normals = s.input.normals.rows() == nv && nv > 0;
    s.tri = pointcloud::pointcloud_triangulation(
        s.input.positions, opt, with_normals ? &s.input.normals : nullptr, &s.cloud);
    s.path = "pointcloud";
    s.path_reason = std::string(s.input.has_faces() ? "--pointcloud" : "no faces") +
                    ": point cloud, k = " + std::to_string(s.cloud.k) +
                    (s.cloud.normals_from_input ? ", file normals" : ", PCA normals");
    s.mollify = s.cloud.mollify;
    s.flips = s.cloud.flips;
    s.build.input_faces = 0;
    s.build.unreferenced_vertices = s.cloud.isolated_points;
    s.seconds_build = s.cloud.seconds_knn + s.cloud.seconds_local + s.cloud.seconds_cover;
    s.seconds_flip = s.cloud.seconds_idt;
    std::ostringstream m;
    m << "point cloud: " << nv << " points, k = " << s.cloud.k << ", " << s.cloud.local_triangles
      << " local triangles, " << s.cloud.isolated_points << " isolated points; kNN "
      << s.cloud.seconds_knn << " s, local Delaunay " << s.cloud.seconds_local
      << " s, tufted cover " << s.cloud.seconds_cover << " s, intrinsic Delaunay "
      << s.cloud.seconds_idt << " s (" << s.flips.flips << " flips)";
    progress(args, m.str());
    return s;
  }

  // ---- mesh: manifold path when it represents the input with non-negative weights,
  //      tufted cover otherwise (the choice lives in the library: build_surface)
  intrinsic::SurfaceOptions opt;
  opt.mollify_relative_epsilon = eps;
  opt.intrinsic_delaunay = !args.has("no-delaunay");
  opt.force_tufted = args.has("tufted");
  intrinsic::SurfaceTriangulation st =
      intrinsic::build_surface(s.input.triangles, s.input.positions, opt);
  s.tri = std::move(st.tri);
  s.path = st.path_name();
  s.path_reason = opt.force_tufted ? "--tufted" : st.reason;
  s.build = std::move(st.build);
  s.tufted = std::move(st.tufted);
  s.mollify = st.mollify;
  s.flips = st.flips;
  s.boundary_vertex = std::move(st.boundary_vertex);
  s.seconds_build = st.seconds_build;
  s.seconds_flip = st.seconds_flip;
  progress(args, "path: " + s.path + " (" + s.path_reason + ")");
  if (s.build.dropped_faces) {
    progress(args,
             "dropped " + std::to_string(s.build.dropped_faces) + " faces that repeat a vertex");
  }
  if (s.build.reoriented_faces) {
    progress(args, "reoriented " + std::to_string(s.build.reoriented_faces) +
                       " faces for a consistent orientation");
  }
  if (s.mollify.delta > 0) {
    std::ostringstream m;
    m << "mollified " << s.mollify.faces_below_margin << " faces: every edge length + "
      << s.mollify.delta;
    progress(args, m.str());
  }
  if (opt.intrinsic_delaunay) {
    progress(args, "intrinsic Delaunay: " + std::to_string(s.flips.flips) + " flips");
  }
  return s;
}

}  // namespace ifem::cli
