// Data on curves in the solver commands (`ifem poisson --curves`, `ifem distance --curves`):
// the two options, the curves file's help, the options refused with curves, and the steps
// around the library's solvers/recipes/curves.h (read the file, check it against the mesh, insert
// the curves, write the results and the curves).
#pragma once

#include <functional>
#include <optional>
#include <string>
#include <vector>

#include "cli.h"
#include "polylines.h"
#include "results.h"
#include "solvers/recipes/curves.h"

namespace ifem::cli {

/// --curves FILE and --curves-out FILE.obj, for a command's own option group. `use` says what
/// the command does with the curves (one line of --curves' help).
std::vector<OptionSpec> curve_options(const std::string& use);

/// The curves file format with examples, for the commands' --help epilogue. `values_used`:
/// whether the command uses the curves' values (poisson) or only where they run (`command`:
/// distance, field).
std::string curves_file_help(bool values_used, const std::string& command = "distance");

/// An option of a command that makes no sense with --curves, and why (for the message).
struct CurveRefusal {
  std::string option;  ///< long name without "--"
  std::string reason;
};

/// Refuses, with a UsageError, --curves-out without --curves, and with --curves every option in
/// `refused` that was given (the command's own, such as distance's --source) and the surface
/// and refinement options curves cannot use (--tufted, --pointcloud, --knn, --no-delaunay,
/// --relax, --max-edge); checks --curves-out's extension. Call before any work.
void check_curve_options(const Args& args, const std::vector<CurveRefusal>& refused);

/// What a command with --curves computes before it writes anything.
struct CurveRun {
  solvers::CurveSurface surface;
  std::vector<Polyline> polylines;  ///< for --curves-out (empty without it)
};

/// Reads --curves' file (before the mesh, so a malformed file fails fast).
/// @throws IoError naming file:line
std::vector<solvers::CurveCondition> read_curves(const Args& args);

/// Checks the curves against the input (validate_curves; `need_values` for poisson), then
/// solvers::prepare_curve_surface() with --mollify and, when given, the refinement settings;
/// the library prints its progress lines (curves inserted, flips, refinement) unless --quiet,
/// this adds curve edges left non-Delaunay and negative cotan weights.
/// @throws InvalidInput on curves that do not fit the input or an input curves cannot use
solvers::CurveSurface prepare_curves(io::SurfaceInput input,
                                     std::vector<solvers::CurveCondition> curves, const Args& args,
                                     bool need_values,
                                     const std::optional<solvers::SurfaceRefineOptions>& refine);

/// Writes the per-vertex results (the input mesh + properties, or .txt) and, with
/// --curves-out, the curves as OBJ polylines; every output is computed before this is called,
/// and a failure on the second file removes the first (no partial outputs).
void write_curve_outputs(const Args& args, const ResultOutput& out, const CurveRun& run,
                         const std::vector<io::VertexProperty>& properties);
/// The same with the main output (out.path) written by `write` (e.g. rows of 3D vectors).
void write_curve_outputs(const Args& args, const ResultOutput& out, const CurveRun& run,
                         const std::function<void()>& write);

/// The "wrote FILE.obj: N curves, P points" line on stdout, with --curves-out.
void print_curves_written(const Args& args, const CurveRun& run);

/// The curves traced over the input when --curves-out is given, else none.
std::vector<Polyline> curve_polylines_if_asked(const Args& args, const solvers::CurveSurface& s);

}  // namespace ifem::cli
