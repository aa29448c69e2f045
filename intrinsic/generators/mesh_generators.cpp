#include "intrinsic/generators/mesh_generators.h"

#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <map>
#include <numeric>
#include <string>
#include <utility>

#include "intrinsic/core/errors.h"
#include "intrinsic/core/geometry.h"

namespace ifem::intrinsic {

void add_quad(std::vector<Triangle>& faces, Index a, Index b, Index c, Index d, bool along_ac) {
  if (along_ac) {
    faces.push_back({a, b, c});
    faces.push_back({a, c, d});
  } else {
    faces.push_back({a, b, d});
    faces.push_back({b, c, d});
  }
}

TriangleMesh icosphere(int n) {
  if (n < 1) throw InvalidInput("icosphere: n must be ≥ 1");
  const double p = (1.0 + std::sqrt(5.0)) / 2.0;
  const double base[12][3] = {{-1, p, 0}, {1, p, 0}, {-1, -p, 0}, {1, -p, 0},
                              {0, -1, p}, {0, 1, p}, {0, -1, -p}, {0, 1, -p},
                              {p, 0, -1}, {p, 0, 1}, {-p, 0, -1}, {-p, 0, 1}};
  const int ico[20][3] = {{0, 11, 5}, {0, 5, 1},  {0, 1, 7},   {0, 7, 10}, {0, 10, 11},
                          {1, 5, 9},  {5, 11, 4}, {11, 10, 2}, {10, 7, 6}, {7, 1, 8},
                          {3, 9, 4},  {3, 4, 2},  {3, 2, 6},   {3, 6, 8},  {3, 8, 9},
                          {4, 9, 5},  {2, 4, 11}, {6, 2, 10},  {8, 6, 7},  {9, 8, 1}};
  TriangleMesh mesh;
  const long nv = 10L * n * n + 2;
  mesh.positions.resize(nv, 3);
  Index next_vertex = 0;
  auto add = [&](const Eigen::RowVector3d& x) {
    mesh.positions.row(next_vertex) = x.normalized();
    return next_vertex++;
  };
  Eigen::RowVector3d corner[12];
  for (int i = 0; i < 12; ++i) {
    corner[i] = Eigen::RowVector3d(base[i][0], base[i][1], base[i][2]);
    add(corner[i]);
  }
  // edge-interior vertices: first id of edge (lo, hi), numbered from lo towards hi
  std::map<std::pair<int, int>, Index> edge_base;
  for (const auto& f : ico) {
    for (int s = 0; s < 3; ++s) {
      const int a = std::min(f[s], f[(s + 1) % 3]), b = std::max(f[s], f[(s + 1) % 3]);
      if (edge_base.count({a, b})) continue;
      edge_base[{a, b}] = next_vertex;
      for (int k = 1; k < n; ++k) add(corner[a] + (corner[b] - corner[a]) * (double(k) / n));
    }
  }
  mesh.faces.reserve(20L * n * n);
  std::vector<Index> lattice((n + 1) * (n + 1));
  for (const auto& f : ico) {
    // lattice point (i, j): weight i/n on f[1], j/n on f[2], the rest on f[0]
    auto on_edge = [&](int u, int v, int k) -> Index {  // k steps from u towards v
      if (k == 0) return u;
      if (k == n) return v;
      const Index b0 = edge_base[{std::min(u, v), std::max(u, v)}];
      return u < v ? b0 + k - 1 : b0 + (n - k) - 1;
    };
    for (int i = 0; i <= n; ++i) {
      for (int j = 0; i + j <= n; ++j) {
        Index id;
        if (j == 0)
          id = on_edge(f[0], f[1], i);
        else if (i == 0)
          id = on_edge(f[0], f[2], j);
        else if (i + j == n)
          id = on_edge(f[1], f[2], j);
        else
          id = add(corner[f[0]] + (corner[f[1]] - corner[f[0]]) * (double(i) / n) +
                   (corner[f[2]] - corner[f[0]]) * (double(j) / n));
        lattice[i * (n + 1) + j] = id;
      }
    }
    auto at = [&](int i, int j) { return lattice[i * (n + 1) + j]; };
    for (int i = 0; i < n; ++i) {
      for (int j = 0; i + j < n; ++j) {
        mesh.faces.push_back({at(i, j), at(i + 1, j), at(i, j + 1)});
        if (i + j + 1 < n) mesh.faces.push_back({at(i + 1, j), at(i + 1, j + 1), at(i, j + 1)});
      }
    }
  }
  return mesh;
}

TriangleMesh uv_sphere(int n_lat, int n_lon) {
  if (n_lat < 2 || n_lon < 3) throw InvalidInput("uv_sphere: need n_lat ≥ 2 and n_lon ≥ 3");
  TriangleMesh mesh;
  const Index nv = 2 + (n_lat - 1) * n_lon;
  mesh.positions.resize(nv, 3);
  mesh.positions.row(0) << 0, 0, 1;
  mesh.positions.row(nv - 1) << 0, 0, -1;
  auto ring = [&](int r, int k) { return 1 + (r - 1) * n_lon + (k % n_lon); };
  for (int r = 1; r < n_lat; ++r) {
    const double theta = kPi * r / n_lat;
    for (int k = 0; k < n_lon; ++k) {
      const double phi = 2.0 * kPi * k / n_lon;
      mesh.positions.row(ring(r, k)) << std::sin(theta) * std::cos(phi),
          std::sin(theta) * std::sin(phi), std::cos(theta);
    }
  }
  for (int k = 0; k < n_lon; ++k) {
    mesh.faces.push_back({0, ring(1, k), ring(1, k + 1)});
    mesh.faces.push_back({nv - 1, ring(n_lat - 1, k + 1), ring(n_lat - 1, k)});
  }
  for (int r = 1; r + 1 < n_lat; ++r) {
    for (int k = 0; k < n_lon; ++k) {
      mesh.faces.push_back({ring(r, k), ring(r + 1, k), ring(r + 1, k + 1)});
      mesh.faces.push_back({ring(r, k), ring(r + 1, k + 1), ring(r, k + 1)});
    }
  }
  return mesh;
}

TriangleMesh grid(int nx, int ny, double width, double height, bool alternate) {
  if (nx < 1 || ny < 1) throw InvalidInput("grid: need at least one cell in each direction");
  TriangleMesh mesh;
  mesh.positions.resize((nx + 1) * (ny + 1), 3);
  auto id = [&](int i, int j) { return j * (nx + 1) + i; };
  for (int j = 0; j <= ny; ++j) {
    for (int i = 0; i <= nx; ++i) {
      mesh.positions.row(id(i, j)) << width * i / nx, height * j / ny, 0.0;
    }
  }
  for (int j = 0; j < ny; ++j) {
    for (int i = 0; i < nx; ++i) {
      add_quad(mesh.faces, id(i, j), id(i + 1, j), id(i + 1, j + 1), id(i, j + 1),
               !alternate || (i + j) % 2 == 0);
    }
  }
  return mesh;
}

TriangleMesh book(int pages, int nx, int ny, double width, double height) {
  if (pages < 1 || nx < 1 || ny < 1 || !(width > 0.0) || !(height > 0.0)) {
    throw InvalidInput("book: need pages ≥ 1, nx ≥ 1, ny ≥ 1, width > 0 and height > 0");
  }
  TriangleMesh mesh;
  const Index column = ny + 1;
  mesh.positions.resize(column * (1 + Index(pages) * nx), 3);
  const auto id = [&](int p, int i, int j) -> Index {
    return i == 0 ? Index(j) : column + (Index(p) * nx + (i - 1)) * column + j;
  };
  const double two_pi = 2.0 * std::acos(-1.0);
  for (int p = 0; p < pages; ++p) {
    const double angle = two_pi * p / pages;
    for (int i = 0; i <= nx; ++i) {
      const double u = width * i / nx;
      for (int j = 0; j <= ny; ++j) {
        mesh.positions.row(id(p, i, j)) << u * std::cos(angle), u * std::sin(angle),
            height * j / ny;
      }
    }
    for (int i = 0; i < nx; ++i) {
      for (int j = 0; j < ny; ++j) {
        add_quad(mesh.faces, id(p, i, j), id(p, i + 1, j), id(p, i + 1, j + 1), id(p, i, j + 1),
                 (i + j) % 2 == 0);
      }
    }
  }
  return mesh;
}

TriangleMesh torus_knot_tube(int n_along, int n_around, double radius, int p, int q) {
  if (n_along < 3 || n_around < 3 || !(radius > 0.0) || p < 1 || q < 1 || std::gcd(p, q) != 1) {
    throw InvalidInput(
        "torus_knot_tube: need n_along ≥ 3, n_around ≥ 3, radius > 0 and coprime p, q ≥ 1");
  }
  const double two_pi = 2.0 * std::acos(-1.0);
  auto centre = [&](double s) {
    const double r = 2.0 + std::cos(q * s);
    return Eigen::Vector3d(r * std::cos(p * s), r * std::sin(p * s), std::sin(q * s));
  };
  TriangleMesh mesh;
  mesh.positions.resize(Index(n_along) * n_around, 3);
  for (int i = 0; i < n_along; ++i) {
    const double s = two_pi * i / n_along, ds = 1e-4;
    const Eigen::Vector3d c = centre(s);
    const Eigen::Vector3d tangent = (centre(s + ds) - centre(s - ds)).normalized();
    // the frame: the direction to the torus' core circle, made normal to the tangent
    Eigen::Vector3d n = Eigen::Vector3d(c.x(), c.y(), 0.0).normalized() * 2.0 - c;
    n = (n - n.dot(tangent) * tangent).normalized();
    const Eigen::Vector3d b = tangent.cross(n);
    for (int j = 0; j < n_around; ++j) {
      const double a = two_pi * j / n_around;
      mesh.positions.row(Index(i) * n_around + j) =
          c + radius * (std::cos(a) * n + std::sin(a) * b);
    }
  }
  auto id = [&](int i, int j) { return Index((i % n_along) * n_around + j % n_around); };
  for (int i = 0; i < n_along; ++i) {
    for (int j = 0; j < n_around; ++j) {
      const Index a = id(i, j), b = id(i + 1, j), c = id(i + 1, j + 1), d = id(i, j + 1);
      if ((i + j) % 2 == 0) {  // (b − a) × (d − a) points inwards: a, d, c and a, c, b
        mesh.faces.push_back({a, c, b});
        mesh.faces.push_back({a, d, c});
      } else {
        mesh.faces.push_back({a, d, b});
        mesh.faces.push_back({b, d, c});
      }
    }
  }
  return mesh;
}

TriangleMesh tetrahedron() {
  TriangleMesh mesh;
  mesh.positions.resize(4, 3);
  const double s = 1.0 / std::sqrt(3.0);
  mesh.positions << s, s, s, s, -s, -s, -s, s, -s, -s, -s, s;
  mesh.faces = {{0, 1, 2}, {0, 3, 1}, {0, 2, 3}, {1, 3, 2}};
  return mesh;
}

}  // namespace ifem::intrinsic

namespace ifem::intrinsic {
namespace {

// SplitMix64 (Steele, Lea & Flood 2014): a small deterministic generator, the same stream on
// every platform (std distributions are not).
class SplitMix {
 public:
  explicit SplitMix(unsigned long seed) : s_(0x9E3779B97F4A7C15ULL * (seed + 1)) {}
  std::uint64_t next() {
    std::uint64_t z = (s_ += 0x9E3779B97F4A7C15ULL);
    z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9ULL;
    z = (z ^ (z >> 27)) * 0x94D049BB133111EBULL;
    return z ^ (z >> 31);
  }
  double uniform() { return double(next() >> 11) * 0x1.0p-53; }  // [0, 1)
  int below(int n) { return static_cast<int>(uniform() * n); }   // [0, n)

 private:
  std::uint64_t s_;
};

struct ScanDisc {
  double cx, cy, r, dz;
  bool rim;  // keep the cells across its rim (needles) instead of cutting them out
};

// Cell states of range_scan()
constexpr char kCellKept = 0, kCellDropped = 1, kCellHalf = 2, kCellIsland = 3;

// Per cell: kept, dropped (dropout, cut rims, the moats around islands) or half.
std::vector<char> scan_cells(const RangeScanOptions& o, const std::vector<int>& label,
                             const std::vector<ScanDisc>& discs, SplitMix& rng) {
  const int nx = o.nx, ny = o.ny;
  auto sample = [&](int i, int j) { return j * (nx + 1) + i; };
  std::vector<char> cell(static_cast<std::size_t>(nx) * ny, kCellKept);
  for (int j = 0; j < ny; ++j) {
    for (int i = 0; i < nx; ++i) {
      const int l[4] = {label[sample(i, j)], label[sample(i + 1, j)], label[sample(i + 1, j + 1)],
                        label[sample(i, j + 1)]};
      bool mixed = false, cut = false;
      for (int k = 0; k < 4; ++k) {
        if (l[k] != l[0]) mixed = true;
        if (l[k] >= 0 && !discs[l[k]].rim) cut = true;
      }
      char& c = cell[j * nx + i];
      if (mixed && cut) c = kCellDropped;
      const double u = rng.uniform();
      if (u < o.dropout)
        c = kCellDropped;
      else if (u < o.dropout + o.half_cells && c == kCellKept)
        c = kCellHalf;
    }
  }
  // islands: a patch of 1×1 or 2×1 cells with a moat of dropped cells around it
  for (int k = 0; k < o.islands; ++k) {
    const int w = 1 + rng.below(2);
    const int i0 = 1 + rng.below(nx - w - 2), j0 = 1 + rng.below(ny - 3);
    for (int j = j0 - 1; j <= j0 + 1; ++j) {
      for (int i = i0 - 1; i <= i0 + w; ++i) {
        char& c = cell[j * nx + i];
        if (c == kCellIsland) continue;  // another island's patch stays
        c = (j == j0 && i >= i0 && i < i0 + w) ? kCellIsland : kCellDropped;
      }
    }
  }
  return cell;
}

}  // namespace

void RangeScanOptions::validate() const {
  auto bad = [](const std::string& what) { throw InvalidInput("range_scan: " + what); };
  if (nx < 4 || ny < 4) bad("nx and ny must be ≥ 4");
  if (objects < 0 || islands < 0) bad("objects and islands must be ≥ 0");
  if (!(depth_jump > 0.0) || !std::isfinite(depth_jump)) bad("depth_jump must be finite and > 0");
  if (!(rim_fraction >= 0.0 && rim_fraction <= 1.0)) bad("rim_fraction must be in [0, 1]");
  if (!(dropout >= 0.0 && dropout < 1.0)) bad("dropout must be in [0, 1)");
  if (!(half_cells >= 0.0 && half_cells < 1.0)) bad("half_cells must be in [0, 1)");
  if (!(jitter >= 0.0 && jitter <= 0.45)) bad("jitter must be in [0, 0.45]");
  if (!(depth_noise >= 0.0) || !std::isfinite(depth_noise)) bad("depth_noise must be ≥ 0");
}

TriangleMesh range_scan(const RangeScanOptions& o) {
  o.validate();
  SplitMix rng(o.seed);
  const int nx = o.nx, ny = o.ny;
  const double hx = 1.0 / nx, hy = 1.0 / ny;
  std::vector<ScanDisc> discs(o.objects);
  for (ScanDisc& d : discs) {
    d.cx = rng.uniform();
    d.cy = rng.uniform();
    d.r = std::max(1.5 * hx, 0.015 + 0.05 * rng.uniform());
    d.dz = (rng.uniform() < 0.7 ? 1.0 : -1.0) * o.depth_jump * (0.5 + rng.uniform());
    d.rim = rng.uniform() < o.rim_fraction;
  }
  const int ns = (nx + 1) * (ny + 1);
  Positions x(ns, 3);
  std::vector<int> label(ns, -1);  // the topmost disc a sample sees, −1: background
  for (int j = 0; j <= ny; ++j) {
    for (int i = 0; i <= nx; ++i) {
      const bool inner_x = i > 0 && i<nx, inner_y = j> 0 && j < ny;
      const double px = (i + (inner_x ? o.jitter * (2.0 * rng.uniform() - 1.0) : 0.0)) * hx;
      const double py = (j + (inner_y ? o.jitter * (2.0 * rng.uniform() - 1.0) : 0.0)) * hy;
      const int s = j * (nx + 1) + i;
      double z = 0.05 * std::sin(7.0 * px) * std::cos(5.0 * py);
      for (int k = 0; k < o.objects; ++k) {
        const ScanDisc& d = discs[k];
        if ((px - d.cx) * (px - d.cx) + (py - d.cy) * (py - d.cy) < d.r * d.r) label[s] = k;
      }
      if (label[s] >= 0) z += discs[label[s]].dz;
      z += o.depth_noise * (2.0 * rng.uniform() - 1.0);
      x.row(s) = Eigen::RowVector3d(px, py, z);
    }
  }
  const std::vector<char> cell = scan_cells(o, label, discs, rng);
  std::vector<Triangle> faces;
  faces.reserve(2 * cell.size());
  for (int j = 0; j < ny; ++j) {
    for (int i = 0; i < nx; ++i) {
      const char c = cell[j * nx + i];
      if (c == kCellDropped) continue;
      const Index a = j * (nx + 1) + i, b = a + 1, d = a + nx + 1, e = d + 1;  // e = (i+1, j+1)
      Triangle t[2];
      if ((i + j) % 2 == 0) {
        t[0] = {a, b, e};
        t[1] = {a, e, d};
      } else {
        t[0] = {a, b, d};
        t[1] = {b, e, d};
      }
      faces.push_back(t[0]);
      if (c != kCellHalf) faces.push_back(t[1]);
    }
  }
  // keep the samples the faces use, in order
  std::vector<Index> id(ns, kInvalidIndex);
  for (const Triangle& t : faces) {
    for (const Index v : t) id[v] = 0;
  }
  TriangleMesh mesh;
  Index n = 0;
  for (int s = 0; s < ns; ++s) {
    if (id[s] == 0) id[s] = n++;
  }
  mesh.positions.resize(n, 3);
  for (int s = 0; s < ns; ++s) {
    if (id[s] != kInvalidIndex) mesh.positions.row(id[s]) = x.row(s);
  }
  for (Triangle& t : faces) {
    for (Index& v : t) v = id[v];
  }
  mesh.faces = std::move(faces);
  return mesh;
}

}  // namespace ifem::intrinsic

namespace ifem::intrinsic {

TriangleMesh needle_fan(int n, double aspect) {
  if (n < 4 || !(aspect > 0.0 && aspect <= 1.0)) {
    throw InvalidInput("needle_fan: need n >= 4 and aspect in (0, 1], got n = " +
                       std::to_string(n) + ", aspect = " + std::to_string(aspect));
  }
  TriangleMesh m;
  m.positions.resize(n, 3);
  for (int i = 0; i < n; ++i) {
    const double a = 2.0 * kPi * i / n;
    m.positions.row(i) << std::cos(a), aspect * std::sin(a), 0.0;
  }
  for (int i = 1; i + 1 < n; ++i) m.faces.push_back({0, i, i + 1});
  return m;
}

TriangleMesh needle_soup(int components) {
  if (components < 1) {
    throw InvalidInput("needle_soup: need components >= 1, got " + std::to_string(components));
  }
  TriangleMesh m;
  const int k = 12;
  m.positions.resize(Index(components) * (k + 2), 3);
  Index row = 0;
  for (int c = 0; c < components; ++c) {
    const Index center = row;
    m.positions.row(row++) << 0.0, 0.0, 1e-3 * (c % 3);
    for (int i = 0; i <= k; ++i) {
      const double a = 2.0 * kPi * std::min(i, k - 1) / k;
      const double r = i % 2 ? 1.0 : 1e-4;  // alternating: needles
      m.positions.row(row++) << r * std::cos(a), r * std::sin(a), 0.0;
    }
    for (int i = 0; i < k; ++i) m.faces.push_back({center, center + 1 + i, center + 2 + i});
  }
  return m;
}

TriangleMesh nearly_coincident_grid(int n, int pairs, double gap, unsigned long seed) {
  if (n < 2 || pairs < 0 || pairs > 2 * n * n || !(gap > 0.0 && gap < 1.0)) {
    throw InvalidInput(
        "nearly_coincident_grid: need n >= 2, 0 <= pairs <= 2n^2 and gap in "
        "(0, 1), got n = " +
        std::to_string(n) + ", pairs = " + std::to_string(pairs) +
        ", gap = " + std::to_string(gap));
  }
  TriangleMesh m = grid(n, n);
  for (Index v = 0; v < m.positions.rows(); ++v) {
    m.positions(v, 2) = 0.1 * std::sin(3.0 * m.positions(v, 0)) * std::cos(2.0 * m.positions(v, 1));
  }
  SplitMix rng(seed);
  std::vector<char> split(m.faces.size(), 0);
  const std::size_t n_faces = m.faces.size();
  std::vector<Eigen::RowVector3d> added;
  for (int p = 0; p < pairs; ++p) {
    std::size_t f = static_cast<std::size_t>(rng.below(static_cast<int>(n_faces)));
    while (split[f]) f = (f + 1) % n_faces;
    split[f] = 1;
    const Triangle t = m.faces[f];
    const int k = rng.below(3);
    const Eigen::RowVector3d corner = m.positions.row(t[k]);
    const Eigen::RowVector3d centroid =
        (m.positions.row(t[0]) + m.positions.row(t[1]) + m.positions.row(t[2])) / 3.0;
    const Index v = m.positions.rows() + Index(added.size());
    added.push_back(corner + gap * (centroid - corner));
    m.faces[f] = {t[0], t[1], v};
    m.faces.push_back({t[1], t[2], v});
    m.faces.push_back({t[2], t[0], v});
  }
  const Index n0 = m.positions.rows();
  m.positions.conservativeResize(n0 + Index(added.size()), 3);
  for (std::size_t i = 0; i < added.size(); ++i) m.positions.row(n0 + Index(i)) = added[i];
  return m;
}

}  // namespace ifem::intrinsic
