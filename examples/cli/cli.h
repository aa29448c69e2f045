// Shared pieces of the `ifem` command: argument parsing, the command table, and loading an
// input into an intrinsic triangulation along the right path (manifold, tufted cover, point
// cloud). Each subcommand lives in its own cli_<name>.cpp and is listed in cli_commands.cpp;
// options are declared as tables (options.h).
#pragma once

#include <string>
#include <vector>

#include "intrinsic/core/triangulation.h"
#include "intrinsic/io/mesh_io.h"
#include "intrinsic/surface/face_analysis.h"
#include "intrinsic/surface/tufted_cover.h"
#include "options.h"
#include "pointcloud/pointcloud_laplacian.h"

namespace ifem::cli {

/// One subcommand: its table (parsing and help) and its body.
struct Command {
  CommandSpec spec;
  std::string summary;  ///< one line for `ifem --help`
  int (*run)(const Args&);
};

/// Every subcommand, in the order `ifem --help` lists them (cli_commands.cpp).
std::vector<Command> all_commands();

/// The options every command that loads a surface understands (appended to its groups):
/// --mollify --no-delaunay --tufted --pointcloud --knn --quiet.
OptionGroup surface_options();

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
/// Options whose range depends on the input (vertex ids, -k, --knn) are checked right after
/// reading (check_input_limits()).
/// @throws UsageError for such an option out of range; IoError / InvalidInput from loading
PreparedSurface prepare_surface(const std::string& file, const Args& args);

/// Prints a progress line to stderr unless --quiet was given.
void progress(const Args& args, const std::string& line);

/// Wall-clock seconds since an arbitrary epoch.
double now_seconds();

}  // namespace ifem::cli
