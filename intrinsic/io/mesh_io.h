// Reading and writing meshes and point clouds: OBJ, OFF, PLY (ASCII / binary LE / BE), STL
// (ASCII / binary), XYZ; PLY output with named per-vertex and per-face scalar properties;
// Matrix Market.
// Vertex count and order of OBJ/OFF/PLY/XYZ input are kept exactly (no welding, reordering or
// dropping of unreferenced vertices). Errors: IoError naming the file, the line (text) or byte
// offset (binary), and the problem. Writers never leave a partial file behind.
#pragma once

#include <Eigen/Core>
#include <Eigen/SparseCore>
#include <string>
#include <vector>

#include "intrinsic/core/progress.h"
#include "intrinsic/core/types.h"
#include "intrinsic/io/surface_input.h"

namespace ifem::io {

/// The lowercased extension of a path's file name, with its dot (".obj"); "" when it has none.
std::string file_extension(const std::string& path);

/// Reads a mesh or point cloud, choosing the format from the extension (.obj .off .ply .stl
/// .xyz .txt; case-insensitive). A file with no faces is a point cloud.
/// @param on_progress optional (ProgressCallback): stage "read", the bytes read over the file's
///        size; then for OBJ stage "parse", the bytes parsed
/// @throws IoError on a missing file, unknown extension, malformed or truncated content, a face
///         index out of range, or a NaN/inf coordinate (with file and line / byte offset)
SurfaceInput read_surface(const std::string& path, const ProgressCallback& on_progress = {});

/// Same, but a file without faces is an error ("no faces") — for commands that need a mesh.
/// @throws IoError as read_surface(), and on a file without faces
SurfaceInput read_mesh(const std::string& path);

/// Writes a PLY (binary little-endian by default) with vertices, optional triangles and any
/// number of named per-vertex double properties (each #V long). Atomic: writes path.tmp and
/// renames it.
/// @throws IoError if the file cannot be written or a property has the wrong length
void write_ply(const std::string& path, const Positions& positions,
               const std::vector<Triangle>& faces,
               const std::vector<VertexProperty>& vertex_properties = {}, bool binary = true);
/// The same with named per-face double properties too (each #F long, one value per triangle of
/// `faces`, written after each face's vertex_indices; names unique within the face element).
/// @throws IoError as above, and if a face property has the wrong length
void write_ply(const std::string& path, const Positions& positions,
               const std::vector<Triangle>& faces,
               const std::vector<VertexProperty>& vertex_properties,
               const std::vector<VertexProperty>& face_properties, bool binary = true);

/// Writes a sparse matrix in Matrix Market coordinate format (general, real, 1-based), atomic.
/// @throws IoError if the file cannot be written
void write_matrix_market(const std::string& path, const Eigen::SparseMatrix<double>& A);

/// Reads a Matrix Market coordinate real matrix (general, symmetric or skew-symmetric; such a
/// file's stored triangle is mirrored), rows × cols as the header says.
/// @throws IoError on a missing or malformed file (naming the line)
Eigen::SparseMatrix<double> read_matrix_market(const std::string& path);

/// Writes one value per line, each the shortest text that reads back to the same double
/// (std::to_chars; inf as "inf", nan as "nan"), atomic.
/// @throws IoError if the file cannot be written
void write_values(const std::string& path, const Eigen::VectorXd& values);

/// Writes a matrix as text: one line per row, its columns separated by one space, each value
/// as write_values() writes it (read_values() reads a one-column file back bit for bit), atomic.
/// @throws IoError if the file cannot be written
void write_rows(const std::string& path, const Eigen::MatrixXd& rows);

/// Reads one value per line (blank lines and '#' comments skipped; "inf"/"nan" accepted).
/// @throws IoError on a missing file or a malformed value (naming the line)
Eigen::VectorXd read_values(const std::string& path);

}  // namespace ifem::io
