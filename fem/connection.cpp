#include "fem/connection.h"

#include <algorithm>
#include <cmath>
#include <string>
#include <vector>

#include "fem/operators.h"
#include "intrinsic/core/errors.h"
#include "intrinsic/core/geometry.h"
#include "intrinsic/core/types.h"

namespace ifem::fem {

using intrinsic::IntrinsicTriangulation;
using intrinsic::kPi;
using T = IntrinsicTriangulation;

namespace {

constexpr double kTwoPi = 2.0 * kPi;

// x reduced to [0, 2π) (x is a scaled angle sum: a few turns at most).
inline double wrap_turn(double x) {
  x = std::fmod(x, kTwoPi);
  if (x < 0.0) x += kTwoPi;
  return x < kTwoPi ? x : 0.0;  // fmod of −tiny + 2π can round up to 2π
}

// x reduced to (−π, π].
inline double wrap_half_turn(double x) {
  x = wrap_turn(x);
  return x > kPi ? x - kTwoPi : x;
}

// Interior angle of every face at every corner, #H (corner of h = at tail(h)): corner_angle()'s
// formula with one area per face.
std::vector<double> corner_angles(const IntrinsicTriangulation& tri) {
  const Index nf = tri.n_faces();
  std::vector<double> corner(tri.n_halfedges());
#pragma omp parallel for schedule(static) if (nf >= kParallelMin)
  for (Index f = 0; f < nf; ++f) {
    double l[3] = {tri.halfedge_length(3 * f), tri.halfedge_length(3 * f + 1),
                   tri.halfedge_length(3 * f + 2)};
    const double scale = intrinsic::length_normalizer(std::max({l[0], l[1], l[2]}));
    for (double& x : l) x /= scale;
    const double four_area = 4.0 * intrinsic::triangle_area(l[0], l[1], l[2]);
    for (int s = 0; s < 3; ++s) {  // between side s and side s + 2, opposite side s + 1
      const double a = l[(s + 1) % 3], b = l[s], c = l[(s + 2) % 3];
      corner[3 * f + s] = std::atan2(four_area, b * b + c * c - a * a);
    }
  }
  return corner;
}

// Θ_v and angle_scale into frames; the number of outgoing halfedges of each vertex into
// outgoing. A vertex with an outgoing boundary halfedge is a boundary vertex: it keeps its true
// angles (scale 1) while they fit in one turn, Θ ≤ 2π, and is compressed to one turn beyond.
void angle_sums_and_scales(const IntrinsicTriangulation& tri, const std::vector<double>& corner,
                           TangentFrames& frames, std::vector<Index>& outgoing) {
  const Index nv = tri.n_vertices();
  frames.angle_sum = Eigen::VectorXd::Zero(nv);
  std::vector<char> boundary(nv, 0);
  outgoing.assign(nv, 0);
  const auto& tail = tri.tails();
  const auto& twin = tri.twins();
  for (Index h = 0; h < tri.n_halfedges(); ++h) {
    frames.angle_sum[tail[h]] += corner[h];
    ++outgoing[tail[h]];
    if (twin[h] == kInvalidIndex) boundary[tail[h]] = 1;
  }
  frames.angle_scale.resize(nv);
  for (Index v = 0; v < nv; ++v) {
    const double theta = frames.angle_sum[v];
    const double turn = boundary[v] ? std::max(theta, kTwoPi) : theta;
    frames.angle_scale[v] = theta > 0.0 ? kTwoPi / turn : 0.0;
  }
}

// The first halfedge (counter-clockwise) of the fan of outgoing halfedge h: the fan's outgoing
// boundary halfedge if the fan is open, h itself if it is closed.
Index fan_start(const IntrinsicTriangulation& tri, Index h) {
  Index x = h;
  for (Index guard = 0; guard <= tri.n_halfedges(); ++guard) {
    const Index t = tri.twin(x);
    if (t == kInvalidIndex) return x;
    x = T::next(t);  // clockwise: the outgoing halfedge before x
    if (x == h) return h;
  }
  return h;
}

// Lays out the fan that starts at `start` counter-clockwise: halfedge_angle = scale × (offset +
// the corner angles accumulated from start), marking each halfedge in `laid` when given.
// Returns offset + the fan's angle sum; `count` gets the number of halfedges laid out and
// `open` whether the fan ended at the boundary.
double lay_out_fan(const IntrinsicTriangulation& tri, const std::vector<double>& corner,
                   double scale, Index start, double offset, Eigen::VectorXd& angle,
                   std::vector<char>* laid, Index& count, bool& open) {
  double acc = offset;
  count = 0;
  open = false;
  Index x = start;
  for (Index guard = 0; guard <= tri.n_halfedges(); ++guard) {
    angle[x] = wrap_turn(scale * acc);
    acc += corner[x];
    ++count;
    if (laid) (*laid)[x] = 1;
    const Index n = tri.twin(T::prev(x));
    if (n == kInvalidIndex) {
      open = true;
      break;
    }
    if (n == start) break;
    x = n;
  }
  return acc;
}

// The fan of vertex_halfedge(v), for every referenced vertex v (the reference halfedge is at
// angle 0; should it not start its open fan, the fan is laid out again from its start). Returns
// the vertices whose fan misses some of their halfedges: pinched, more fans to lay out.
std::vector<Index> lay_out_first_fans(const IntrinsicTriangulation& tri,
                                      const std::vector<double>& corner,
                                      const std::vector<Index>& outgoing, TangentFrames& frames) {
  const Index nv = tri.n_vertices();
  std::vector<char> pinched(nv, 0);
#pragma omp parallel for schedule(static) if (nv >= kParallelMin)
  for (Index v = 0; v < nv; ++v) {
    const Index h0 = tri.vertex_halfedge(v);
    if (h0 == kInvalidIndex) continue;
    Index count = 0;
    bool open = false;
    const double s = frames.angle_scale[v];
    lay_out_fan(tri, corner, s, h0, 0.0, frames.halfedge_angle, nullptr, count, open);
    if (open && tri.twin(h0) != kInvalidIndex) {
      lay_out_fan(tri, corner, s, fan_start(tri, h0), 0.0, frames.halfedge_angle, nullptr, count,
                  open);
    }
    pinched[v] = count < outgoing[v] ? 1 : 0;
  }
  std::vector<Index> out;
  for (Index v = 0; v < nv; ++v) {
    if (pinched[v]) out.push_back(v);
  }
  return out;
}

// The other fans of pinched vertices, one after the other in the order of their smallest
// outgoing halfedge id, each starting where the previous one ended.
void lay_out_other_fans(const IntrinsicTriangulation& tri, const std::vector<double>& corner,
                        const std::vector<Index>& pinched, TangentFrames& frames) {
  if (pinched.empty()) return;
  std::vector<char> laid(tri.n_halfedges(), 0);
  std::vector<char> is_pinched(tri.n_vertices(), 0);
  for (const Index v : pinched) is_pinched[v] = 1;
  std::vector<std::vector<Index>> out(tri.n_vertices());  // outgoing halfedges, pinched only
  for (Index h = 0; h < tri.n_halfedges(); ++h) {
    if (is_pinched[tri.tail(h)]) out[tri.tail(h)].push_back(h);
  }
  Eigen::VectorXd& angle = frames.halfedge_angle;
  for (const Index v : pinched) {
    const double s = frames.angle_scale[v];
    Index count = 0;
    bool open = false;
    const Index first = fan_start(tri, tri.vertex_halfedge(v));  // as lay_out_first_fans()
    double end = lay_out_fan(tri, corner, s, first, 0.0, angle, &laid, count, open);
    for (const Index h : out[v]) {
      if (laid[h]) continue;
      end = lay_out_fan(tri, corner, s, fan_start(tri, h), end, angle, &laid, count, open);
    }
  }
}

// r_h = exp(i (θ_back − θ_h + π)), θ_back the direction at head(h) of the edge back to tail(h):
// θ_twin(h), or on a boundary edge its direction in face(h) (next(h) turned by its corner).
void transports(const IntrinsicTriangulation& tri, const std::vector<double>& corner,
                TangentFrames& frames) {
  const Index nh = tri.n_halfedges();
  frames.transport.resize(nh);
  const Eigen::VectorXd& angle = frames.halfedge_angle;
#pragma omp parallel for schedule(static) if (nh >= kParallelMin)
  for (Index h = 0; h < nh; ++h) {
    const Index t = tri.twin(h);
    double back = 0.0;
    if (t != kInvalidIndex) {
      back = angle[t];
    } else {
      const Index n = T::next(h);
      back = angle[n] + frames.angle_scale[tri.tail(n)] * corner[n];
    }
    frames.transport[h] = std::polar(1.0, wrap_turn(back - angle[h] + kPi));
  }
}

}  // namespace

TangentFrames tangent_frames(const IntrinsicTriangulation& tri) {
  TangentFrames frames;
  const std::vector<double> corner = corner_angles(tri);
  std::vector<Index> outgoing;
  angle_sums_and_scales(tri, corner, frames, outgoing);
  frames.halfedge_angle = Eigen::VectorXd::Zero(tri.n_halfedges());
  const std::vector<Index> pinched = lay_out_first_fans(tri, corner, outgoing, frames);
  lay_out_other_fans(tri, corner, pinched, frames);
  transports(tri, corner, frames);
  return frames;
}

double TangentFrames::holonomy_around(const IntrinsicTriangulation& tri, Index v) const {
  if (v < 0 || v >= tri.n_vertices()) {
    throw InvalidInput("holonomy_around: vertex " + std::to_string(v) + " out of range");
  }
  if (transport.size() != tri.n_halfedges() || angle_scale.size() != tri.n_vertices()) {
    throw InvalidInput("holonomy_around: the frames are not those of this triangulation");
  }
  const Index h0 = tri.vertex_halfedge(v);
  if (h0 == kInvalidIndex) return 0.0;
  // Around each face at v: the rotation of a vector carried along its three sides, minus the
  // share of the face's two other corners ((scale − 1) × angle each): what remains is v's.
  const Index start = fan_start(tri, h0);
  double total = 0.0;
  Index x = start;
  for (Index guard = 0; guard <= tri.n_halfedges(); ++guard) {
    const Index b = T::next(x), c = T::prev(x);
    total += std::arg(transport[x]) + std::arg(transport[b]) + std::arg(transport[c]);
    total -= (angle_scale[tri.tail(b)] - 1.0) * intrinsic::corner_angle(tri, b);
    total -= (angle_scale[tri.tail(c)] - 1.0) * intrinsic::corner_angle(tri, c);
    const Index n = tri.twin(c);
    if (n == kInvalidIndex || n == start) break;
    x = n;
  }
  return wrap_half_turn(total);
}

namespace {

// cotan_laplacian()'s refusal: a non-finite weight means a zero-area face.
void require_finite(const IntrinsicTriangulation& tri, const Eigen::VectorXd& w) {
  for (Index e = 0; e < w.size(); ++e) {
    if (std::isfinite(w[e])) continue;
    const Index h = tri.edge_halfedge(e);
    throw Error("connection_laplacian: the weight of edge " + std::to_string(e) + " (" +
                std::to_string(tri.tail(h)) + "," + std::to_string(tri.head(h)) +
                ") is not finite: face " + std::to_string(T::face(h)) +
                " or its neighbour has zero area (mollify the triangulation first)");
  }
}

// r^n for a unit r (repeated squaring), renormalized when n > 1.
inline std::complex<double> unit_power(std::complex<double> r, int n) {
  if (n == 1) return r;
  std::complex<double> q(1.0, 0.0);
  for (; n > 0; n >>= 1, r *= r) {
    if (n & 1) q *= r;
  }
  return q / std::sqrt(std::norm(q));
}

// The stored entry (row, col) of a compressed matrix whose pattern holds it.
inline std::complex<double>& entry(ComplexSparseMatrix& L, Index row, Index col) {
  const int* begin = L.innerIndexPtr() + L.outerIndexPtr()[col];
  const int* end = L.innerIndexPtr() + L.outerIndexPtr()[col + 1];
  return L.valuePtr()[std::lower_bound(begin, end, row) - L.innerIndexPtr()];
}

}  // namespace

ComplexSparseMatrix connection_laplacian(const IntrinsicTriangulation& tri,
                                         const TangentFrames& frames, int symmetry) {
  if (symmetry < 1) {
    throw InvalidInput("connection_laplacian: symmetry must be ≥ 1, got " +
                       std::to_string(symmetry));
  }
  if (frames.transport.size() != tri.n_halfedges() ||
      frames.angle_scale.size() != tri.n_vertices()) {
    throw InvalidInput("connection_laplacian: the frames are not those of this triangulation");
  }
  const Eigen::VectorXd w = intrinsic::cotan_weights(tri);
  require_finite(tri, w);
  // The scalar Laplacian gives the pattern (parallel edges merged) and the diagonal Σ w_ij;
  // the edges then write their rotated off-diagonal entries, self-edges their holonomy term.
  const SparseMatrix scalar = laplacian_from_weights(tri, w);
  ComplexSparseMatrix L(tri.n_vertices(), tri.n_vertices());
  L.resizeNonZeros(static_cast<Index>(scalar.nonZeros()));
  std::copy_n(scalar.outerIndexPtr(), tri.n_vertices() + 1, L.outerIndexPtr());
  std::copy_n(scalar.innerIndexPtr(), scalar.nonZeros(), L.innerIndexPtr());
  std::fill_n(L.valuePtr(), scalar.nonZeros(), std::complex<double>(0.0, 0.0));
  for (Index v = 0; v < tri.n_vertices(); ++v) entry(L, v, v) = scalar.coeff(v, v);
  const double inv_multiplicity = 1.0 / tri.multiplicity();
  for (Index e = 0; e < tri.n_edges(); ++e) {
    const Index h = tri.edge_halfedge(e);
    const Index i = tri.tail(h), j = tri.head(h);
    const double we = inv_multiplicity * w[e];
    const std::complex<double> q = unit_power(frames.transport[h], symmetry);  // r_{i→j}^n
    if (i == j) {
      entry(L, i, i) += we * std::norm(1.0 - q);  // w |x − q x|²
    } else {
      entry(L, j, i) -= we * q;
      entry(L, i, j) -= we * std::conj(q);
    }
  }
  return L;
}

}  // namespace ifem::fem
