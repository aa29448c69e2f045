#include "cli.h"

#include <cctype>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <sstream>
#include <utility>

#include "intrinsic/core/errors.h"
#include "intrinsic/io/mesh_io.h"
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

solvers::PrepareOptions prepare_options(const Args& args) {
  solvers::PrepareOptions opt;
  opt.mollify_relative_epsilon = args.get_double("mollify", intrinsic::kDefaultMollifyEpsilon);
  opt.intrinsic_delaunay = !args.has("no-delaunay");
  opt.force_tufted = args.has("tufted");
  opt.force_pointcloud = args.has("pointcloud");
  opt.knn = static_cast<int>(args.get_int("knn", 30));
  if (!args.has("quiet")) {
    opt.progress = [](const std::string& line) {
      std::fprintf(stderr, "ifem: %s\n", line.c_str());
    };
  }
  return opt;
}

io::SurfaceInput read_input(const std::string& file, const Args& args) {
  io::SurfaceInput in;
  if (io::file_extension(file) != ".pcd") {
    in = io::read_surface(file);
  } else {
#ifdef IFEM_HAVE_PCL
    pointcloud::PclPoints pts = pointcloud::read_pcd(file);
    in.positions = std::move(pts.positions);
    if (pts.has_normals()) in.normals = std::move(pts.normals);
    in.format = "pcd";
    if (pts.dropped_non_finite > 0) {
      progress(args, file + ": dropped " + std::to_string(pts.dropped_non_finite) +
                         " points with non-finite coordinates");
    }
#else
    throw IoError(file +
                  ": this ifem was built without PCL: .pcd needs the PCL adapter "
                  "(install libpcl-dev and reconfigure with -DIFEM_WITH_PCL=ON)");
#endif
  }
  progress(args, "read " + file + ": " + std::to_string(in.positions.rows()) + " vertices, " +
                     std::to_string(in.n_polygons) + " faces (" + in.format + ")");
  return in;
}

PreparedSurface prepare_surface(io::SurfaceInput input, const Args& args,
                                const std::optional<solvers::RefineSettings>& refine) {
  solvers::PrepareOptions opt = prepare_options(args);
  opt.refine = refine;
  return solvers::prepare_surface(std::move(input), opt);
}

PreparedSurface prepare_surface(const std::string& file, const Args& args,
                                const std::optional<solvers::RefineSettings>& refine) {
  return prepare_surface(read_input(file, args), args, refine);
}

}  // namespace ifem::cli
