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

}  // namespace ifem::intrinsic
