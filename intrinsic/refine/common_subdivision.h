// The common subdivision of a signpost triangulation (the overlay of the intrinsic and the input
// triangulations as a 3D mesh on the input surface) and the PLY writers for it and for traced
// polylines.
#pragma once

#include <Eigen/Core>
#include <cstddef>
#include <string>
#include <vector>

#include "intrinsic/refine/signpost.h"

namespace ifem::intrinsic {

/// The common subdivision of a signpost triangulation: the overlay of the intrinsic and the
/// input triangulations, as a 3D triangle mesh on the input surface. Each of its polygons (the
/// intersection of one intrinsic face with one input face, convex) is split into a fan of
/// triangles, which record both faces. Its total area is the input's.
struct CommonSubdivision {
  Positions positions;  ///< vertices: input vertices first (same ids), then
                        ///< inserted intrinsic vertices, then edge crossings
  std::vector<Triangle> faces;
  std::vector<Index> intrinsic_face;  ///< per face: the intrinsic face it lies in
  std::vector<Index> input_face;      ///< per face: the input face, as an index into the
                                      ///< faces given (SignpostTriangulation::input_faces())
  std::size_t crossings = 0;          ///< C below: path points inside the intrinsic edges
};

/// Bytes the common subdivision costs at its peak (paths, segments, per-face planar graphs,
/// output) per unit of C + n_V + n_F_in (below): an upper bound of the measured peak
/// (docs/decisions.md D-095).
inline constexpr double kSubdivisionBytesPerCrossing = 512.0;

/// Builds the common subdivision by tracing every intrinsic edge over the input and cutting
/// each input face along the traced segments.
///
/// Size: let C = Σ over intrinsic edges e of the points inside e's traced path (the input
/// edges e crosses, plus the input vertices it runs through). Then the output has at most
/// n_V + C + P vertices and at most Σ_P (|P| − 2 or |P|) ≤ 3 (C + n_F_in + E_int) triangles, P
/// the polygons (every polygon's nodes are path points, intrinsic vertices or input corners, each
/// shared by at most a bounded number of polygons), and it is built in memory about
/// kSubdivisionBytesPerCrossing × (C + n_V + n_F_in). The traces are counted as they are made:
/// when that would exceed `max_memory_bytes` (0:
/// default_memory_budget()), the call stops tracing and throws InvalidInput stating C so far
/// and the budget. A trace that fails (TraceError: a straight line crossing more than 4 × n_F_in
/// + 1000 sides, on degenerate input) stops the others too.
/// @throws TraceError when a trace fails; InvalidInput over the memory budget
CommonSubdivision common_subdivision(const SignpostTriangulation& st,
                                     double max_memory_bytes = 0.0);

/// Writes a common subdivision as a PLY triangle mesh with face properties `intrinsic_face`
/// and `input_face` (int). Atomic. @throws IoError if the file cannot be written
void write_common_subdivision_ply(const std::string& path, const CommonSubdivision& cs,
                                  bool binary = true);

/// Writes polylines (e.g. SignpostTriangulation::traced_edges_3d()) as a PLY line set:
/// vertices (x, y, z as double) and edges (vertex1, vertex2 as int), binary little-endian or
/// ASCII; opens in MeshLab, ParaView, Polyscope. Atomic (writes path.tmp, then renames).
/// `comment`: the header's comment line (what the lines are).
/// @throws IoError if the file cannot be written
void write_polylines_ply(
    const std::string& path, const std::vector<std::vector<Eigen::Vector3d>>& polylines,
    bool binary = true,
    const std::string& comment = "traced intrinsic edges over the input surface");

}  // namespace ifem::intrinsic
