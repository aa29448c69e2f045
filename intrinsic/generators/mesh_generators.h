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

/// Appends the two triangles of the quad a → b → c → d (counter-clockwise): split along the
/// diagonal a–c, {a, b, c} and {a, c, d}, when `along_ac`; else along b–d, {a, b, d} and
/// {b, c, d}. The grids here alternate the diagonal by cell parity.
void add_quad(std::vector<Triangle>& faces, Index a, Index b, Index c, Index d, bool along_ac);

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

/// A flat ellipse (semi-axes 1 and `aspect`, z = 0) with n boundary vertices, fanned from
/// vertex 0: n − 2 faces, nearly all needles (long and thin), a strongly non-Delaunay input.
/// @throws InvalidInput unless n ≥ 4 and 0 < aspect ≤ 1
TriangleMesh needle_fan(int n, double aspect = 0.08);

/// `components` separate fans (not welded) stacked on each other: each a centre vertex (at
/// height 1e-3·(c mod 3)) with 13 rim vertices in the plane z = 0 alternating between radius 1
/// and 1e-4 (needles), the last two rim vertices at the same angle, 12 faces per fan. Rim
/// vertices of different components coincide exactly.
/// @throws InvalidInput unless components ≥ 1
TriangleMesh needle_soup(int components);

/// A wavy grid of n×n cells over [0,1]² (alternating diagonals, z = 0.1·sin(3x)·cos(2y)) in
/// which `pairs` triangles, chosen at random (seed), are each split into three at a point at
/// relative distance `gap` from one of their corners (towards the centroid): a vertex nearly
/// coincident with an input vertex, two faces with a side of length about gap·h and the third
/// a needle of about that width. Edge-manifold, orientable, one component with boundary.
/// @throws InvalidInput unless n ≥ 2, 0 ≤ pairs ≤ 2n², 0 < gap < 1
TriangleMesh nearly_coincident_grid(int n, int pairs, double gap, unsigned long seed = 1);

/// A nonmanifold "book": `pages` flat rectangular pages of `width` × `height` sharing their
/// spine, the segment from (0, 0, 0) to (0, 0, height) on the z axis; page p lies in the
/// half-plane at angle 2π·p/pages about z (the point at distance u from the spine and height
/// z is (u·cos θ_p, u·sin θ_p, z)). Each page is an nx×ny grid of cells (nx across, ny up the
/// spine), split along alternating diagonals. Vertices: the ny + 1 spine vertices first (vertex
/// j at height height·j/ny), then page by page the columns i = 1..nx, each j = 0..ny: vertex
/// (ny + 1) + p·nx·(ny + 1) + (i − 1)·(ny + 1) + j. The ny spine edges have `pages` faces each
/// (nonmanifold from 3 pages on). Two points on different pages are joined on the book by the
/// straight line of the two pages unfolded into one plane: √((u₁ + u₂)² + (z₁ − z₂)²).
/// @throws InvalidInput unless pages ≥ 1, nx, ny ≥ 1, width, height > 0
TriangleMesh book(int pages, int nx, int ny, double width = 1.0, double height = 1.0);

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
