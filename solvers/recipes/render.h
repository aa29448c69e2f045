// Headless pictures of a result: a small software rasterizer (z-buffer, per-vertex field through
// a colour map, Lambert shading, isolines, wireframe and curves as lines) writing PNG through
// zlib. No GPU, display or browser; the same input and options give the same bytes
// (docs/decisions.md D-156).
#pragma once

#include <Eigen/Core>
#include <array>
#include <cstdint>
#include <limits>
#include <string>
#include <vector>

#include "intrinsic/core/types.h"
#include "intrinsic/io/surface_input.h"

namespace ifem::solvers {

/// What a picture shows: a mesh (or, without faces, a point cloud drawn as points), at most
/// one per-vertex scalar field, polylines (curves on the surface, geodesic paths), intrinsic
/// edges and field glyphs. recipes::render_scene_of() makes one from `ifem view`'s Scene.
struct RenderScene {
  Positions positions;              ///< #V×3
  std::vector<Triangle> triangles;  ///< #F, ids < #V; empty: the vertices are drawn as points
  Eigen::VectorXd field;            ///< #V values (non-finite ones drawn grey), or empty: no field
  std::string field_name;           ///< shown in messages only
  std::vector<std::vector<Eigen::Vector3d>> curves;  ///< polylines, each ≥ 2 points
  /// An intrinsic triangulation's edges traced over the surface, one polyline each (≥ 2
  /// points), drawn in RenderOptions::intrinsic_color under the curves.
  std::vector<std::vector<Eigen::Vector3d>> intrinsic_edges;
  /// Tangent-field glyphs, one segment (2 points) each, drawn as thin dark lines.
  std::vector<std::array<Eigen::Vector3d, 2>> glyphs;

  /// @throws InvalidInput on a face id out of range, a field of the wrong length, a non-finite
  ///   position, curve, intrinsic edge or glyph point, an empty scene
  void validate() const;
};

/// Colour maps (tables of this project, linear between knots):
///  - kViridis: perceptual, dark violet (low) → blue → green → yellow (high), luminance rising
///  - kDiverging: blue (low) → light grey (middle) → red (high); its default range is symmetric
///    about 0, [−m, m] with m = max |value|, for signed fields (eigenfunctions)
///  - kGray: black → white
enum class ColorMap { kViridis, kDiverging, kGray };

/// Camera and drawing settings.
///
/// Camera: orthographic, looking at the centre of the scene's bounding box from the direction
/// d = (cos e sin a, sin e, cos e cos a) (a = azimuth, e = elevation, degrees). The image's right
/// is (cos a, 0, −sin a), its up d × right: +y is up in side views. Named views: front (0, 0),
/// camera on +z; right (90, 0), on +x; back (180, 0); left (−90, 0); top (0, 90), on +y with −z
/// up in the image; bottom (0, −90), +z up. Framing: the sphere around the box's centre through
/// the scene's farthest point has the image radius `fill` · min(W', H) / 2, whatever the view,
/// centred in the W' columns of the scene area (W' = W, or W less the legend's columns).
///
/// Colour: value t = (v − lo) / (hi − lo) clamped to [0, 1] through the colour map, times the
/// shade ambient + (1 − ambient) |n · l| (n the interpolated vertex normal, l the light: from
/// the camera, a little up and to the left; both sides of a face lit alike). Without a field the
/// surface is light grey. Isolines: `isolines` = N levels lo + k (hi − lo) / (N + 1), k = 1..N,
/// as dark lines traced across each face (N lines, N + 1 bands).
struct RenderOptions {
  int width = 800;             ///< pixels, [1, 16384]
  int height = 600;            ///< pixels, [1, 16384]
  double azimuth_deg = 0.0;    ///< any finite value
  double elevation_deg = 0.0;  ///< [−90, 90]
  double fill = 0.9;           ///< (0, 10]: the scene's bounding sphere over half the image
  ColorMap colormap = ColorMap::kViridis;
  /// The colour map's range [lo, hi]; NaN (default): the field's finite min / max (kDiverging:
  /// ±max |value|). lo < hi when both are given.
  double range_lo = std::numeric_limits<double>::quiet_NaN();
  double range_hi = std::numeric_limits<double>::quiet_NaN();
  int isolines = 0;          ///< [0, 1000] isolines of the field (needs a field when > 0)
  bool wireframe = false;    ///< the mesh's edges as thin dark lines
  double line_width = 1.0;   ///< isolines and wireframe, output pixels, (0, 64]
  double curve_width = 3.0;  ///< curves, output pixels, (0, 64]
  double point_size = 3.0;   ///< a point cloud's points, output pixels, (0, 64]
  /// Anti-aliasing: the picture is drawn at S× the size and box-filtered down, S in [1, 4].
  int supersample = 2;
  std::array<std::uint8_t, 3> background = {255, 255, 255};
  std::array<std::uint8_t, 3> curve_color = {220, 30, 30};
  std::array<std::uint8_t, 3> intrinsic_color = {20, 70, 210};  ///< the intrinsic edges
  double intrinsic_width = 1.5;  ///< the intrinsic edges, output pixels, (0, 64]
  double ambient = 0.3;          ///< [0, 1]
  /// A colour bar at the right edge (high end at the top, a tick per isoline, lo and hi written
  /// beside it); the scene is framed in the columns left of it. Needs a field.
  bool legend = false;

  /// @throws InvalidInput naming the option and its allowed range
  void validate() const;
};

/// An RGB picture, 8 bits per channel.
struct Image {
  int width = 0;
  int height = 0;
  std::vector<std::uint8_t> rgb;  ///< width · height · 3 bytes, rows top to bottom
  /// The pixel in column x (< width) of row y (< height), rows counted from the top.
  std::array<std::uint8_t, 3> pixel(int x, int y) const;
};

/// The picture, and the colour map's range used (lo, hi; NaN without a field).
struct Rendering {
  Image image;
  double range_lo = 0.0;
  double range_hi = 0.0;
  int scene_width = 0;  ///< columns framing the scene: the width, less the legend's when drawn
};

/// Draws the scene. Deterministic: the same scene and options give the same pixels.
/// @throws InvalidInput from scene.validate() / options.validate(), for isolines or a legend
///   without a field, and for a legend that leaves the scene less than a quarter of the height
Rendering render_scene(const RenderScene& scene, const RenderOptions& options);

/// The camera direction (azimuth, elevation) in degrees of a named view: front back left right
/// top bottom. @throws InvalidInput on another name, listing the names
std::array<double, 2> named_view(const std::string& name);

/// "viridis", "diverging", "gray". @throws InvalidInput on another name, listing the names
ColorMap colormap_from_name(const std::string& name);

/// The colour map's colour at t (clamped to [0, 1]), unshaded.
std::array<std::uint8_t, 3> colormap_color(ColorMap map, double t);

/// The polylines of an OBJ file's 'v' and 'l' lines (what --curves-out and `ifem geodesic -o`
/// write; negative ids count back from the last 'v'), each ≥ 2 points. Other lines are ignored.
/// @throws IoError on a missing file, a malformed 'v' or 'l' line, an id out of range (FILE:line)
std::vector<std::vector<Eigen::Vector3d>> read_polylines_obj(const std::string& path);

/// The polylines of a PLY line set: 'vertex' (x, y, z) and 'edge' (vertex1, vertex2, 0-based)
/// elements, ASCII or binary (what `ifem refine --lines` writes: the intrinsic edges traced over
/// the input). Consecutive edges that share an end form one polyline; other elements are
/// skipped (binary: when they have no list property).
/// @throws IoError on a missing or malformed file, an id out of range
std::vector<std::vector<Eigen::Vector3d>> read_polylines_ply(const std::string& path);

/// read_polylines_obj() or read_polylines_ply() by the extension (.obj / .ply, any case).
/// @throws IoError as those, and on another extension
std::vector<std::vector<Eigen::Vector3d>> read_polylines(const std::string& path);

/// The PNG file of an image (8-bit RGB, no interlace, every row filter 0, zlib level 6).
std::vector<std::uint8_t> encode_png(const Image& image);

/// Writes encode_png() to `path` atomically (path.tmp, then rename).
/// @throws IoError if it cannot be written
void write_png(const std::string& path, const Image& image);

}  // namespace ifem::solvers
