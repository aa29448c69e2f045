// The one writer of per-vertex results (distance, poisson, eigen, geodesic --all-from, field): the
// input mesh with PLY vertex (and face) properties, or one value per line in a .txt. The output's
// extension is checked when the command starts, before any computation (result_output()).
#pragma once

#include <string>
#include <vector>

#include "cli.h"

namespace ifem::cli {

/// Where and how a command writes its per-vertex results.
struct ResultOutput {
  std::string path;
  bool ply = true;  ///< .ply: the input mesh + vertex properties; else .txt: one value a line
};

/// The option `name`'s path (normally "output"), its extension checked against the option's
/// table entry (OptionSpec::extensions: {".ply"} or {".ply", ".txt"}).
/// @throws UsageError when the option is missing or has another extension
ResultOutput result_output(const Args& args, const std::string& name = "output");

/// Writes per-vertex results: each property's first #V values (the input's vertices, in the
/// input's order; the triangulation's further vertices are refinement's and are dropped).
/// .ply: the input positions and faces with every property; .txt: exactly one property.
/// @throws std::logic_error if a property has fewer than #V values or a .txt gets several
/// @throws IoError if the file cannot be written
void write_results(const ResultOutput& out, const PreparedSurface& s,
                   const std::vector<io::VertexProperty>& properties,
                   const std::vector<io::VertexProperty>& face_properties = {});
/// The same on an input as read (for commands that build no PreparedSurface). face_properties:
/// per-face values (one per triangle of input.triangles, in order) for the .ply's face element;
/// a .txt does not hold them.
void write_results(const ResultOutput& out, const io::SurfaceInput& input,
                   const std::vector<io::VertexProperty>& properties,
                   const std::vector<io::VertexProperty>& face_properties = {});

/// Writes a per-vertex matrix as text: one line per row (an input vertex), its columns separated
/// by spaces, each value the shortest text that reads back to the same double (io::write_rows;
/// `x y z` tangent vectors, `u v` coordinates, distance batches).
/// @throws IoError if the file cannot be written
void write_rows(const std::string& path, const Eigen::MatrixXd& rows);

/// Writes a matrix as a NumPy .npy file (format 1.0, little-endian float64, shape
/// (rows, cols), Fortran order: numpy.load() gives the same matrix, no copy of Eigen's layout).
/// @throws IoError if the file cannot be written
void write_npy(const std::string& path, const Eigen::MatrixXd& m);

}  // namespace ifem::cli
