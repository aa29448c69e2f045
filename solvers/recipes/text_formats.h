// The small text formats of the recipes, one reader each, used by the CLI and the Python
// package alike (the curves file is solvers/recipes/curves.h's read_curves_file /
// write_curves_file). Every format: one item per line, '#' starts a comment, blank lines are
// skipped, anything else is an error naming FILE:line, the token and what was expected.
//
//   vertex list     one vertex id per line                 `ifem distance --sources-batch`
//   Dirichlet file  'VERTEX VALUE' per line                `ifem poisson --dirichlet`
//   constraints     'VERTEX X Y Z' per line                `ifem field --constraints`
//   network file    'path P0 P1 ...' / 'loop P0 P1 ...'    `ifem geodesic --network`
//
// Points of a network (and of `ifem geodesic --path`) are a vertex id or a face point
// face:F:u:v: the point of face F (0-based, the file's face order) with barycentric
// coordinates (1 − u − v, u, v) for its corners in the file's order; u, v ≥ 0 and u + v ≤ 1
// (within 1e-12), anything else is refused.
#pragma once

#include <Eigen/Core>
#include <array>
#include <string>
#include <vector>

#include "intrinsic/core/types.h"
#include "solvers/recipes/tangent_fields.h"

namespace ifem::recipes {

/// A vertex id read from a file, with its line (for messages once #V is known).
struct ListedVertex {
  Index vertex = kInvalidIndex;
  long line = 0;  ///< 1-based line of the file
};

/// A vertex list: one vertex id (an integer ≥ 0) per line, in order, repeats allowed.
/// @throws IoError naming "FILE:line" on an unreadable file or a malformed line
/// @throws InvalidInput when the file lists no vertex
std::vector<ListedVertex> read_vertex_list(const std::string& path);

/// The ids of a vertex list, each checked against an input of n_vertices vertices.
/// @throws InvalidInput naming "FILE:line" and the range for an id ≥ n_vertices
std::vector<Index> checked_vertex_ids(const std::string& path,
                                      const std::vector<ListedVertex>& listed, Index n_vertices);

/// Dirichlet values: vertices and the values u takes there (same length).
struct DirichletValues {
  std::vector<Index> vertices;
  Eigen::VectorXd values;
};

/// A Dirichlet file: 'VERTEX VALUE' per line (a vertex id and a finite number). An empty file
/// (only comments) gives no values.
/// @throws IoError naming "FILE:line" on an unreadable file or a malformed line
/// @throws InvalidInput naming "FILE:line" for a vertex outside [0, n_vertices)
DirichletValues read_dirichlet_file(const std::string& path, Index n_vertices);

/// A constraints file: 'VERTEX X Y Z' per line, a direction to hold at an input vertex (any
/// length, finite); each direction's origin is "FILE:line". The vertex range and conflicting
/// directions at one vertex are checked by the field recipe (it knows #V; arrays from Python
/// go there too).
/// @throws IoError naming "FILE:line" on an unreadable file or a malformed line; a file with
///         no direction is an error too
std::vector<solvers::InputDirection> read_constraints_file(const std::string& path);

/// A point of a geodesic curve as given: an input vertex, or a point inside a face of the
/// input (barycentric weights of that face's corners, in the input's corner order).
struct GivenPoint {
  Index vertex = kInvalidIndex;  ///< input vertex id; kInvalidIndex for a face point
  Index face = kInvalidIndex;    ///< face of the input (io::SurfaceInput::triangles), 0-based
  std::array<double, 3> bary{};  ///< weights ≥ 0 summing to 1 (face points only)
  std::string token;             ///< how messages name it ("'face:12:0.3:0.3'", "points[2]")
  bool same_as(const GivenPoint& o) const {
    return vertex == o.vertex && face == o.face && bary == o.bary;
  }
};

/// One geodesic curve as asked for (geodesic recipe, solvers/recipes/geodesic.h).
struct GivenCurve {
  std::vector<GivenPoint> points;  ///< ≥ 2, consecutive ones distinct (a loop's last and first)
  bool closed = false;             ///< a loop
  bool pin = true;                 ///< keep passing through every point (open paths always do)
  std::string origin;              ///< where it was given: "--path", "FILE:line", "curves[2]"
};

/// The fields of s between separators, empty ones included ("a,,b" → {"a", "", "b"}; "" →
/// {""}; a trailing separator gives a last empty field): the tokenizer of the comma lists of
/// the CLI's options and of the point tokens (face:F:u:v) in network files.
std::vector<std::string> split_fields(const std::string& s, char sep);

/// One point token, a vertex id (an integer ≥ 0) or face:F:u:v, into p (p.token = "'token'").
/// @return "" on success, else what is wrong with it (naming the token)
std::string parse_point_token(const std::string& token, GivenPoint& p);

/// "" when no two consecutive points of c (a loop's last and first too) are the same point,
/// else which ones ("points 2 and 3 are the same point '5' ...").
std::string repeated_point(const GivenCurve& c);

/// A network file: 'path P0 P1 ...' (an open geodesic through the points) or 'loop P0 P1 ...'
/// (a closed one; pinned to its points when pin_loops) per line, ≥ 2 points each, points as
/// parse_point_token(). Each curve's origin is "FILE:line".
/// @throws IoError naming "FILE:line" on an unreadable file, a malformed line, a bad point
///         (a face point with u + v > 1 included) or repeated consecutive points; a file with no
///         curve is an error too
std::vector<GivenCurve> read_network_file(const std::string& path, bool pin_loops);

}  // namespace ifem::recipes
