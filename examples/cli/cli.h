// Shared pieces of the `ifem` command: argument parsing, the command table, and loading an
// input into an intrinsic triangulation along the right path (manifold, tufted cover, point
// cloud). Each subcommand lives in its own cli_<name>.cpp and is listed in cli_commands.cpp;
// options are declared as tables (options.h).
#pragma once

#include <optional>
#include <string>
#include <vector>

#include "intrinsic/io/mesh_io.h"
#include "options.h"
#include "progress_bar.h"
#include "solvers/recipes/pipeline.h"

namespace ifem::recipes {
struct Scene;
}

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

/// The library's prepared surface (solvers/recipes/pipeline.h): the CLI adds no state of its own.
using PreparedSurface = solvers::PreparedSurface;

/// The library's PrepareOptions from the surface options (--mollify, --no-delaunay, --tufted,
/// --pointcloud, --knn), with the progress sink (stderr unless --quiet).
solvers::PrepareOptions prepare_options(const Args& args);

/// Reads `file` (.pcd through the optional PCL adapter, anything else through
/// io::read_surface), prints one progress line, and checks the options whose range depends on
/// the input (vertex ids, -k, --knn: check_input_limits()).
/// @throws UsageError for such an option out of range; IoError from reading
io::SurfaceInput read_input(const std::string& file, const Args& args);

/// solvers::prepare_surface() of an input read by read_input(), with the command line's surface
/// options and, when given, refinement. The path is chosen by the library: point cloud (no
/// faces, or --pointcloud), tufted cover (--tufted, nonmanifold, non-orientable, negative
/// boundary weights), manifold otherwise. On every path the triangulation's first #V_in
/// vertices are the input's, in the input's order.
PreparedSurface prepare_surface(io::SurfaceInput input, const Args& args,
                                const std::optional<solvers::SurfaceRefineOptions>& refine = {});
/// read_input() then prepare_surface().
PreparedSurface prepare_surface(const std::string& file, const Args& args,
                                const std::optional<solvers::SurfaceRefineOptions>& refine = {});

/// Prints a progress line to stderr unless --quiet was given.
void progress(const Args& args, const std::string& line);

/// --triangulation FILE.ifem of `ifem view` and `ifem render`, when given: the saved intrinsic
/// triangulation's edges traced into scene.intrinsic_edges (recipes::add_intrinsic_edges), and
/// a progress line. @throws IoError, InvalidInput (another mesh's triangulation), TraceError
void add_triangulation(recipes::Scene& scene, const Args& args);

}  // namespace ifem::cli
