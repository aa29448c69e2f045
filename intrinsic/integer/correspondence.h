// The correspondence between an intrinsic triangulation and its input, whichever way it is kept:
// signposts (SignpostTriangulation: real-valued directions, traced in floating point) or integer
// coordinates (NormalCoordinateTriangulation: normal coordinates and roundabouts, whose
// combinatorics are exact). One view serves every consumer (vertex locations, data carried onto
// inserted vertices, the common subdivision, traced edges, saving) so none of them branches on
// the representation; docs/decisions.md D-250.
#pragma once

#include <Eigen/Core>
#include <optional>
#include <string>
#include <vector>

#include "intrinsic/core/surface_point.h"
#include "intrinsic/core/triangulation.h"
#include "intrinsic/integer/normal_coordinates.h"
#include "intrinsic/refine/common_subdivision.h"
#include "intrinsic/refine/signpost.h"

namespace ifem::intrinsic {

/// How an intrinsic triangulation keeps its correspondence with the input.
enum class Correspondence {
  kSignposts,  ///< SignpostTriangulation
  kInteger,    ///< NormalCoordinateTriangulation
};

/// "signposts" or "integer" (the word the CLI and Python take).
const char* to_string(Correspondence c);

/// The Correspondence named by `word` ("signposts" or "integer").
/// @throws InvalidInput naming the word and the two allowed ones
Correspondence parse_correspondence(const std::string& word);

/// A non-owning view of one triangulation with its correspondence (the object viewed must
/// outlive the view). Every intrinsic vertex id and input face id is the viewed object's own.
class CorrespondenceView {
 public:
  CorrespondenceView(const SignpostTriangulation& st) : st_(&st) {}          // NOLINT
  CorrespondenceView(const NormalCoordinateTriangulation& nc) : nc_(&nc) {}  // NOLINT

  Correspondence kind() const {
    return st_ ? Correspondence::kSignposts : Correspondence::kInteger;
  }
  /// The viewed object when it is of that kind, else nullptr.
  const SignpostTriangulation* signposts() const { return st_; }
  const NormalCoordinateTriangulation* integer() const { return nc_; }

  const IntrinsicTriangulation& intrinsic() const;
  /// The input triangulation (vertices 0..#V_in−1 are the input's and the intrinsic ones).
  const IntrinsicTriangulation& input() const;
  const Positions& input_positions() const;  ///< #V_in×3
  Index n_input_vertices() const { return input().n_vertices(); }

  /// Where every intrinsic vertex lies on the input: a face of input() and barycentric
  /// coordinates (#V entries). Integer coordinates place inserted vertices through the common
  /// subdivision (vertex_locations(nc)), so the call costs O(overlay) when there are any.
  /// @throws InvalidInput / TraceError when a location cannot be found
  std::vector<SurfacePoint> vertex_locations() const;
  /// Every intrinsic vertex in 3D (#V×3): input vertices at their positions, inserted ones at
  /// their locations on the input's faces.
  Positions vertex_positions() const;
  /// Per-vertex values on the input's vertices (#V_in) carried onto every intrinsic vertex
  /// (#V): copied on input vertices, interpolated linearly over the input face of an inserted
  /// vertex's location.
  /// @throws InvalidInput on a size mismatch
  Eigen::VectorXd input_to_intrinsic(const Eigen::VectorXd& input_values) const;
  /// The common subdivision (common_subdivision(st, max_memory_bytes) or common_subdivision(nc);
  /// the same format). The budget applies to signposts only.
  CommonSubdivision common_subdivision(double max_memory_bytes = 0.0) const;
  /// One polyline per intrinsic edge (#E), in 3D on the input's faces, from one end over each
  /// input edge it crosses to the other, starting at an input vertex when one end is.
  /// @throws TraceError / InvalidInput when a trace fails
  std::vector<std::vector<Eigen::Vector3d>> traced_edges_3d() const;
  /// The unit 3D direction in which halfedge h leaves its tail on the input surface
  /// (SignpostTriangulation::halfedge_direction_3d() or
  /// NormalCoordinateTriangulation::halfedge_direction_3d(); the latter needs an input vertex
  /// as the tail).
  /// @throws InvalidInput as those
  Eigen::Vector3d halfedge_direction_3d(Index h) const;
  /// Writes the object: format "ifem-signpost 1" or "ifem-integer 1" (file_format()).
  /// @throws IoError if the file cannot be written
  void save(const std::string& path) const;

 private:
  const SignpostTriangulation* st_ = nullptr;
  const NormalCoordinateTriangulation* nc_ = nullptr;
};

/// The first line of the file CorrespondenceView::save() writes for c: "ifem-signpost 1" or
/// "ifem-integer 1".
const char* file_format(Correspondence c);

/// A triangulation read back by load_triangulation(): exactly one of the two is set.
struct SavedTriangulation {
  std::optional<SignpostTriangulation> signposts;
  std::optional<NormalCoordinateTriangulation> integer;
  CorrespondenceView view() const {
    return signposts ? CorrespondenceView(*signposts) : CorrespondenceView(*integer);
  }
};

/// Reads a file written by CorrespondenceView::save() (either format, told by its first line).
/// @throws IoError naming the file and what is wrong: missing, neither format, an unsupported
///         version, or malformed / inconsistent content (SignpostTriangulation::load,
///         NormalCoordinateTriangulation::load)
SavedTriangulation load_triangulation(const std::string& path);

}  // namespace ifem::intrinsic
