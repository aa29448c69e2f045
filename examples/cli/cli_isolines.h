// Isolines of a per-vertex field as a polyline file (solvers/recipes/isolines.h): what
// `ifem isolines` writes, and the --isolines N / --isolines-out FILE options of the commands
// that compute a field (distance, poisson).
#pragma once

#include <Eigen/Core>
#include <optional>
#include <string>
#include <vector>

#include "cli.h"
#include "solvers/recipes/isolines.h"

namespace ifem::cli {

/// Isolines computed, not yet written.
struct IsolineOutput {
  std::string path;  ///< .obj ('l' lines) or .ply (line set)
  std::vector<recipes::Isoline> lines;
  std::size_t n_levels = 0;
  std::string title;  ///< the file's comment line
};

/// --isolines N and --isolines-out FILE for a command whose per-vertex result is `field`
/// ("distance", "u").
std::vector<OptionSpec> isoline_options(const std::string& field);

/// Both or neither of --isolines and --isolines-out; called before any computation.
/// @throws UsageError
void check_isoline_options(const Args& args);

/// With --isolines N: the isolines of f (its first #V_in values) at N levels evenly spaced
/// inside its finite range, on the input's faces. Computed before any output is written, so a
/// failure leaves no file. @throws InvalidInput on a point cloud or a field with no finite value
std::optional<IsolineOutput> isolines_if_asked(const Args& args, const io::SurfaceInput& input,
                                               const Eigen::VectorXd& f, const std::string& name);

/// Writes the polyline file and prints its 'wrote' line.
/// @throws IoError if it cannot be written
void write_isolines(const IsolineOutput& out);

}  // namespace ifem::cli
