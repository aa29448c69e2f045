#include "intrinsic/surface/tufted_cover.h"

#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <string>
#include <tuple>
#include <utility>

namespace ifem::intrinsic {
namespace {

// Builds the cover. `positions` may be null (length-only input); then faces around a
// nonmanifold edge are ordered combinatorially.
IntrinsicTriangulation build_cover(const std::vector<Triangle>& faces, Index nv,
                                   const Eigen::MatrixX3d& side, const Positions* positions,
                                   TuftedCoverReport* report, int input_multiplicity) {
  if (input_multiplicity < 1) throw InvalidInput("tufted_cover: input multiplicity must be ≥ 1");
  TuftedCoverReport rep;
  const Index nf_in = checked_index(faces.size(), "tufted_cover");
  rep.input_faces = nf_in;

  // ---- kept faces (a face that repeats a vertex has no surface: dropped, counted)
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
    if (t[0] == t[1] || t[1] == t[2] || t[2] == t[0]) {
      ++rep.dropped_faces;
      continue;
    }
    kept.push_back(f);
  }
  const Index nk = static_cast<Index>(kept.size());
  checked_index(6 * static_cast<std::size_t>(nk), "tufted_cover");

  // ---- cover faces: 2k = front (v0, v1, v2), 2k+1 = back (v0, v2, v1)
  // back side t runs along input side 2 − t, reversed
  const std::size_t nh = 6 * static_cast<std::size_t>(nk);
  std::vector<Index> tail(nh);
  std::vector<double> hlen(nh);
  std::vector<Triangle> kept_tri(nk);  // kept faces, compact (one indirection less per lookup)
#pragma omp parallel for schedule(static) if (nk > kParallelMin)
  for (Index k = 0; k < nk; ++k) {
    const Index f = kept[k];
    const Triangle& t = faces[f];
    kept_tri[k] = t;
    Index* ft = &tail[6 * static_cast<std::size_t>(k)];
    double* fl = &hlen[6 * static_cast<std::size_t>(k)];
    ft[0] = t[0], ft[1] = t[1], ft[2] = t[2];
    ft[3] = t[0], ft[4] = t[2], ft[5] = t[1];
    fl[0] = side(f, 0), fl[1] = side(f, 1), fl[2] = side(f, 2);
    fl[3] = side(f, 2), fl[4] = side(f, 1), fl[5] = side(f, 0);
  }

  // Input side x = 3k + s joins lo(x) < hi(x). Its "up" cover halfedge runs lo → hi, its
  // "down" one hi → lo; front halfedge 6k + s, back halfedge 6k + 3 + (2 − s).
  auto corner = [&](Index x, int d) {
    static constexpr int kMod3[5] = {0, 1, 2, 0, 1};
    return kept_tri[x / 3][kMod3[x % 3 + d]];
  };
  auto front = [](Index x) { return 6 * (x / 3) + x % 3; };
  auto back = [](Index x) { return 6 * (x / 3) + 3 + (2 - x % 3); };
  auto up = [&](Index x) { return corner(x, 0) < corner(x, 1) ? front(x) : back(x); };
  auto down = [&](Index x) { return corner(x, 0) < corner(x, 1) ? back(x) : front(x); };

  // ---- group sides by edge: counting sort by lo into 64-bit keys (hi << 32 | 2x + rising,
  // rising = corner order is lo → hi), then sort each (small) bucket by key, i.e. (hi, x)
  const Index ns = 3 * nk;
  std::vector<Index> start(static_cast<std::size_t>(nv) + 1, 0);
  for (Index k = 0; k < nk; ++k) {
    const Triangle& t = kept_tri[k];
    ++start[std::min(t[0], t[1]) + 1];
    ++start[std::min(t[1], t[2]) + 1];
    ++start[std::min(t[2], t[0]) + 1];
  }
  Index unreferenced = 0;
  for (Index v = 0; v < nv; ++v) start[v + 1] += start[v];
  std::vector<std::uint64_t> order(ns);
  {
    std::vector<char> referenced(nv, 0);
    std::vector<Index> fill(start.begin(), start.end() - 1);
    for (Index k = 0; k < nk; ++k) {
      const Triangle& t = kept_tri[k];
      referenced[t[0]] = referenced[t[1]] = referenced[t[2]] = 1;
      for (int s = 0; s < 3; ++s) {
        const Index a = t[s], b = t[s == 2 ? 0 : s + 1];
        const Index x = 3 * k + s;
        const std::uint32_t low = 2 * static_cast<std::uint32_t>(x) + (a < b ? 1u : 0u);
        order[fill[std::min(a, b)]++] = static_cast<std::uint64_t>(std::max(a, b)) << 32 | low;
      }
    }
    unreferenced = static_cast<Index>(std::count(referenced.begin(), referenced.end(), 0));
  }
  rep.unreferenced_vertices = unreferenced;
  std::vector<Index> twin(nh, kInvalidIndex);
  Index n_edges = 0, n_boundary = 0, n_nonmanifold = 0, max_per_edge = 0;
  Index first_nm_lo = kInvalidIndex, first_nm_hi = kInvalidIndex;

  // from a key's low word: the side id, and its up / down cover halfedges
  auto side_of = [](std::uint64_t key) { return static_cast<Index>((key & 0xffffffffu) >> 1); };
  auto up_k = [&](std::uint64_t key) {
    const Index x = side_of(key);
    return (key & 1u) ? front(x) : back(x);
  };
  auto down_k = [&](std::uint64_t key) {
    const Index x = side_of(key);
    return (key & 1u) ? back(x) : front(x);
  };
#pragma omp parallel if (ns > kParallelMin)
  {
    // per-thread scratch for the angular sort around a nonmanifold edge
    std::vector<std::tuple<double, Index, double, double, Index>> keyed;
    std::vector<Index> opps, sides;
#pragma omp for schedule(dynamic, 256) reduction(+ : n_edges, n_boundary, n_nonmanifold) \
    reduction(max : max_per_edge)
    for (Index v = 0; v < nv; ++v) {
      std::uint64_t* b = order.data() + start[v];
      std::uint64_t* e = order.data() + start[v + 1];
      if (e - b > 1) std::sort(b, e);
      for (std::uint64_t* ki = b; ki < e;) {
        std::uint64_t* kj = ki + 1;
        const std::uint64_t edge_key = *ki >> 32;
        while (kj < e && (*kj >> 32) == edge_key) ++kj;
        const Index n = static_cast<Index>(kj - ki);
        const Index h_hi = static_cast<Index>(edge_key);
        ++n_edges;
        max_per_edge = std::max(max_per_edge, n);
        if (n == 1) {
          ++n_boundary;
          twin[up_k(ki[0])] = down_k(ki[0]);
          twin[down_k(ki[0])] = up_k(ki[0]);
        } else if (n == 2) {
          twin[up_k(ki[0])] = down_k(ki[1]);
          twin[down_k(ki[1])] = up_k(ki[0]);
          twin[up_k(ki[1])] = down_k(ki[0]);
          twin[down_k(ki[0])] = up_k(ki[1]);
        } else {
          // side ids of this edge, increasing
          sides.resize(n);
          for (Index m = 0; m < n; ++m) sides[m] = side_of(ki[m]);
          Index* i = sides.data();
          Index* j = i + n;
          ++n_nonmanifold;
#pragma omp critical(ifem_tufted_first_nm)
          if (first_nm_lo == kInvalidIndex || v < first_nm_lo ||
              (v == first_nm_lo && h_hi < first_nm_hi)) {
            first_nm_lo = v;
            first_nm_hi = h_hi;
          }
          // canonical cyclic order: angle of the opposite vertex about the axis lo → hi,
          // measured from the opposite vertex with the smallest id; then opposite id, then
          // the lengths of the other two sides (length-only input), then the side id
          keyed.clear();
          for (Index* k = i; k < j; ++k) {
            const Index x = *k;
            const Index opp = corner(x, 2);
            const Index f = kept[x / 3];
            const int s = x % 3;
            // other two sides, in the direction lo → hi → opp → lo
            double l_ho = side(f, (s + 1) % 3), l_ol = side(f, (s + 2) % 3);
            if (corner(x, 0) != v) std::swap(l_ho, l_ol);
            keyed.emplace_back(0.0, opp, l_ho, l_ol, x);
          }
          if (positions) {
            const Eigen::Vector3d pa = positions->row(v).transpose();
            Eigen::Vector3d u = positions->row(h_hi).transpose() - pa;
            const double ul = u.norm();
            if (ul > 0.0 && std::isfinite(ul)) {
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
              if (r.squaredNorm() > 0.0) {
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
            }
          }
          std::sort(keyed.begin(), keyed.end());
          for (Index k = 0; k < n; ++k) {
            const Index x = std::get<4>(keyed[k]);
            const Index y = std::get<4>(keyed[(k + 1) % n]);
            twin[up(x)] = down(y);
            twin[down(y)] = up(x);
          }
        }
        ki = kj;
      }
    }
  }
  rep.edges = n_edges;
  rep.boundary_edges = n_boundary;
  rep.nonmanifold_edges = n_nonmanifold;
  rep.max_faces_per_edge = max_per_edge;
  rep.first_nonmanifold_edge[0] = first_nm_lo;
  rep.first_nonmanifold_edge[1] = first_nm_hi;

  IntrinsicTriangulation tri = IntrinsicTriangulation::from_gluing(
      std::move(tail), std::move(twin), hlen, nv, 2 * input_multiplicity);
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
#pragma omp parallel for schedule(static) if (nf > kParallelMin)
  for (Index f = 0; f < nf; ++f) {
    for (int s = 0; s < 3; ++s) {
      const Index a = faces[f][s], b = faces[f][(s + 1) % 3];
      if (a < 0 || a >= nv || b < 0 || b >= nv) {
        side(f, s) = -1.0;  // reported with the face id by build_cover
        continue;
      }
      const double* pa = xyz + 3 * static_cast<std::size_t>(a);
      const double* pb = xyz + 3 * static_cast<std::size_t>(b);
      const double dx = pa[0] - pb[0], dy = pa[1] - pb[1], dz = pa[2] - pb[2];
      double l = std::sqrt(dx * dx + dy * dy + dz * dz);
      if (!std::isfinite(l)) {  // huge coordinates: avoid overflow in x²
        l = (positions.row(a) - positions.row(b)).stableNorm();
      }
      side(f, s) = l;
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
