#include "fem/prolongation.h"

#include <cmath>
#include <complex>
#include <string>
#include <vector>

#include "intrinsic/core/triangle_formulas.h"

namespace ifem::fem {

SparseMatrix prolongation(const intrinsic::Simplification& s) {
  const Index n_fine = Index(s.fine_in_coarse.size());
  const Index n_coarse = s.coarse.n_vertices();
  std::vector<Index> fine_to_coarse(n_fine, kInvalidIndex);
  for (Index c = 0; c < Index(s.coarse_to_fine.size()); ++c) {
    const Index v = s.coarse_to_fine[c];
    if (v < 0 || v >= n_fine) {
      throw InvalidInput("prolongation: coarse_to_fine[" + std::to_string(c) +
                         "] = " + std::to_string(v) + " is not a fine vertex");
    }
    fine_to_coarse[v] = c;
  }
  std::vector<Eigen::Triplet<double, int>> entries;
  entries.reserve(3 * std::size_t(n_fine));
  for (Index i = 0; i < n_fine; ++i) {
    const intrinsic::SurfacePoint& p = s.fine_in_coarse[i];
    if (p.face == kInvalidIndex) {
      if (fine_to_coarse[i] == kInvalidIndex) {
        throw InvalidInput("prolongation: fine vertex " + std::to_string(i) +
                           " has neither a coarse face nor a coarse copy");
      }
      entries.emplace_back(i, fine_to_coarse[i], 1.0);
      continue;
    }
    if (p.face < 0 || p.face >= s.coarse.n_faces()) {
      throw InvalidInput("prolongation: fine vertex " + std::to_string(i) + " names face " +
                         std::to_string(p.face) + " of a coarse mesh with " +
                         std::to_string(s.coarse.n_faces()) + " faces");
    }
    for (int k = 0; k < 3; ++k) {
      if (p.bary[k] != 0.0) entries.emplace_back(i, s.coarse.tail(3 * p.face + k), p.bary[k]);
    }
  }
  SparseMatrix P(n_fine, n_coarse);
  P.setFromTriplets(entries.begin(), entries.end());  // repeated corners (Δ-complex) add up
  return P;
}

}  // namespace ifem::fem

namespace ifem::fem {

namespace {

using T = intrinsic::IntrinsicTriangulation;

// A coarse face's planar layout: corner k at p[k], corner 0 at the origin, side 0 on the x axis.
struct FaceLayout {
  Eigen::Vector2d p[3];
};

FaceLayout layout_of(const T& c, Index f) {
  FaceLayout L;
  intrinsic::face_layout(c, f, L.p);
  return L;
}

// The position of surface point q (face g, barycentric) in the layout of face f: directly when
// g == f; a corner of g that is a corner of f; g unfolded across a side it shares with f.
// False when q is in none of these.
bool place_in(const T& c, Index f, const FaceLayout& L, const intrinsic::SurfacePoint& q,
              Eigen::Vector2d& out) {
  const Index g = q.face;
  if (g == f) {
    out = q.bary[0] * L.p[0] + q.bary[1] * L.p[1] + q.bary[2] * L.p[2];
    return true;
  }
  for (int m = 0; m < 3; ++m) {
    if (q.bary[m] != 1.0) continue;
    for (int k = 0; k < 3; ++k) {
      if (c.tail(3 * f + k) == c.tail(3 * g + m)) {
        out = L.p[k];
        return true;
      }
    }
  }
  for (int s = 0; s < 3; ++s) {
    const Index t = c.twin(3 * f + s);
    if (t == kInvalidIndex || T::face(t) != g) continue;
    const int sg = T::side(t);  // g's side from f's corner s+1 (A) to f's corner s (B)
    const Eigen::Vector2d A = L.p[(s + 1) % 3], B = L.p[s];
    const double lab = (B - A).norm();
    if (!(lab > 0.0)) return false;
    const Eigen::Vector2d e = (B - A) / lab, n(-e.y(), e.x());
    const Eigen::Vector2d x = intrinsic::triangle_apex(lab, c.halfedge_length(3 * g + (sg + 1) % 3),
                                                       c.halfedge_length(3 * g + (sg + 2) % 3));
    Eigen::Vector2d pos[3];
    pos[sg] = A;
    pos[(sg + 1) % 3] = B;
    pos[(sg + 2) % 3] = A + x.x() * e + x.y() * n;
    out = q.bary[0] * pos[0] + q.bary[1] * pos[1] + q.bary[2] * pos[2];
    return true;
  }
  return false;
}

}  // namespace

ComplexSparseMatrix tangent_prolongation(const intrinsic::IntrinsicTriangulation& fine,
                                         const intrinsic::Simplification& s) {
  (void)prolongation(s);  // checks the faces and the coarse copies
  const Index nv = fine.n_vertices();
  if (Index(s.fine_in_coarse.size()) != nv) {
    throw InvalidInput("tangent_prolongation: the simplification has " +
                       std::to_string(s.fine_in_coarse.size()) +
                       " fine vertices, the fine triangulation " + std::to_string(nv));
  }
  const T& c = s.coarse;
  std::vector<Index> fine_to_coarse(nv, kInvalidIndex);
  for (Index k = 0; k < Index(s.coarse_to_fine.size()); ++k)
    fine_to_coarse[s.coarse_to_fine[k]] = k;
  const TangentFrames ff = tangent_frames(fine), cf = tangent_frames(c);
  // per fine vertex: Σ over its fine edges of exp(i(layout angle − fine halfedge angle))
  std::vector<std::complex<double>> to_fine(nv, 0.0);
  for (Index h = 0; h < fine.n_halfedges(); ++h) {
    const Index i = fine.tail(h), j = fine.head(h);
    const intrinsic::SurfacePoint& pi = s.fine_in_coarse[i];
    if (i == j || pi.face == kInvalidIndex || s.fine_in_coarse[j].face == kInvalidIndex) continue;
    const FaceLayout L = layout_of(c, pi.face);
    Eigen::Vector2d xj;
    if (!place_in(c, pi.face, L, s.fine_in_coarse[j], xj)) continue;
    const Eigen::Vector2d d =
        xj - (pi.bary[0] * L.p[0] + pi.bary[1] * L.p[1] + pi.bary[2] * L.p[2]);
    if (!(d.norm() > 0.0)) continue;
    to_fine[i] += std::polar(1.0, std::atan2(d.y(), d.x()) - ff.halfedge_angle[h]);
  }
  std::vector<Eigen::Triplet<std::complex<double>, int>> entries;
  entries.reserve(3 * std::size_t(nv));
  for (Index i = 0; i < nv; ++i) {
    const intrinsic::SurfacePoint& p = s.fine_in_coarse[i];
    if (p.face == kInvalidIndex) {  // unreferenced: its coarse copy (prolongation() checked it)
      entries.emplace_back(i, fine_to_coarse[i], 1.0);
      continue;
    }
    const double m = std::abs(to_fine[i]);
    const std::complex<double> back = m > 0.0 ? std::conj(to_fine[i]) / m : 1.0;
    const FaceLayout L = layout_of(c, p.face);
    for (int k = 0; k < 3; ++k) {
      if (p.bary[k] == 0.0) continue;
      const Eigen::Vector2d d = L.p[(k + 1) % 3] - L.p[k];
      const double psi = std::atan2(d.y(), d.x());
      entries.emplace_back(
          i, c.tail(3 * p.face + k),
          p.bary[k] * std::polar(1.0, psi - cf.halfedge_angle[3 * p.face + k]) * back);
    }
  }
  ComplexSparseMatrix R(nv, c.n_vertices());
  R.setFromTriplets(entries.begin(), entries.end());
  return R;
}

}  // namespace ifem::fem
