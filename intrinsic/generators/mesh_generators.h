// Small mesh generators for tests, examples and benchmarks (scalable to millions of faces).
#pragma once

#include <vector>

#include "intrinsic/core/types.h"

namespace ifem::intrinsic {

/// A triangle mesh as plain arrays.
struct TriangleMesh {
  Positions positions;          ///< #V×3
  std::vector<Triangle> faces;  ///< #F, counter-clockwise seen from outside
};

/// Unit icosphere with every icosahedron edge cut into n segments: 20·n² faces, 10·n² + 2
/// vertices, all on the unit sphere. n = 224 gives 1,003,520 faces.
TriangleMesh icosphere(int n);

/// Unit sphere in latitude/longitude: n_lat rings, n_lon segments, a single vertex at each pole
/// (the fans there are needle triangles when n_lon ≫ n_lat). 2·n_lon·(n_lat − 1) faces.
TriangleMesh uv_sphere(int n_lat, int n_lon);

/// Flat grid on [0, width]×[0, height] (z = 0) with nx×ny cells, each split into two triangles
/// along alternating diagonals when `alternate` is true, else always along the same diagonal.
TriangleMesh grid(int nx, int ny, double width = 1.0, double height = 1.0, bool alternate = true);

/// Closed tube of radius `radius` around the (p, q) torus knot on the torus of radii 2 and 1
/// (centre line (2 + cos qs)·(cos ps, sin ps), sin qs, s ∈ [0, 2π)): n_along rings of n_around
/// vertices, 2·n_along·n_around faces, genus 1. With n_along small against the knot's length
/// over the ring spacing (e.g. 100 rings, 8 around, radius 0.1 on the (2, 3) knot: sides of
/// about 0.3 along and 0.08 around, alternating diagonals), the faces are slivers.
/// @throws InvalidInput unless n_along ≥ 3, n_around ≥ 3, radius > 0 and p, q ≥ 1 coprime
TriangleMesh torus_knot_tube(int n_along, int n_around, double radius = 0.1, int p = 2, int q = 3);

/// Regular tetrahedron inscribed in the unit sphere.
TriangleMesh tetrahedron();

/// What range_scan() puts into the scan.
struct RangeScanOptions {
  int nx = 100, ny = 100;   ///< sample grid cells (nx+1)×(ny+1) samples over [0,1]², each ≥ 4
  unsigned long seed = 1;   ///< every random choice below
  int objects = 40;         ///< discs standing out of (or sunk into) the background, ≥ 0
  double depth_jump = 0.5;  ///< depth step at a disc's rim (absolute, > 0; the grid step is 1/nx)
  /// Fraction of the discs whose rim is kept as a band of needle triangles spanning the depth
  /// jump (the others are cut out: separate components), in [0, 1].
  double rim_fraction = 0.3;
  int islands = 12;             ///< tiny components of one or two cells cut out of the grid, ≥ 0
  double dropout = 0.01;        ///< probability that a cell is missing (holes), in [0, 1)
  double half_cells = 0.01;     ///< probability that a cell keeps one triangle only, in [0, 1)
  double jitter = 0.25;         ///< sample displacement in the view plane, cells, in [0, 0.45]
  double depth_noise = 0.0005;  ///< random depth added per sample (absolute), ≥ 0
  /// @throws InvalidInput naming the field outside its range
  void validate() const;
};

/// A synthetic single-view range scan: a height field z(x, y) over a jittered grid seen along
/// z, a wavy background with disc-shaped objects at other depths. Cells across a disc's rim
/// are cut out (so that disc is its own component) or kept as needle triangles spanning the
/// depth jump (long and thin: rim_fraction of the discs); missing cells make holes and
/// vertices where two fans touch (nonmanifold vertices); islands are tiny components of a few
/// triangles. The faces are edge-manifold and oriented (normals towards +z), every face has
/// positive area, samples no face uses are dropped. Deterministic in the options (own random
/// generator, no std distributions). At most 2·nx·ny faces.
/// @throws InvalidInput on bad options (RangeScanOptions::validate())
TriangleMesh range_scan(const RangeScanOptions& options);

}  // namespace ifem::intrinsic
