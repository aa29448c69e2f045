// Shared pieces of the `ifem` command: argument parsing, the command table, and loading an
// input into an intrinsic triangulation along the right path (manifold, tufted cover, point
// cloud). Each subcommand lives in its own cli_<name>.cpp and is listed in ifem.cpp.
#pragma once

#include <map>
#include <optional>
#include <set>
#include <string>
#include <vector>

#include "intrinsic/io/mesh_io.h"
#include "solvers/pipeline.h"

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

/// The library's prepared surface (solvers/pipeline.h): the CLI adds no state of its own.
using PreparedSurface = solvers::PreparedSurface;

/// The library's PrepareOptions from the surface options (--mollify, --no-delaunay, --tufted,
/// --pointcloud, --knn) and the progress sink (stderr unless --quiet).
solvers::PrepareOptions prepare_options(const Args& args);

/// Reads `file` (.pcd through the optional PCL adapter, anything else through io::read_surface)
/// and prints one progress line.
io::SurfaceInput read_input(const std::string& file, const Args& args);

/// solvers::prepare_surface() of an input read by read_input(), with the command line's surface
/// options and, when given, refinement. The path is chosen by the library: point cloud (no
/// faces, or --pointcloud), tufted cover (--tufted, nonmanifold, non-orientable, negative
/// boundary weights), manifold otherwise. On every path the triangulation's first #V_in
/// vertices are the input's, in the input's order.
PreparedSurface prepare_surface(io::SurfaceInput input, const Args& args,
                                const std::optional<solvers::RefineSettings>& refine = {});
/// read_input() then prepare_surface().
PreparedSurface prepare_surface(const std::string& file, const Args& args,
                                const std::optional<solvers::RefineSettings>& refine = {});

/// Prints a progress line to stderr unless --quiet was given.
void progress(const Args& args, const std::string& line);

/// Wall-clock seconds since an arbitrary epoch.
double now_seconds();

}  // namespace ifem::cli
