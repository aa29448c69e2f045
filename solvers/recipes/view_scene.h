// What `ifem view` shows, as data: a Scene (the input surface or point cloud, per-vertex
// scalar fields, polylines on the surface, tangent-field glyphs and singularities, the
// intrinsic triangulation's edges traced over the input), assembled from the project's own
// outputs, and the self-contained HTML page that draws it offline in a browser.
//
//   mesh file ──► view_scene() ──► add_properties()       PLY outputs: fields, fx fy fz,
//                                                         singularity
//                                  add_polylines()        OBJ polylines (--curves-out, geodesic;
//                                                         solvers::read_polylines)
//                                  add_intrinsic_edges()  a saved .ifem triangulation
//             ──► view_page() / write_view_page()         one HTML file: the page template (in
//                                                         the repository), scene and three.js
//             ──► render_scene_of() ──► solvers::render_scene()   the same scene as a PNG
//
// The page embeds three.js (npm package `three`, version kThreeVersion, installed by
// scripts/setup.sh; never copied into the repository): find_three_js() says where it is.
#pragma once

#include <Eigen/Core>
#include <string>
#include <vector>

#include "intrinsic/core/types.h"
#include "intrinsic/integer/correspondence.h"
#include "intrinsic/io/surface_input.h"
#include "solvers/recipes/render.h"

namespace ifem::recipes {

/// The three.js release the page is written for (scripts/setup.sh installs exactly this one).
inline constexpr const char* kThreeVersion = "0.170.0";

/// A per-vertex scalar the page can colour by.
struct SceneField {
  std::string name;        ///< shown in the property menu; unique within a scene
  std::string units;       ///< shown in the legend after the range; "" for none
  Eigen::VectorXd values;  ///< #V of the scene; non-finite values are drawn grey
};

/// Polylines in 3D (curves on the surface, traced edges): each has ≥ 2 points.
using Polylines = std::vector<std::vector<Eigen::Vector3d>>;

/// A named group of polylines, one toggle in the page.
struct SceneCurves {
  std::string name;
  Polylines lines;
};

/// A point where a direction field turns: its position and index (in units of 1/N).
struct SceneSingularity {
  Eigen::Vector3d position;
  double index = 0.0;
};

/// Everything the page draws. Positions and polylines are in the input's units.
struct Scene {
  std::string title;
  Positions positions;          ///< #V×3
  std::vector<Triangle> faces;  ///< empty: a point cloud, drawn as points
  std::vector<SceneField> fields;
  std::vector<SceneCurves> curves;
  /// Tangent-field glyphs as segments: rows 2i and 2i+1 are the ends of segment i (N segments
  /// per vertex for an N-direction field, starting at the vertex; N = 2 draws both halves).
  Eigen::Matrix<double, Eigen::Dynamic, 3, Eigen::RowMajor> glyph_segments;
  std::vector<SceneSingularity> singularities;
  Polylines intrinsic_edges;  ///< one polyline per intrinsic edge, traced over the input
};

/// A scene of an input as read (io::read_surface): its positions and triangles, and its PLY
/// vertex properties as fields (add_properties() with symmetry 1).
/// @throws InvalidInput if the input has no vertex
Scene view_scene(const io::SurfaceInput& input, const std::string& title);

/// Adds per-vertex properties (#V each) to the scene: fx, fy, fz together become glyphs (a
/// unit tangent vector per vertex, `symmetry` = N directions: the vector turned by 2πk/N about
/// the vertex normal, k = 0..N−1; for N = 2 a line through the vertex), `singularity` (nonzero
/// entries) becomes singularity markers; every property, these too, becomes a field named
/// `prefix` + its name (a name already used gets " (2)", " (3)", ...).
/// @throws InvalidInput if a property's length is not #V or symmetry is not in [1, 6]
void add_properties(Scene& scene, const std::vector<io::VertexProperty>& properties,
                    const std::string& prefix = "", int symmetry = 1);

/// Adds one field. @throws InvalidInput if its length is not #V or its name is empty
void add_field(Scene& scene, SceneField field);

/// Adds a group of polylines (polylines with fewer than 2 points are dropped).
/// @throws InvalidInput on a non-finite point
void add_polylines(Scene& scene, const std::string& name, const Polylines& lines);

/// Traces every intrinsic edge of `st` (signposts or integer coordinates) over its input
/// (CorrespondenceView::traced_edges_3d()) into scene.intrinsic_edges: one polyline per
/// intrinsic edge, every point on an input face.
/// @throws InvalidInput if st's input does not have the scene's vertices (count, or positions
///         farther apart than 1e-9 × the bounding box diagonal)
/// @throws TraceError when a trace fails
void add_intrinsic_edges(Scene& scene, const intrinsic::CorrespondenceView& st);

/// The same scene for `ifem render` (solvers::render_scene): positions, faces, the field named
/// `property` ("" = the first field, or none when the scene has none), every curve group's
/// polylines as curves, the intrinsic edges and the glyph segments. Singularities are not
/// drawn (colour by the `singularity` field to see them).
/// @throws InvalidInput when `property` is not a field of the scene (naming those it has)
solvers::RenderScene render_scene_of(const Scene& scene, const std::string& property = "");

/// The scene as JSON text (the page's data block): positions, faces and segments as
/// little-endian float32 / uint32 arrays in base64, field values as float32 in base64 with
/// their finite min / max as numbers.
std::string scene_json(const Scene& scene);

/// The directory of the three.js package (holding build/three.module.min.js and
/// examples/jsm/controls/OrbitControls.js): `hint` when not empty, else $IFEM_THREE_DIR, else
/// where scripts/setup.sh installs it in the build tree, else under the install prefix.
/// @throws IoError listing the places looked at, and how to install it
std::string find_three_js(const std::string& hint = "");

/// The self-contained page: the template with the scene and three.js (module text as data:
/// URLs behind an import map) inlined; it makes no network request.
/// @throws IoError if three.js cannot be read from three_dir
std::string view_page(const Scene& scene, const std::string& three_dir);

/// Writes view_page() to `path` atomically (path.tmp, then rename).
/// @throws IoError if it cannot be written
void write_view_page(const std::string& path, const Scene& scene, const std::string& three_dir);

}  // namespace ifem::recipes
