// Shared pieces of the `ifem` command: argument parsing, the command table, and loading an
// input into an intrinsic triangulation along the right path (manifold, tufted cover, point
// cloud). Each subcommand lives in its own cli_<name>.cpp and is listed in ifem.cpp.
#pragma once

#include <map>
#include <set>
#include <string>
#include <vector>

#include "intrinsic/core/triangulation.h"
#include "intrinsic/io/mesh_io.h"
#include "intrinsic/surface/face_analysis.h"
#include "intrinsic/surface/tufted_cover.h"
#include "pointcloud/pointcloud_laplacian.h"

namespace ifem::cli {

/// Parsed command line of one subcommand: positionals, `--key value` / `--key=value` options
/// and value-less `--flags`. Short aliases: -o = --output, -k = --k, -h = --help.
class Args {
 public:
  /// @param flags the value-less options this command accepts
  /// @param options the options that take a value
  /// @throws InvalidInput on an unknown option or a missing value
  Args(int argc, char** argv, const std::set<std::string>& flags,
       const std::set<std::string>& options);
  const std::vector<std::string>& positional() const { return positional_; }
  bool has(const std::string& key) const { return values_.count(key) > 0; }
  std::string get(const std::string& key, const std::string& fallback = "") const;
  double get_double(const std::string& key, double fallback) const;
  long get_int(const std::string& key, long fallback) const;
  /// Comma-separated integers ("3,17,42").
  std::vector<long> get_int_list(const std::string& key) const;

 private:
  std::vector<std::string> positional_;
  std::map<std::string, std::string> values_;
};

/// One subcommand.
struct Command {
  std::string name;
  std::string summary;  ///< one line for `ifem --help`
  std::string help;     ///< full text for `ifem NAME --help`
  std::set<std::string> flags;
  std::set<std::string> options;
  int (*run)(const Args&);
};

/// The options every command that loads a surface understands (added to its option sets).
extern const std::set<std::string> kSurfaceFlags;    // --no-delaunay --tufted --pointcloud --quiet
extern const std::set<std::string> kSurfaceOptions;  // --mollify --knn
/// Help text for those options, to append to a command's help.
extern const char* const kSurfaceHelp;

/// An input loaded and turned into an intrinsic triangulation, with everything that was
/// repaired or chosen along the way.
struct PreparedSurface {
  io::SurfaceInput input;
  intrinsic::FaceListStats stats;
  intrinsic::IntrinsicTriangulation tri;
  intrinsic::BuildReport build;
  intrinsic::MollifyReport mollify;
  intrinsic::FlipReport flips;
  intrinsic::TuftedCoverReport tufted;  ///< filled on the "tufted" path
  pointcloud::Report cloud;             ///< filled on the "pointcloud" path
  std::string path;                     ///< "manifold", "tufted" or "pointcloud"
  std::string path_reason;              ///< why that path was taken
  /// #V, 1 on vertices of the input's boundary (edges with one face); empty for point clouds
  std::vector<char> boundary_vertex;
  double seconds_load = 0, seconds_build = 0, seconds_flip = 0;
};

/// Loads `file` and builds its intrinsic triangulation: mollified (--mollify, default 1e-5
/// relative), flipped to intrinsic Delaunay unless --no-delaunay. Prints one progress line per
/// stage to stderr unless --quiet. The path is chosen automatically:
///  - "pointcloud" when the file has no faces or --pointcloud (kNN local triangulations,
///    --knn K neighbours, glued into a tufted cover);
///  - "tufted" when --tufted, when an edge has 3+ faces, when the gluing is non-orientable, or
///    when boundary edges opposite obtuse angles would keep negative cotan weights;
///  - "manifold" otherwise (intrinsic::build_surface makes the mesh choice).
/// On every path the triangulation's vertices are the input's vertices in the input's order
/// (unreferenced / isolated ones included: zero row in L, zero mass).
PreparedSurface prepare_surface(const std::string& file, const Args& args);

/// Prints a progress line to stderr unless --quiet was given.
void progress(const Args& args, const std::string& line);

/// Wall-clock seconds since an arbitrary epoch.
double now_seconds();

}  // namespace ifem::cli
