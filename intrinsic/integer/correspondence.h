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

/// Point location between the input and the intrinsic triangulation of a CorrespondenceView,
/// both ways, from its common subdivision (CorrespondenceView::common_subdivision(): built from
/// the traced signposts or from the integers, one implementation for both). Each triangle of
/// the subdivision (a "piece": part of one overlay polygon, so one intrinsic face ∩ one input
/// face) carries its corners' barycentric coordinates in both faces; inside a piece the map
/// between the two is affine (both faces are flat there), so a point is located by finding the
/// piece that holds it and interpolating. Input-side coordinates come from the subdivision's 3D
/// positions in the input face; intrinsic-side ones from unfolding the pieces of each intrinsic
/// face into the plane (rigid steps across shared sides) and reading them against its corners.
/// Faces on the input side are faces of view.input() (as vertex_locations()), not the indices
/// of the faces given (CommonSubdivision::input_face). Holds no reference to the view.
class PointLocator {
 public:
  /// Builds the common subdivision (max_memory_bytes as CorrespondenceView::common_subdivision)
  /// and both coordinates of every piece corner: O(subdivision) time and about 250 bytes per
  /// piece.
  /// @throws TraceError / InvalidInput as common_subdivision(); InvalidInput when the pieces of
  ///         an intrinsic face do not form one connected region (an inconsistent subdivision)
  explicit PointLocator(const CorrespondenceView& view, double max_memory_bytes = 0.0);

  /// Points on faces of view.input() → the same points on view.intrinsic() (batched, parallel).
  /// Points on edges and at vertices are found in any piece that touches them (the result is
  /// one of the equivalent SurfacePoints).
  /// @throws InvalidInput naming the first bad point: a face out of range, coordinates not
  ///         finite / below −1e−9 / not summing to 1 within 1e−9, or (cannot happen on a valid
  ///         subdivision) a point in no piece of its face, with how far outside the nearest is
  std::vector<SurfacePoint> input_to_intrinsic(const std::vector<SurfacePoint>& points) const;
  /// Points on faces of view.intrinsic() → the same points on faces of view.input().
  /// @throws InvalidInput as input_to_intrinsic()
  std::vector<SurfacePoint> intrinsic_to_input(const std::vector<SurfacePoint>& points) const;

  /// Pieces (triangles of the common subdivision, in its order).
  Index n_pieces() const { return Index(intrinsic_face_.size()); }
  Index intrinsic_face(Index p) const { return intrinsic_face_[std::size_t(p)]; }
  /// The face of view.input() piece p lies in.
  Index input_face(Index p) const { return input_face_[std::size_t(p)]; }
  /// Column k: barycentric coordinates of piece p's corner k in intrinsic_face(p) (each column
  /// sums to 1; exact unit vectors at intrinsic vertices).
  const Eigen::Matrix3d& at_intrinsic(Index p) const { return at_intrinsic_[std::size_t(p)]; }
  /// Column k: barycentric coordinates of piece p's corner k in input_face(p).
  const Eigen::Matrix3d& at_input(Index p) const { return at_input_[std::size_t(p)]; }
  /// Area of piece p in the input's metric (input face area × its share), ≥ 0.
  double area(Index p) const { return area_[std::size_t(p)]; }

  /// Per face of one side, its pieces with a coarse grid over each face's barycentric square for
  /// faces with many pieces (internal; public for the implementation's helpers).
  struct FaceIndex {
    std::vector<Index> begin;        ///< #faces + 1
    std::vector<Index> pieces;       ///< piece ids, grouped by face
    std::vector<Index> grid_offset;  ///< #faces + 1: first cell slot (0 cells: no grid)
    std::vector<int> grid_size;      ///< #faces: cells per axis
    std::vector<Index> cell_begin;   ///< per cell + 1 (concatenated over faces)
    std::vector<Index> cell_pieces;  ///< piece ids per cell
  };

 private:
  std::vector<Index> intrinsic_face_, input_face_;
  std::vector<Eigen::Matrix3d> at_intrinsic_, at_input_;
  std::vector<double> area_;
  FaceIndex by_input_, by_intrinsic_;
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
