// Per-vertex 3D tangent bases (tangent_basis.h).
#include "solvers/vector/tangent_basis.h"

#include <Eigen/Eigenvalues>
#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <functional>
#include <queue>
#include <string>
#include <tuple>

#include "intrinsic/core/errors.h"

namespace ifem::solvers {

using intrinsic::IntrinsicTriangulation;

namespace {

std::string str(Index v) { return std::to_string(v); }

}  // namespace

// --- 3D tangent bases ---------------------------------------------------------------------------

namespace {

// Per input vertex (ids < n), its distinct neighbours through tri's edges (input vertices only).
std::vector<std::vector<Index>> input_neighbours(const IntrinsicTriangulation& tri, Index n) {
  std::vector<std::vector<Index>> out(static_cast<std::size_t>(n));
  for (Index e = 0; e < tri.n_edges(); ++e) {
    const Index h = tri.edge_halfedge(e);
    const Index v = tri.tail(h), w = tri.head(h);
    if (v >= n || w >= n || v == w) continue;
    out[v].push_back(w);
    out[w].push_back(v);
  }
  for (auto& list : out) {
    std::sort(list.begin(), list.end());
    list.erase(std::unique(list.begin(), list.end()), list.end());
  }
  return out;
}

// The smallest principal axis of the chords from v to its neighbours (unit), or 0 when they do
// not span a plane's worth (fewer than two, or all at v).
Eigen::Vector3d principal_normal(const Positions& p, Index v, const std::vector<Index>& nbrs) {
  if (nbrs.size() < 2) return Eigen::Vector3d::Zero();
  Eigen::Vector3d mean = Eigen::Vector3d::Zero();  // of the chords and v's own 0
  for (const Index w : nbrs) mean += (p.row(w) - p.row(v)).transpose();
  mean /= double(nbrs.size() + 1);
  Eigen::Matrix3d cov = mean * mean.transpose();
  for (const Index w : nbrs) {
    const Eigen::Vector3d d = (p.row(w) - p.row(v)).transpose() - mean;
    cov += d * d.transpose();
  }
  if (cov.isZero()) return Eigen::Vector3d::Zero();
  const Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> es(cov);
  return es.eigenvectors().col(0);  // eigenvalues ascending
}

// Twice the area times the unit normal of each triangle, summed per vertex (sum), and the sum of
// their lengths (total).
void face_normal_sums(const Positions& p, const std::vector<Triangle>& triangles,
                      Eigen::MatrixX3d& sum, Eigen::VectorXd& total) {
  sum = Eigen::MatrixX3d::Zero(p.rows(), 3);
  total = Eigen::VectorXd::Zero(p.rows());
  for (const Triangle& f : triangles) {
    const Eigen::Vector3d a = p.row(f[0]), b = p.row(f[1]), c = p.row(f[2]);
    const Eigen::Vector3d nf = (b - a).cross(c - a);
    for (const Index v : f) {
      sum.row(v) += nf.transpose();
      total[v] += nf.norm();
    }
  }
}

// Area-weighted vertex normals of the triangles (unnormalized), or for a point cloud the given
// normals, or the smallest principal axis of the chords to the intrinsic neighbours.
Eigen::MatrixX3d raw_normals(const Positions& p, const std::vector<Triangle>& triangles,
                             const Eigen::MatrixX3d& normals, const IntrinsicTriangulation& tri) {
  const Index n = static_cast<Index>(p.rows());
  if (!triangles.empty()) {
    Eigen::MatrixX3d sum;
    Eigen::VectorXd total;
    face_normal_sums(p, triangles, sum, total);
    return sum;
  }
  if (normals.rows() == n) return normals;
  const std::vector<std::vector<Index>> nbrs = input_neighbours(tri, n);
  Eigen::MatrixX3d out(n, 3);
  for (Index v = 0; v < n; ++v) out.row(v) = principal_normal(p, v, nbrs[v]).transpose();
  return out;
}

// A unit vector orthogonal to the unit vector n.
Eigen::Vector3d any_orthogonal(const Eigen::Vector3d& n) {
  const Eigen::Vector3d a =
      std::abs(n.x()) < 0.9 ? Eigen::Vector3d::UnitX() : Eigen::Vector3d::UnitY();
  return (a - a.dot(n) * n).normalized();
}

void check_basis_inputs(const Positions& positions, const std::vector<Triangle>& triangles,
                        const Eigen::MatrixX3d& normals, const IntrinsicTriangulation& tri,
                        const fem::TangentFrames& frames) {
  const Index n = static_cast<Index>(positions.rows());
  if (n > tri.n_vertices()) {
    throw InvalidInput("tangent_basis_3d: positions has " + str(n) +
                       " rows for a triangulation of " + str(tri.n_vertices()) + " vertices");
  }
  if (normals.rows() != 0 && normals.rows() != n) {
    throw InvalidInput("tangent_basis_3d: normals has " + str(Index(normals.rows())) +
                       " rows, expected 0 or " + str(n));
  }
  if (frames.halfedge_angle.size() != tri.n_halfedges() ||
      frames.angle_scale.size() != tri.n_vertices()) {
    throw InvalidInput("tangent_basis_3d: frames are not those of the triangulation");
  }
  for (const Triangle& f : triangles) {
    for (const Index v : f) {
      if (v < 0 || v >= n) {
        throw InvalidInput("tangent_basis_3d: triangle index " + str(v) + " out of range [0, " +
                           str(n) + ")");
      }
    }
  }
}

}  // namespace

namespace {

// The direction in which halfedge h leaves its tail (an input vertex), projected to the tail's
// tangent plane (unit normals), not normalized; zero where it is not known: with a correspondence
// their exact 3D direction, else the chord to the head when that is another input vertex.
class TangentDirections {
 public:
  TangentDirections(const Positions& p, const IntrinsicTriangulation& tri,
                    const Eigen::MatrixX3d& normal,
                    const std::optional<intrinsic::CorrespondenceView>& c)
      : p_(p), tri_(tri), normal_(normal), c_(c) {}

  Eigen::Vector3d operator()(Index h) const {
    const Index v = tri_.tail(h), w = tri_.head(h);
    Eigen::Vector3d d;
    if (c_) {
      d = c_->halfedge_direction_3d(h);
    } else if (w < p_.rows() && w != v) {
      d = (p_.row(w) - p_.row(v)).transpose();
    } else {
      return Eigen::Vector3d::Zero();
    }
    const Eigen::Vector3d nv = normal_.row(v).transpose();
    const Eigen::Vector3d t = d - d.dot(nv) * nv;
    return t.allFinite() ? t : Eigen::Vector3d::Zero();
  }

 private:
  const Positions& p_;
  const IntrinsicTriangulation& tri_;
  const Eigen::MatrixX3d& normal_;
  const std::optional<intrinsic::CorrespondenceView>& c_;
};

// Per input vertex, the outgoing halfedge that fixes e1: the reference halfedge when its
// direction is known (and off the normal), else such a halfedge of smallest angle;
// kInvalidIndex when there is none.
std::vector<Index> anchors(Index n, const IntrinsicTriangulation& tri,
                           const fem::TangentFrames& frames, const TangentDirections& direction) {
  auto usable = [&](Index h) { return direction(h).norm() > 0.0; };
  std::vector<Index> anchor(static_cast<std::size_t>(n), kInvalidIndex);
  for (Index v = 0; v < n; ++v) {
    const Index h = tri.vertex_halfedge(v);
    if (h != kInvalidIndex && usable(h)) anchor[v] = h;
  }
  for (Index h = 0; h < tri.n_halfedges(); ++h) {
    const Index v = tri.tail(h);
    if (v >= n) continue;
    const Index a = anchor[v];
    if (a != kInvalidIndex && a == tri.vertex_halfedge(v)) continue;
    if ((a == kInvalidIndex || frames.halfedge_angle[h] < frames.halfedge_angle[a]) && usable(h)) {
      anchor[v] = h;
    }
  }
  return anchor;
}

// Per vertex, > 0 when the directions turn counter-clockwise about the normal as the angles grow:
// Σ_h sin(θ_h − θ_anchor) · sin(angle from the anchor's direction to h's, about the normal).
Eigen::VectorXd orientation_votes(Index n, const IntrinsicTriangulation& tri,
                                  const fem::TangentFrames& frames, const Eigen::MatrixX3d& normal,
                                  const TangentDirections& direction,
                                  const std::vector<Index>& anchor) {
  Eigen::VectorXd vote = Eigen::VectorXd::Zero(n);
  Eigen::MatrixX3d anchor_direction = Eigen::MatrixX3d::Zero(n, 3);
  for (Index v = 0; v < n; ++v) {
    if (anchor[v] != kInvalidIndex) anchor_direction.row(v) = direction(anchor[v]).transpose();
  }
  for (Index h = 0; h < tri.n_halfedges(); ++h) {
    const Index v = tri.tail(h);
    if (v >= n || anchor[v] == kInvalidIndex || h == anchor[v]) continue;
    const Eigen::Vector3d a = anchor_direction.row(v).transpose();
    const Eigen::Vector3d d = direction(h);
    const double norms = a.norm() * d.norm();
    if (!(norms > 0.0)) continue;
    const double s = std::sin(frames.halfedge_angle[h] - frames.halfedge_angle[anchor[v]]);
    vote[v] += s * a.cross(d).dot(normal.row(v).transpose()) / norms;
  }
  return vote;
}

// With a correspondence: it must be that of tri (same vertices, halfedges and tails) over an input
// of n vertices.
void check_correspondence(const intrinsic::CorrespondenceView& c, const IntrinsicTriangulation& tri,
                          Index n) {
  const IntrinsicTriangulation& t = c.intrinsic();
  bool same = c.n_input_vertices() == n && t.n_vertices() == tri.n_vertices() &&
              t.n_halfedges() == tri.n_halfedges();
  for (Index h = 0; same && h < tri.n_halfedges(); ++h) same = t.tail(h) == tri.tail(h);
  if (!same) {
    throw InvalidInput("tangent_basis_3d: the correspondence is not that of the triangulation (" +
                       str(t.n_vertices()) + " vertices, " + str(c.n_input_vertices()) +
                       " input ones, against " + str(tri.n_vertices()) + " and " + str(n) + ")");
  }
}

}  // namespace

TangentBasis3d tangent_basis_3d(const Positions& p, const std::vector<Triangle>& triangles,
                                const Eigen::MatrixX3d& normals, const IntrinsicTriangulation& tri,
                                const fem::TangentFrames& frames,
                                std::optional<intrinsic::CorrespondenceView> correspondence) {
  check_basis_inputs(p, triangles, normals, tri, frames);
  const Index n = static_cast<Index>(p.rows());
  if (correspondence) check_correspondence(*correspondence, tri, n);
  TangentBasis3d b;
  b.normal = raw_normals(p, triangles, normals, tri);
  std::vector<char> fallback(static_cast<std::size_t>(n), 0);
  for (Index v = 0; v < n; ++v) {
    const double len = b.normal.row(v).norm();
    if (len > 0.0 && std::isfinite(len)) {
      b.normal.row(v) /= len;
    } else {
      b.normal.row(v) = Eigen::RowVector3d::UnitZ();
      fallback[v] = 1;
    }
  }
  const TangentDirections direction(p, tri, b.normal, correspondence);
  const std::vector<Index> anchor = anchors(n, tri, frames, direction);
  const Eigen::VectorXd vote = orientation_votes(n, tri, frames, b.normal, direction, anchor);
  b.e1.resize(n, 3);
  b.e2.resize(n, 3);
  for (Index v = 0; v < n; ++v) {
    if (vote[v] < 0.0) b.normal.row(v) *= -1.0;
    const Eigen::Vector3d nv = b.normal.row(v).transpose();
    Eigen::Vector3d e1;
    if (anchor[v] == kInvalidIndex) {
      e1 = any_orthogonal(nv);
      fallback[v] = 1;
    } else {  // the anchor's direction turned back by its angle to angle 0
      const Eigen::Vector3d a = direction(anchor[v]).normalized();
      const double theta = frames.halfedge_angle[anchor[v]];
      e1 = std::cos(theta) * a - std::sin(theta) * nv.cross(a);
    }
    b.e1.row(v) = e1.transpose();
    b.e2.row(v) = nv.cross(e1).transpose();
  }
  b.fallback_vertices = static_cast<Index>(std::count(fallback.begin(), fallback.end(), 1));
  return b;
}

TangentBasis3d tangent_basis_3d(const io::SurfaceInput& input, const IntrinsicTriangulation& tri,
                                const fem::TangentFrames& frames,
                                std::optional<intrinsic::CorrespondenceView> correspondence) {
  return tangent_basis_3d(input.positions, input.triangles, input.normals, tri, frames,
                          correspondence);
}

// --- frames for the frame path ------------------------------------------------------------------

namespace {

// Below this fraction of Σ|n_f| the faces' normals at a vertex count as cancelled.
constexpr double kCancelled = 0.2;

// Unit normals before orientation; `trusted` marks those whose sign means something (from the
// faces or the given normals); zero rows where there is no normal at all.
void unoriented_normals(const Positions& p, const std::vector<Triangle>& triangles,
                        const Eigen::MatrixX3d& normals,
                        const std::vector<std::vector<Index>>& nbrs, Eigen::MatrixX3d& out,
                        std::vector<char>& trusted) {
  const Index n = static_cast<Index>(p.rows());
  out = Eigen::MatrixX3d::Zero(n, 3);
  trusted.assign(static_cast<std::size_t>(n), 0);
  Eigen::MatrixX3d sum = normals.rows() == n ? normals : Eigen::MatrixX3d::Zero(n, 3);
  Eigen::VectorXd total = sum.rowwise().norm();
  if (!triangles.empty()) face_normal_sums(p, triangles, sum, total);
  for (Index v = 0; v < n; ++v) {
    const double len = sum.row(v).norm();
    if (std::isfinite(len) && len > 0.0 && len >= kCancelled * total[v]) {
      out.row(v) = sum.row(v) / len;
      trusted[v] = 1;
    } else {
      out.row(v) = principal_normal(p, v, nbrs[v]).transpose();
    }
  }
}

// ±1 per vertex: each connected component of the neighbour graph grown as a minimum spanning
// tree (Prim) under the weights 1 − |n_i·n_j| from its lowest vertex, every vertex taking the
// sign that makes its normal agree with its tree parent's. label: the component per vertex.
std::vector<int> propagated_signs(const Eigen::MatrixX3d& normal,
                                  const std::vector<std::vector<Index>>& nbrs,
                                  std::vector<Index>& label) {
  const Index n = static_cast<Index>(normal.rows());
  std::vector<int> sign(static_cast<std::size_t>(n), 1);
  label.assign(static_cast<std::size_t>(n), kInvalidIndex);
  using Item = std::tuple<double, Index, Index>;  // weight, vertex, parent
  std::priority_queue<Item, std::vector<Item>, std::greater<Item>> queue;
  Index count = 0;
  for (Index root = 0; root < n; ++root) {
    if (label[root] != kInvalidIndex) continue;
    queue.emplace(0.0, root, kInvalidIndex);
    while (!queue.empty()) {
      const auto [weight, v, parent] = queue.top();
      queue.pop();
      if (label[v] != kInvalidIndex) continue;
      label[v] = count;
      if (parent != kInvalidIndex && sign[parent] * normal.row(parent).dot(normal.row(v)) < 0.0) {
        sign[v] = -1;
      }
      for (const Index w : nbrs[v]) {
        if (label[w] == kInvalidIndex) {
          queue.emplace(1.0 - std::abs(normal.row(v).dot(normal.row(w))), w, v);
        }
      }
    }
    ++count;
  }
  return sign;
}

// Per component, the neighbour pairs whose signed normals disagree.
std::vector<Index> conflicts(const Eigen::MatrixX3d& normal, const std::vector<int>& sign,
                             const std::vector<std::vector<Index>>& nbrs,
                             const std::vector<Index>& label, Index components) {
  std::vector<Index> out(static_cast<std::size_t>(components), 0);
  for (Index v = 0; v < static_cast<Index>(nbrs.size()); ++v) {
    for (const Index w : nbrs[v]) {
      if (w > v && sign[v] * sign[w] * normal.row(v).dot(normal.row(w)) < 0.0) ++out[label[v]];
    }
  }
  return out;
}

// The orientation of each component (see frame_basis_3d()): signs applied to `normal`.
Index orient_components(const Positions& p, const std::vector<std::vector<Index>>& nbrs,
                        const std::vector<char>& trusted, Eigen::MatrixX3d& normal) {
  const Index n = static_cast<Index>(normal.rows());
  std::vector<Index> label;
  std::vector<int> sign = propagated_signs(normal, nbrs, label);
  const Index nc = n == 0 ? 0 : *std::max_element(label.begin(), label.end()) + 1;
  std::vector<double> vote(nc, 0.0), outward(nc, 0.0);
  std::vector<Eigen::Vector3d> centroid(nc, Eigen::Vector3d::Zero());
  std::vector<Index> size(nc, 0), n_trusted(nc, 0);
  for (Index v = 0; v < n; ++v) {
    centroid[label[v]] += p.row(v).transpose();
    ++size[label[v]];
    if (trusted[v]) {
      vote[label[v]] += sign[v];  // agreement of the propagated sign with the raw one
      ++n_trusted[label[v]];
    }
  }
  for (Index v = 0; v < n; ++v) {
    const Eigen::Vector3d c = centroid[label[v]] / double(size[label[v]]);
    outward[label[v]] += sign[v] * normal.row(v).dot(p.row(v).transpose() - c);
  }
  std::vector<int> raw(sign);  // trusted vertices as given, the others propagated
  for (Index v = 0; v < n; ++v) {
    const Index c = label[v];
    if ((n_trusted[c] > 0 ? vote[c] : outward[c]) < 0.0) sign[v] = -sign[v];
    raw[v] = trusted[v] ? 1 : sign[v];
  }
  const std::vector<Index> by_propagation = conflicts(normal, sign, nbrs, label, nc);
  const std::vector<Index> by_input = conflicts(normal, raw, nbrs, label, nc);
  Index total = 0;
  for (Index v = 0; v < n; ++v) {
    const Index c = label[v];
    const bool keep_input = n_trusted[c] > 0 && by_input[c] <= by_propagation[c];
    normal.row(v) *= keep_input ? raw[v] : sign[v];
  }
  for (Index c = 0; c < nc; ++c) {
    total += n_trusted[c] > 0 ? std::min(by_input[c], by_propagation[c]) : by_propagation[c];
  }
  return total;
}

void check_frame_inputs(const Positions& positions, const std::vector<Triangle>& triangles,
                        const Eigen::MatrixX3d& normals, const IntrinsicTriangulation& tri) {
  fem::TangentFrames none;
  none.halfedge_angle.resize(tri.n_halfedges());
  none.angle_scale.resize(tri.n_vertices());
  check_basis_inputs(positions, triangles, normals, tri, none);
  if (!positions.allFinite()) throw InvalidInput("frame_basis_3d: a position is not finite");
}

}  // namespace

TangentBasis3d frame_basis_3d(const Positions& p, const std::vector<Triangle>& triangles,
                              const Eigen::MatrixX3d& normals, const IntrinsicTriangulation& tri) {
  check_frame_inputs(p, triangles, normals, tri);
  const Index n = static_cast<Index>(p.rows());
  const std::vector<std::vector<Index>> nbrs = input_neighbours(tri, n);
  TangentBasis3d b;
  std::vector<char> trusted;
  unoriented_normals(p, triangles, normals, nbrs, b.normal, trusted);
  for (Index v = 0; v < n; ++v) {
    if (b.normal.row(v).isZero()) {
      b.normal.row(v) = Eigen::RowVector3d::UnitZ();
      ++b.fallback_vertices;
    }
  }
  b.orientation_conflicts = orient_components(p, nbrs, trusted, b.normal);
  b.e1.resize(n, 3);
  b.e2.resize(n, 3);
  for (Index v = 0; v < n; ++v) {
    const Eigen::Vector3d nv = b.normal.row(v).transpose();
    const Eigen::Vector3d e1 = any_orthogonal(nv);
    b.e1.row(v) = e1.transpose();
    b.e2.row(v) = nv.cross(e1).transpose();
  }
  return b;
}

TangentBasis3d frame_basis_3d(const io::SurfaceInput& input, const IntrinsicTriangulation& tri) {
  return frame_basis_3d(input.positions, input.triangles, input.normals, tri);
}

Eigen::MatrixX3d to_3d(const Eigen::VectorXcd& z, const TangentBasis3d& basis) {
  const Eigen::Index n = basis.e1.rows();
  if (z.size() < n) {
    throw InvalidInput("to_3d: " + std::to_string(z.size()) + " vectors for a basis of " +
                       std::to_string(n) + " vertices");
  }
  Eigen::MatrixX3d out(n, 3);
  for (Eigen::Index v = 0; v < n; ++v) {
    out.row(v) = z[v].real() * basis.e1.row(v) + z[v].imag() * basis.e2.row(v);
  }
  return out;
}

}  // namespace ifem::solvers
