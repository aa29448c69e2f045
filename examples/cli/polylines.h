// Polylines on the input surface as an OBJ file ('v' lines, one 'l' line per polyline): the
// one writer of `ifem geodesic -o OUT.obj` and of the solver commands' --curves-out.
#pragma once

#include <Eigen/Core>
#include <string>
#include <vector>

namespace ifem::cli {

using Polyline = std::vector<Eigen::Vector3d>;

/// The OBJ text: a '# title' line, the points as 'v' lines, then one 'l' line per polyline
/// with ≥ 2 points (shorter ones are skipped). A closed polyline (`closed[i]`, its last point
/// repeating its first) writes that point once and ends its 'l' line at its first index again.
/// `closed` is empty (all open) or one flag per polyline.
std::string polylines_obj(const std::vector<Polyline>& lines, const std::vector<char>& closed,
                          const std::string& title);

/// Writes polylines_obj() to `path` atomically (path.tmp, then rename).
/// @throws IoError if it cannot be written
void write_polylines_obj(const std::string& path, const std::vector<Polyline>& lines,
                         const std::vector<char>& closed, const std::string& title);

/// Writes polylines_obj() (path ending in .obj, any case) or an ASCII PLY line set
/// (intrinsic::write_polylines_ply: vertex and edge elements, a closed polyline's first point
/// repeated at its end) to `path` atomically (path.tmp, then rename).
/// @throws IoError if it cannot be written; std::logic_error on another extension (a bug: the
///   extension is checked when the command starts)
void write_polylines(const std::string& path, const std::vector<Polyline>& lines,
                     const std::vector<char>& closed, const std::string& title);

}  // namespace ifem::cli
