// The signed heat method (signed_heat.h).
#include "solvers/vector/signed_heat.h"

#include <Eigen/SparseCore>
#include <algorithm>
#include <cmath>
#include <complex>
#include <limits>
#include <optional>
#include <string>
#include <vector>

#include "fem/connection.h"
#include "fem/frame_connection.h"
#include "fem/operators.h"
#include "intrinsic/core/errors.h"
#include "intrinsic/core/geometry.h"
#include "solvers/linalg/cholesky.h"
#include "solvers/linalg/parallel.h"
#include "solvers/scalar/components.h"
#include "solvers/scalar/poisson.h"

namespace ifem::solvers {
namespace {

using Complex = std::complex<double>;

// |Y| is resolved above this fraction of its component's largest value and above an absolute
// floor clear of subnormals (as the vector heat method's transport).
constexpr double kResolvedRelative = 1e-270;
constexpr double kAbsoluteFloor = 1e-290;
// Stages of unit_field() at most (each reaches about 700·√t further).
constexpr int kMaxStages = 64;

// Per edge (via tri.edge_halfedge(e), tail a → head b): the edge vector read at a and at b.
struct EdgeVectors {
  Eigen::VectorXcd at_tail, at_head;
};

EdgeVectors intrinsic_edge_vectors(const intrinsic::IntrinsicTriangulation& tri,
                                   const fem::TangentFrames& frames) {
  EdgeVectors ev{Eigen::VectorXcd(tri.n_edges()), Eigen::VectorXcd(tri.n_edges())};
  for (Index e = 0; e < tri.n_edges(); ++e) {
    const Index h = tri.edge_halfedge(e);
    const double l = tri.length(e);
    ev.at_tail[e] = std::polar(l, frames.halfedge_angle[h]);
    ev.at_head[e] = std::polar(l, frames.halfedge_angle[h]) * frames.transport[h];
  }
  return ev;
}

// The chord c in v's frame, scaled to length l (0 where c is normal to the tangent plane).
Complex in_frame(const TangentBasis3d& basis, Index v, const Eigen::Vector3d& c, double l) {
  const Complex z(c.dot(basis.e1.row(v)), c.dot(basis.e2.row(v)));
  const double r = std::abs(z);
  return r > 0.0 ? z * (l / r) : Complex(0.0);
}

EdgeVectors frame_edge_vectors(const intrinsic::IntrinsicTriangulation& tri,
                               const Positions& positions, const TangentBasis3d& basis) {
  EdgeVectors ev{Eigen::VectorXcd(tri.n_edges()), Eigen::VectorXcd(tri.n_edges())};
  for (Index e = 0; e < tri.n_edges(); ++e) {
    const Index h = tri.edge_halfedge(e);
    const Index a = tri.tail(h), b = tri.head(h);
    const Eigen::Vector3d c = (positions.row(b) - positions.row(a)).transpose();
    ev.at_tail[e] = in_frame(basis, a, c, tri.length(e));
    ev.at_head[e] = in_frame(basis, b, c, tri.length(e));
  }
  return ev;
}

// The cotan weights clamped to ≥ 0 (not divided by the multiplicity): curves inserted as
// constrained edges may leave large negative weights (a curve edge across a nearly flat triangle
// pair), which make M + tL∇ indefinite and the Poisson step ill-conditioned (signed_heat.h).
Eigen::VectorXd clamped_weights(const intrinsic::IntrinsicTriangulation& tri) {
  Eigen::VectorXd w = intrinsic::cotan_weights(tri);
  for (Eigen::Index e = 0; e < w.size(); ++e) {
    if (!std::isfinite(w[e])) {
      throw Error("signed_heat_distance: the cotan weight of edge " + std::to_string(e) +
                  " is not finite (a face of zero area: mollify the triangulation first)");
    }
    w[e] = std::max(w[e], 0.0);
  }
  return w;
}

// The connection Laplacian (n = 1, fem/connection.h's convention: x*Lx = Σ w |x_j − r_{i→j} x_i|²)
// on the weights w (divided by the multiplicity here).
fem::ComplexSparseMatrix intrinsic_connection(const intrinsic::IntrinsicTriangulation& tri,
                                              const fem::TangentFrames& frames,
                                              const Eigen::VectorXd& weights) {
  const Eigen::VectorXd w = weights / double(tri.multiplicity());
  std::vector<Eigen::Triplet<Complex>> t;
  t.reserve(4 * std::size_t(tri.n_edges()));
  for (Index e = 0; e < tri.n_edges(); ++e) {
    const double we = std::max(w[e], 0.0);
    if (!(we > 0.0)) continue;
    const Index h = tri.edge_halfedge(e);
    const Index i = tri.tail(h), j = tri.head(h);
    const Complex r = frames.transport[h];  // i's coordinate → j's
    if (i == j) {
      t.emplace_back(i, i, we * std::norm(Complex(1.0) - r));
      continue;
    }
    t.emplace_back(i, i, we);
    t.emplace_back(j, j, we);
    t.emplace_back(j, i, -we * r);
    t.emplace_back(i, j, -we * std::conj(r));
  }
  fem::ComplexSparseMatrix a(tri.n_vertices(), tri.n_vertices());
  a.setFromTriplets(t.begin(), t.end());
  return a;
}

void check_sources(const intrinsic::IntrinsicTriangulation& tri, const SignedHeatSources& s,
                   const SignedHeatOptions& options) {
  options.validate();
  const Index nv = tri.n_vertices();
  if (s.normals.size() != nv) {
    throw InvalidInput("signed_heat_distance: " + std::to_string(s.normals.size()) +
                       " normals for " + std::to_string(nv) + " vertices");
  }
  if (!s.normals.allFinite()) throw InvalidInput("signed_heat_distance: a normal is not finite");
  if (s.normals.cwiseAbs().maxCoeff() == 0.0) {
    throw InvalidInput("signed_heat_distance: no source (every normal is zero)");
  }
  if (s.zero_set.empty()) throw InvalidInput("signed_heat_distance: the zero set is empty");
  std::vector<char> seen(nv, 0);
  for (const Index v : s.zero_set) {
    if (v < 0 || v >= nv || tri.vertex_halfedge(v) == kInvalidIndex) {
      throw InvalidInput("signed_heat_distance: zero-set vertex " + std::to_string(v) +
                         " is out of range or used by no face");
    }
    if (seen[v]++) {
      throw InvalidInput("signed_heat_distance: zero-set vertex " + std::to_string(v) +
                         " is repeated");
    }
  }
  if (!s.zero_weights.empty() && s.zero_weights.size() != s.zero_set.size()) {
    throw InvalidInput("signed_heat_distance: " + std::to_string(s.zero_weights.size()) +
                       " zero-set weights for " + std::to_string(s.zero_set.size()) + " vertices");
  }
  for (const double w : s.zero_weights) {
    if (!(w >= 0.0) || !std::isfinite(w)) {
      throw InvalidInput("signed_heat_distance: a zero-set weight is negative or not finite");
    }
  }
}
// X = Y/|Y| on the vertices still open whose |Y| is resolved (above kResolvedRelative of the
// largest |Y| over the open vertices of its component, and above kAbsoluteFloor), which are then
// closed; returns how many.
Index resolve(const Eigen::VectorXcd& y, const Components& comps, std::vector<char>& open,
              Eigen::VectorXcd& x) {
  std::vector<double> largest(comps.count, 0.0);
  for (Eigen::Index v = 0; v < y.size(); ++v) {
    if (open[v]) largest[comps.label[v]] = std::max(largest[comps.label[v]], std::abs(y[v]));
  }
  Index n = 0;
  for (Eigen::Index v = 0; v < y.size(); ++v) {
    if (!open[v]) continue;
    const double r = std::abs(y[v]);
    if (r > std::max(kResolvedRelative * largest[comps.label[v]], kAbsoluteFloor) &&
        std::isfinite(r)) {
      x[v] = y[v] / r;
      open[v] = 0;
      ++n;
    }
  }
  return n;
}

// The next stage's sources: X on the closed vertices of reached components next to an open one.
Eigen::VectorXcd frontier(const intrinsic::IntrinsicTriangulation& tri,
                          const std::vector<char>& open, const Eigen::VectorXcd& x) {
  Eigen::VectorXcd y0 = Eigen::VectorXcd::Zero(x.size());
  for (Index e = 0; e < tri.n_edges(); ++e) {
    const Index h = tri.edge_halfedge(e);
    const Index a = tri.tail(h), b = tri.head(h);
    if (open[a] && !open[b]) y0[b] = x[b];
    if (open[b] && !open[a]) y0[a] = x[a];
  }
  return y0;
}

// The unit field: X from the sources' diffusion, then, where the heat underflowed (beyond about
// 700·√t from every source), further stages diffusing X from the frontier of the resolved
// region with the same factor, until every vertex of a reached component is resolved.
Eigen::VectorXcd unit_field(const intrinsic::IntrinsicTriangulation& tri,
                            const ComplexCholeskySolver& factor, const Eigen::VectorXcd& y,
                            const Components& comps, const std::vector<char>& reached,
                            SignedHeatReport& rep) {
  const Index nv = tri.n_vertices();
  std::vector<char> open(nv, 0);
  for (Index v = 0; v < nv; ++v) {
    const Index c = comps.label[v];
    open[v] = c != kInvalidIndex && reached[c];
  }
  Eigen::VectorXcd x = Eigen::VectorXcd::Zero(nv);
  resolve(y, comps, open, x);
  for (int stage = 1; stage < kMaxStages; ++stage) {
    const Eigen::VectorXcd y0 = frontier(tri, open, x);
    if (y0.cwiseAbs().maxCoeff() == 0.0) break;
    if (resolve(factor.solve(y0), comps, open, x) == 0) break;
    rep.stages = stage + 1;
  }
  for (Index v = 0; v < nv; ++v) rep.unresolved_vertices += open[v];
  return x;
}

// b = d₀ᵀ W α: the weak divergence whose Poisson solution fits ∇φ to X edge by edge.
Eigen::VectorXd edge_divergence(const intrinsic::IntrinsicTriangulation& tri,
                                const Eigen::VectorXd& weights, const EdgeVectors& ev,
                                const Eigen::VectorXcd& x) {
  const Eigen::VectorXd w = weights / double(tri.multiplicity());
  Eigen::VectorXd b = Eigen::VectorXd::Zero(tri.n_vertices());
  for (Index e = 0; e < tri.n_edges(); ++e) {
    const Index h = tri.edge_halfedge(e);
    const Index a = tri.tail(h), bv = tri.head(h);
    if (a == bv) continue;
    const double alpha = 0.5 * (std::real(std::conj(ev.at_tail[e]) * x[a]) +
                                std::real(std::conj(ev.at_head[e]) * x[bv]));
    b[a] -= w[e] * alpha;
    b[bv] += w[e] * alpha;
  }
  return b;
}

// The Poisson step and the level set; NaN on vertices of unreached components.
Eigen::VectorXd recover(const PoissonSolver& poisson, const Eigen::VectorXd& b,
                        const SignedHeatSources& s, const SignedHeatOptions& options,
                        const Components& comps, const std::vector<char>& reached) {
  const Index nv = static_cast<Index>(b.size());
  Eigen::VectorXd phi;
  if (options.level_set == SignedLevelSet::kZeroSet) {
    phi = poisson.solve_weak(b, Eigen::VectorXd::Zero(Eigen::Index(s.zero_set.size())));
  } else {
    phi = poisson.solve_weak(b, Eigen::VectorXd());
    std::vector<double> sum(comps.count, 0.0), weight(comps.count, 0.0);
    for (std::size_t k = 0; k < s.zero_set.size(); ++k) {
      const Index v = s.zero_set[k];
      const double wk = s.zero_weights.empty() ? 1.0 : s.zero_weights[k];
      sum[comps.label[v]] += wk * phi[v];
      weight[comps.label[v]] += wk;
    }
    for (Index v = 0; v < nv; ++v) {
      const Index c = comps.label[v];
      if (c != kInvalidIndex && weight[c] > 0.0) phi[v] -= sum[c] / weight[c];
    }
  }
  for (Index v = 0; v < nv; ++v) {
    const Index c = comps.label[v];
    if (c == kInvalidIndex || !reached[c]) phi[v] = std::numeric_limits<double>::quiet_NaN();
  }
  return phi;
}

Eigen::VectorXd run(const intrinsic::IntrinsicTriangulation& tri, const Eigen::VectorXd& weights,
                    const fem::SparseMatrix& l, const fem::ComplexSparseMatrix& connection,
                    const EdgeVectors& ev, const SignedHeatSources& s,
                    const SignedHeatOptions& options, SignedHeatReport* report) {
  SignedHeatReport rep;
  const Index nv = tri.n_vertices();
  const double h =
      options.mean_edge_length > 0.0 ? options.mean_edge_length : intrinsic::mean_edge_length(tri);
  const double t = options.time_factor * h * h;
  rep.time_step = t;
  const Components comps = connected_components(tri);
  // a component is reached when it holds a zero-set vertex and a nonzero normal
  std::vector<char> has_zero(comps.count, 0), has_normal(comps.count, 0), reached(comps.count, 0);
  for (const Index v : s.zero_set) has_zero[comps.label[v]] = 1;
  for (Index v = 0; v < nv; ++v) {
    if (comps.label[v] != kInvalidIndex && s.normals[v] != Complex(0.0))
      has_normal[comps.label[v]] = 1;
  }
  for (Index c = 0; c < comps.count; ++c) reached[c] = has_zero[c] && has_normal[c];
  for (Index v = 0; v < nv; ++v) {
    const Index c = comps.label[v];
    if (c == kInvalidIndex || !reached[c]) ++rep.unreached_vertices;
  }
  const Eigen::VectorXd mass = fem::lumped_mass(tri);
  fem::ComplexSparseMatrix a = connection * Complex(t);
  for (Index v = 0; v < nv; ++v) {
    // unreferenced vertices: a unit diagonal keeps the matrix definite (their rows are empty)
    a.coeffRef(v, v) += Complex(mass[v] > 0.0 ? mass[v] : 1.0);
  }
  a.makeCompressed();
  // the two factorizations are independent: side by side (as the vector heat method's)
  std::optional<ComplexCholeskySolver> vector_heat;
  std::optional<PoissonSolver> poisson;
  PoissonOptions po;
  po.cholesky.factor_blas_threads = 1;
  run_parallel({[&] { vector_heat.emplace(a); },
                [&] {
                  const bool zero_set = options.level_set == SignedLevelSet::kZeroSet;
                  poisson.emplace(l, mass, comps, zero_set ? s.zero_set : std::vector<Index>(), po);
                }});
  const Eigen::VectorXcd x =
      unit_field(tri, *vector_heat, vector_heat->solve(s.normals), comps, reached, rep);
  Eigen::VectorXd phi =
      recover(*poisson, edge_divergence(tri, weights, ev, x), s, options, comps, reached);
  if (report) *report = rep;
  return phi;
}

}  // namespace

const char* to_string(SignedLevelSet level_set) {
  return level_set == SignedLevelSet::kZeroSet ? "zero-set" : "mean";
}

SignedLevelSet signed_level_set_from(const std::string& name) {
  if (name == "zero-set") return SignedLevelSet::kZeroSet;
  if (name == "mean") return SignedLevelSet::kMean;
  throw InvalidInput("'" + name + "': expected 'zero-set' or 'mean'");
}

void SignedHeatOptions::validate() const {
  if (!(time_factor > 0.0) || !std::isfinite(time_factor)) {
    throw InvalidInput("SignedHeatOptions: time_factor must be > 0 and finite, got " +
                       std::to_string(time_factor));
  }
  if (!(mean_edge_length >= 0.0) || !std::isfinite(mean_edge_length)) {
    throw InvalidInput("SignedHeatOptions: mean_edge_length must be ≥ 0 and finite, got " +
                       std::to_string(mean_edge_length));
  }
}

Eigen::VectorXd signed_heat_distance(const intrinsic::IntrinsicTriangulation& tri,
                                     const SignedHeatSources& sources,
                                     const SignedHeatOptions& options, SignedHeatReport* report) {
  check_sources(tri, sources, options);
  const fem::TangentFrames frames = fem::tangent_frames(tri);
  const Eigen::VectorXd w = clamped_weights(tri);
  return run(tri, w, fem::laplacian_from_weights(tri, w), intrinsic_connection(tri, frames, w),
             intrinsic_edge_vectors(tri, frames), sources, options, report);
}

Eigen::VectorXd signed_heat_distance(const intrinsic::IntrinsicTriangulation& tri,
                                     const Positions& positions, const TangentBasis3d& basis,
                                     const SignedHeatSources& sources,
                                     const SignedHeatOptions& options, SignedHeatReport* report) {
  check_sources(tri, sources, options);
  const Index nv = tri.n_vertices();
  if (positions.rows() != nv || basis.normal.rows() != nv || basis.e1.rows() != nv ||
      basis.e2.rows() != nv) {
    throw InvalidInput("signed_heat_distance: positions (" + std::to_string(positions.rows()) +
                       " rows) and frames (" + std::to_string(basis.normal.rows()) +
                       ") must have one row per vertex (" + std::to_string(nv) + ")");
  }
  const Eigen::VectorXd w = clamped_weights(tri);
  const fem::SparseMatrix l = fem::laplacian_from_weights(tri, w);
  const fem::ComplexSparseMatrix connection =
      fem::connection_laplacian_from_frames(l, basis.normal, basis.e1, basis.e2);
  return run(tri, w, l, connection, frame_edge_vectors(tri, positions, basis), sources, options,
             report);
}

}  // namespace ifem::solvers
