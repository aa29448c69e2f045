#include "intrinsic/surface/tufted_cover.h"

#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <string>
#include <tuple>
#include <utility>

#include "intrinsic/core/geometry.h"
#include "intrinsic/core/side_pairs.h"
#include "intrinsic/core/types.h"

namespace ifem::intrinsic {
namespace {

// The input faces the cover keeps (a face that repeats a vertex has no surface: dropped,
// counted in rep). Checks ids and lengths.
std::vector<Index> kept_faces(const std::vector<Triangle>& faces, Index nv,
                              const Eigen::MatrixX3d& side, TuftedCoverReport& rep) {
  const Index nf_in = rep.input_faces;
  std::vector<Index> kept;
  kept.reserve(faces.size());
  for (Index f = 0; f < nf_in; ++f) {
    const Triangle& t = faces[f];
    for (int s = 0; s < 3; ++s) {
      if (t[s] < 0 || t[s] >= nv) {
        throw InvalidInput("tufted_cover: face " + std::to_string(f) + " has vertex index " +
                           std::to_string(t[s]) + " out of range [0, " + std::to_string(nv) + ")");
      }
    }
    for (int s = 0; s < 3; ++s) {
      const double l = side(f, s);
      if (!std::isfinite(l) || l < 0.0) {
        throw InvalidInput("tufted_cover: face " + std::to_string(f) + " side " +
                           std::to_string(s) + " has invalid length " + std::to_string(l));
      }
    }
    if (repeats_vertex(t)) {
      ++rep.dropped_faces;
      continue;
    }
    kept.push_back(f);
  }
  return kept;
}

// The cover's faces before gluing: 2k = front (v0, v1, v2), 2k+1 = back (v0, v2, v1) of kept
// face k; back side t runs along input side 2 − t, reversed.
struct CoverFaces {
  std::vector<Index> tail;         // 6 per kept face
  std::vector<double> hlen;        // 6 per kept face
  std::vector<Triangle> kept_tri;  // kept faces, compact (one indirection less per lookup)
};

CoverFaces cover_faces(const std::vector<Triangle>& faces, const std::vector<Index>& kept,
                       const Eigen::MatrixX3d& side) {
  const Index nk = static_cast<Index>(kept.size());
  const std::size_t nh = 6 * static_cast<std::size_t>(nk);
  CoverFaces c;
  c.tail.resize(nh);
  c.hlen.resize(nh);
  c.kept_tri.resize(nk);
#pragma omp parallel for schedule(static) if (nk >= kParallelMin)
  for (Index k = 0; k < nk; ++k) {
    const Index f = kept[k];
    const Triangle& t = faces[f];
    c.kept_tri[k] = t;
    Index* ft = &c.tail[6 * static_cast<std::size_t>(k)];
    double* fl = &c.hlen[6 * static_cast<std::size_t>(k)];
    ft[0] = t[0], ft[1] = t[1], ft[2] = t[2];
    ft[3] = t[0], ft[4] = t[2], ft[5] = t[1];
    fl[0] = side(f, 0), fl[1] = side(f, 1), fl[2] = side(f, 2);
    fl[3] = side(f, 2), fl[4] = side(f, 1), fl[5] = side(f, 0);
  }
  return c;
}

// Input side x = 3k + s of kept face k joins lo(x) < hi(x). Its "up" cover halfedge runs
// lo → hi, its "down" one hi → lo; front halfedge 6k + s, back halfedge 6k + 3 + (2 − s).
struct CoverSides {
  const std::vector<Triangle>& kept_tri;
  Index corner(Index x, int d) const {
    static constexpr int kMod3[5] = {0, 1, 2, 0, 1};
    return kept_tri[x / 3][kMod3[x % 3 + d]];
  }
  static Index front(Index x) { return 6 * (x / 3) + x % 3; }
  static Index back(Index x) { return 6 * (x / 3) + 3 + (2 - x % 3); }
  Index up(Index x) const { return corner(x, 0) < corner(x, 1) ? front(x) : back(x); }
  Index down(Index x) const { return corner(x, 0) < corner(x, 1) ? back(x) : front(x); }
};

// Sorts the sides of a nonmanifold edge lo–hi into the canonical cyclic order: angle of the
// opposite vertex about the axis lo → hi, measured from the opposite vertex with the smallest id
// (only with positions); then opposite id, then the lengths of the other two sides
// (length-only input), then the side id. `keyed` and `opps` are scratch; returns the side ids.
struct EdgeFanSorter {
  const CoverSides& sides;
  const std::vector<Index>& kept;
  const Eigen::MatrixX3d& side;
  const Positions* positions;
  std::vector<std::tuple<double, Index, double, double, Index>> keyed;
  std::vector<Index> opps;

  void sort(Index lo, Index hi, const Index* x_begin, Index n) {
    keyed.clear();
    for (const Index* k = x_begin; k < x_begin + n; ++k) {
      const Index x = *k;
      const Index f = kept[x / 3];
      const int s = x % 3;
      // other two sides, in the direction lo → hi → opp → lo
      double l_ho = side(f, (s + 1) % 3), l_ol = side(f, (s + 2) % 3);
      if (sides.corner(x, 0) != lo) std::swap(l_ho, l_ol);
      keyed.emplace_back(0.0, sides.corner(x, 2), l_ho, l_ol, x);
    }
    if (positions) set_angles(lo, hi);
    std::sort(keyed.begin(), keyed.end());
  }
  Index sorted_side(Index k) const { return std::get<4>(keyed[k]); }

 private:
  // the angle keys: pseudo-angles of the opposite vertices about the axis lo → hi
  void set_angles(Index lo, Index hi) {
    const Eigen::Vector3d pa = positions->row(lo).transpose();
    Eigen::Vector3d u = positions->row(hi).transpose() - pa;
    const double ul = u.norm();
    if (!(ul > 0.0 && std::isfinite(ul))) return;
    u /= ul;
    auto perp = [&](Index c) {
      const Eigen::Vector3d w = positions->row(c).transpose() - pa;
      return Eigen::Vector3d(w - w.dot(u) * u);
    };
    // reference: the first opposite vertex (by id) off the axis
    opps.clear();
    for (const auto& kt : keyed) opps.push_back(std::get<1>(kt));
    std::sort(opps.begin(), opps.end());
    Eigen::Vector3d r = Eigen::Vector3d::Zero();
    for (const Index c : opps) {
      const Eigen::Vector3d w = perp(c);
      const double wl = w.norm();
      if (wl > 1e-14 * ul) {
        r = w / wl;
        break;
      }
    }
    if (!(r.squaredNorm() > 0.0)) return;
    const Eigen::Vector3d r2 = u.cross(r);
    for (auto& kt : keyed) {
      const Eigen::Vector3d w = perp(std::get<1>(kt));
      // pseudo-angle in [0, 4): increasing with the angle from r towards r2
      // (same order as atan2 in [0, 2π), without the transcendental call)
      const double x = w.dot(r), y = w.dot(r2);
      const double l1 = std::abs(x) + std::abs(y);
      double th = 0.0;
      if (l1 > 0.0) th = y >= 0.0 ? 1.0 - x / l1 : 3.0 + x / l1;
      std::get<0>(kt) = th;
    }
  }
};

// Glues the cover halfedges of every input edge (a group of sides): one side zips its front
// and back copies, two are glued crosswise, 3+ cyclically in the fan order. Fills the edge
// counts of rep.
std::vector<Index> glue_cover(const SideGroups& groups, const CoverSides& sides,
                              const std::vector<Index>& kept, const Eigen::MatrixX3d& side,
                              const Positions* positions, std::size_t nh, TuftedCoverReport& rep) {
  std::vector<Index> twin(nh, kInvalidIndex);
  auto glue = [&](Index up_side, Index down_side) {
    twin[sides.up(up_side)] = sides.down(down_side);
    twin[sides.down(down_side)] = sides.up(up_side);
  };
  const Index ng = groups.n_groups();
  Index n_boundary = 0, n_nonmanifold = 0, max_per_edge = 0;
#pragma omp parallel if (ng >= kParallelMin)
  {
    EdgeFanSorter fan{sides, kept, side, positions, {}, {}};  // per-thread scratch
#pragma omp for schedule(dynamic, 256) reduction(+ : n_boundary, n_nonmanifold) \
    reduction(max : max_per_edge)
    for (Index g = 0; g < ng; ++g) {
      const Index n = groups.size(g);
      const Index* x = groups.begin(g);
      max_per_edge = std::max(max_per_edge, n);
      if (n == 1) {
        ++n_boundary;
        glue(x[0], x[0]);
      } else if (n == 2) {
        glue(x[0], x[1]);
        glue(x[1], x[0]);
      } else {
        ++n_nonmanifold;
        fan.sort(groups.lo[g], groups.hi[g], x, n);
        for (Index k = 0; k < n; ++k) glue(fan.sorted_side(k), fan.sorted_side((k + 1) % n));
      }
    }
  }
  rep.edges = ng;
  rep.boundary_edges = n_boundary;
  rep.nonmanifold_edges = n_nonmanifold;
  rep.max_faces_per_edge = max_per_edge;
  for (Index g = 0; g < ng; ++g) {  // groups are in (lo, hi) order: the first is the smallest
    if (groups.size(g) > 2) {
      rep.first_nonmanifold_edge[0] = groups.lo[g];
      rep.first_nonmanifold_edge[1] = groups.hi[g];
      break;
    }
  }
  return twin;
}

Index count_unreferenced(const std::vector<Triangle>& kept_tri, Index nv) {
  std::vector<char> referenced(nv, 0);
  for (const Triangle& t : kept_tri) referenced[t[0]] = referenced[t[1]] = referenced[t[2]] = 1;
  return static_cast<Index>(std::count(referenced.begin(), referenced.end(), 0));
}

// Builds the cover. `positions` may be null (length-only input); then faces around a
// nonmanifold edge are ordered combinatorially.
IntrinsicTriangulation build_cover(const std::vector<Triangle>& faces, Index nv,
                                   const Eigen::MatrixX3d& side, const Positions* positions,
                                   TuftedCoverReport* report, int input_multiplicity) {
  if (input_multiplicity < 1) throw InvalidInput("tufted_cover: input multiplicity must be ≥ 1");
  TuftedCoverReport rep;
  rep.input_faces = checked_index(faces.size(), "tufted_cover");
  const std::vector<Index> kept = kept_faces(faces, nv, side, rep);
  const Index nk = static_cast<Index>(kept.size());
  checked_index(6 * static_cast<std::size_t>(nk), "tufted_cover");
  CoverFaces cover = cover_faces(faces, kept, side);
  rep.unreferenced_vertices = count_unreferenced(cover.kept_tri, nv);
  const SideGroups groups = group_sides(cover.kept_tri, nv);
  const CoverSides sides{cover.kept_tri};
  std::vector<Index> twin =
      glue_cover(groups, sides, kept, side, positions, cover.tail.size(), rep);

  IntrinsicTriangulation tri = IntrinsicTriangulation::from_gluing(
      std::move(cover.tail), std::move(twin), cover.hlen, nv, 2 * input_multiplicity);
  if (report) {
    rep.parent_face.resize(2 * static_cast<std::size_t>(nk));
    for (Index k = 0; k < nk; ++k) rep.parent_face[2 * k] = rep.parent_face[2 * k + 1] = kept[k];
    *report = std::move(rep);
  }
  return tri;
}

}  // namespace

IntrinsicTriangulation tufted_cover(const std::vector<Triangle>& faces, const Positions& positions,
                                    TuftedCoverReport* report, int input_multiplicity) {
  const Index nv = checked_index(static_cast<std::size_t>(positions.rows()), "tufted_cover");
  for (Index v = 0; v < nv; ++v) {
    if (!positions.row(v).allFinite()) {
      throw InvalidInput("tufted_cover: vertex " + std::to_string(v) +
                         " has a non-finite coordinate");
    }
  }
  const Index nf = checked_index(faces.size(), "tufted_cover");
  Eigen::MatrixX3d side(nf, 3);
  static_assert(Positions::IsRowMajor, "rows of Positions are contiguous xyz triples");
  const double* xyz = positions.data();
#pragma omp parallel for schedule(static) if (nf >= kParallelMin)
  for (Index f = 0; f < nf; ++f) {
    for (int s = 0; s < 3; ++s) {
      const Index a = faces[f][s], b = faces[f][(s + 1) % 3];
      if (a < 0 || a >= nv || b < 0 || b >= nv) {
        side(f, s) = -1.0;  // reported with the face id by build_cover
        continue;
      }
      side(f, s) =
          side_length(xyz + 3 * static_cast<std::size_t>(a), xyz + 3 * static_cast<std::size_t>(b));
    }
  }
  return build_cover(faces, nv, side, &positions, report, input_multiplicity);
}

IntrinsicTriangulation tufted_cover(const std::vector<Triangle>& faces, Index n_vertices,
                                    const Eigen::MatrixX3d& side_lengths, TuftedCoverReport* report,
                                    int input_multiplicity) {
  if (n_vertices < 0) throw InvalidInput("tufted_cover: negative vertex count");
  if (side_lengths.rows() != static_cast<Eigen::Index>(faces.size())) {
    throw InvalidInput("tufted_cover: " + std::to_string(side_lengths.rows()) +
                       " rows of side lengths for " + std::to_string(faces.size()) + " faces");
  }
  return build_cover(faces, n_vertices, side_lengths, nullptr, report, input_multiplicity);
}

}  // namespace ifem::intrinsic
