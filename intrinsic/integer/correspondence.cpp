// The correspondence view over signposts or integer coordinates, and loading either file.
#include "intrinsic/integer/correspondence.h"

#include <algorithm>
#include <cmath>
#include <complex>
#include <fstream>
#include <limits>
#include <sstream>
#include <tuple>

#include "intrinsic/core/errors.h"
#include "intrinsic/core/first_error.h"
#include "intrinsic/core/geometry.h"
#include "intrinsic/integer/integer_subdivision.h"

namespace ifem::intrinsic {

const char* to_string(Correspondence c) {
  return c == Correspondence::kSignposts ? "signposts" : "integer";
}

Correspondence parse_correspondence(const std::string& word) {
  if (word == "signposts") return Correspondence::kSignposts;
  if (word == "integer") return Correspondence::kInteger;
  throw InvalidInput("correspondence: '" + word +
                     "' is neither 'signposts' nor 'integer' (the two ways an intrinsic "
                     "triangulation keeps its places on the input)");
}

const char* file_format(Correspondence c) {
  return c == Correspondence::kSignposts ? "ifem-signpost 1" : "ifem-integer 1";
}

const IntrinsicTriangulation& CorrespondenceView::intrinsic() const {
  return st_ ? st_->intrinsic() : nc_->intrinsic();
}

const IntrinsicTriangulation& CorrespondenceView::input() const {
  return st_ ? st_->input() : nc_->input();
}

const Positions& CorrespondenceView::input_positions() const {
  return st_ ? st_->input_positions() : nc_->input_positions();
}

std::vector<SurfacePoint> CorrespondenceView::vertex_locations() const {
  if (nc_) return intrinsic::vertex_locations(*nc_);
  std::vector<SurfacePoint> out(st_->intrinsic().n_vertices());
  for (Index v = 0; v < Index(out.size()); ++v) out[v] = st_->vertex_location(v);
  return out;
}

Positions CorrespondenceView::vertex_positions() const {
  if (st_) return st_->vertex_positions();
  const Positions& x = nc_->input_positions();
  const Index n_in = n_input_vertices();
  const Index nv = nc_->intrinsic().n_vertices();
  Positions out(nv, 3);
  out.topRows(n_in) = x.topRows(n_in);
  if (nv == n_in) return out;
  const std::vector<SurfacePoint> at = vertex_locations();
  for (Index v = n_in; v < nv; ++v) out.row(v) = point_position(nc_->input(), x, at[v]).transpose();
  return out;
}

Eigen::VectorXd CorrespondenceView::input_to_intrinsic(const Eigen::VectorXd& values) const {
  if (st_) return st_->input_to_intrinsic(values);
  const Index n_in = n_input_vertices();
  const Index nv = nc_->intrinsic().n_vertices();
  if (values.size() != n_in) {
    throw InvalidInput("input_to_intrinsic: " + std::to_string(values.size()) + " values for " +
                       std::to_string(n_in) + " input vertices");
  }
  Eigen::VectorXd out(nv);
  out.head(n_in) = values;
  if (nv == n_in) return out;
  const std::vector<SurfacePoint> at = vertex_locations();
  for (Index v = n_in; v < nv; ++v) out[v] = interpolate_at(nc_->input(), values, at[v]);
  return out;
}

CommonSubdivision CorrespondenceView::common_subdivision(double max_memory_bytes) const {
  if (st_) return intrinsic::common_subdivision(*st_, max_memory_bytes);
  return intrinsic::common_subdivision(*nc_);
}

Eigen::Vector3d CorrespondenceView::halfedge_direction_3d(Index h) const {
  return st_ ? st_->halfedge_direction_3d(h) : nc_->halfedge_direction_3d(h);
}

std::vector<std::vector<Eigen::Vector3d>> CorrespondenceView::traced_edges_3d() const {
  if (st_) return st_->traced_edges_3d();
  const IntrinsicTriangulation& tri = nc_->intrinsic();
  const Positions x = vertex_positions();
  const Index n_in = n_input_vertices();
  std::vector<std::vector<Eigen::Vector3d>> out(tri.n_edges());
  FirstError failure;  // transport out of the OpenMP loop: any exception ends the call
#pragma omp parallel for schedule(dynamic, 256)
  for (Index e = 0; e < tri.n_edges(); ++e) {
    if (failure.failed()) continue;
    try {
      Index h = tri.edge_halfedge(e);  // from an input vertex when one end is (as signposts)
      if (tri.tail(h) >= n_in && tri.head(h) < n_in && tri.twin(h) != kInvalidIndex) {
        h = tri.twin(h);
      }
      const std::vector<InputCrossing> crossings = nc_->trace_halfedge(h);
      auto& line = out[e];
      line.reserve(crossings.size() + 2);
      line.push_back(x.row(tri.tail(h)).transpose());
      for (const InputCrossing& c : crossings) line.push_back(nc_->crossing_position(c));
      line.push_back(x.row(tri.head(h)).transpose());
    } catch (...) {
      failure.record_current("edge " + std::to_string(e));
    }
  }
  failure.rethrow_if_any("traced_edges_3d");
  return out;
}

void CorrespondenceView::save(const std::string& path) const {
  if (st_) {
    st_->save(path);
  } else {
    nc_->save(path);
  }
}

// ===== Point location =====

namespace {

using Mat3 = Eigen::Matrix3d;
using Vec2 = Eigen::Vector2d;
using T = IntrinsicTriangulation;

// Barycentric coordinates of x in the 3D triangle (a, b, c), least squares in its plane; the
// centroid for a degenerate triangle.
Eigen::Vector3d bary_3d(const Eigen::Vector3d& x, const Eigen::Vector3d& a,
                        const Eigen::Vector3d& b, const Eigen::Vector3d& c) {
  const Eigen::Vector3d e1 = b - a, e2 = c - a, d = x - a;
  const double g11 = e1.dot(e1), g12 = e1.dot(e2), g22 = e2.dot(e2);
  const double det = g11 * g22 - g12 * g12;
  if (!(det > 0.0)) return Eigen::Vector3d::Constant(1.0 / 3.0);
  const double r1 = d.dot(e1), r2 = d.dot(e2);
  const double s = (g22 * r1 - g12 * r2) / det, t = (g11 * r2 - g12 * r1) / det;
  return {1.0 - s - t, s, t};
}

// The determinant of a 3×3 matrix (a piece's share of its face, from barycentric columns).
double det3(const Mat3& a) {
  return a(0, 0) * (a(1, 1) * a(2, 2) - a(1, 2) * a(2, 1)) -
         a(0, 1) * (a(1, 0) * a(2, 2) - a(1, 2) * a(2, 0)) +
         a(0, 2) * (a(1, 0) * a(2, 1) - a(1, 1) * a(2, 0));
}

// Barycentric coordinates of x in the 2D triangle c[0..2]; the centroid when degenerate.
Eigen::Vector3d bary_2d(const Vec2& x, const Vec2 c[3]) {
  const Vec2 e1 = c[1] - c[0], e2 = c[2] - c[0], d = x - c[0];
  const double det = e1.x() * e2.y() - e1.y() * e2.x();
  if (det == 0.0) return Eigen::Vector3d::Constant(1.0 / 3.0);
  const double s = (d.x() * e2.y() - d.y() * e2.x()) / det;
  const double t = (e1.x() * d.y() - e1.y() * d.x()) / det;
  return {1.0 - s - t, s, t};
}

// For each face id given to the subdivision, the face of input() it became (kInvalidIndex if
// dropped): the inverse of input_face_origin() (identity when that is empty).
std::vector<Index> given_to_input(const std::vector<Index>& origin, Index n_input_faces,
                                  const CommonSubdivision& cs) {
  Index n_given = n_input_faces;
  for (Index g : cs.input_face) n_given = std::max(n_given, g + 1);
  for (Index g : origin) n_given = std::max(n_given, g + 1);
  std::vector<Index> out(std::size_t(n_given), kInvalidIndex);
  for (Index f = 0; f < n_input_faces; ++f) {
    out[std::size_t(origin.empty() ? f : origin[std::size_t(f)])] = f;
  }
  return out;
}

// The pieces grouped by face (counting sort), for faces 0 .. n_faces − 1.
void group_by_face(const std::vector<Index>& face_of, Index n_faces, PointLocator::FaceIndex& idx) {
  idx.begin.assign(std::size_t(n_faces) + 1, 0);
  for (Index f : face_of) ++idx.begin[std::size_t(f) + 1];
  for (Index f = 0; f < n_faces; ++f) idx.begin[f + 1] += idx.begin[f];
  idx.pieces.resize(face_of.size());
  std::vector<Index> next(idx.begin.begin(), idx.begin.end() - 1);
  for (Index p = 0; p < Index(face_of.size()); ++p) {
    idx.pieces[std::size_t(next[std::size_t(face_of[std::size_t(p)])]++)] = p;
  }
}

constexpr Index kGridFrom = 24;  // faces with more pieces get a grid

// The cells (cx, cy) of an n × n grid over the barycentric square (b1, b2) ∈ [0, 1]² that the
// bounding box of piece corners `at` (columns) touches, each passed to emit(cell).
template <class Emit>
void piece_cells(const Mat3& at, int n, Emit&& emit) {
  const double pad = 1e-9;
  auto cell = [n](double x) { return std::clamp(int(std::floor(x * n)), 0, n - 1); };
  const int x0 = cell(at.row(1).minCoeff() - pad), x1 = cell(at.row(1).maxCoeff() + pad);
  const int y0 = cell(at.row(2).minCoeff() - pad), y1 = cell(at.row(2).maxCoeff() + pad);
  for (int y = y0; y <= y1; ++y) {
    for (int x = x0; x <= x1; ++x) emit(y * n + x);
  }
}

// Grids for the faces of idx with at least kGridFrom pieces (about 2 pieces per cell).
void build_grids(const std::vector<Mat3>& at, PointLocator::FaceIndex& idx) {
  const Index nf = Index(idx.begin.size()) - 1;
  idx.grid_size.assign(std::size_t(nf), 0);
  idx.grid_offset.assign(std::size_t(nf) + 1, 0);
  for (Index f = 0; f < nf; ++f) {
    const Index m = idx.begin[f + 1] - idx.begin[f];
    const int n = m >= kGridFrom ? std::min(256, int(std::ceil(std::sqrt(m / 2.0)))) : 0;
    idx.grid_size[std::size_t(f)] = n;
    idx.grid_offset[f + 1] = idx.grid_offset[f] + Index(n) * n;
  }
  std::vector<std::pair<Index, Index>> entries;  // (cell, piece)
  for (Index f = 0; f < nf; ++f) {
    const int n = idx.grid_size[std::size_t(f)];
    if (n == 0) continue;
    for (Index i = idx.begin[f]; i < idx.begin[f + 1]; ++i) {
      const Index p = idx.pieces[std::size_t(i)];
      piece_cells(at[std::size_t(p)], n,
                  [&](int c) { entries.emplace_back(idx.grid_offset[f] + c, p); });
    }
  }
  std::sort(entries.begin(), entries.end());
  idx.cell_begin.assign(std::size_t(idx.grid_offset[nf]) + 1, 0);
  idx.cell_pieces.resize(entries.size());
  for (std::size_t i = 0; i < entries.size(); ++i) {
    ++idx.cell_begin[std::size_t(entries[i].first) + 1];
    idx.cell_pieces[i] = entries[i].second;
  }
  for (std::size_t c = 0; c + 1 < idx.cell_begin.size(); ++c) {
    idx.cell_begin[c + 1] += idx.cell_begin[c];
  }
}

// Coordinates λ of barycentric point b in the piece with corners `at` (columns), in the
// barycentric plane; all −∞ for a degenerate piece.
Eigen::Vector3d piece_coordinates(const Mat3& at, const Eigen::Vector3d& b) {
  const Vec2 c[3] = {{at(1, 0), at(2, 0)}, {at(1, 1), at(2, 1)}, {at(1, 2), at(2, 2)}};
  const Vec2 e1 = c[1] - c[0], e2 = c[2] - c[0];
  if (e1.x() * e2.y() - e1.y() * e2.x() == 0.0) {
    return Eigen::Vector3d::Constant(-std::numeric_limits<double>::infinity());
  }
  return bary_2d(Vec2(b[1], b[2]), c);
}

// The piece of `face` holding b (the largest smallest coordinate) and b's coordinates in it.
std::pair<Index, Eigen::Vector3d> find_piece(const PointLocator::FaceIndex& idx,
                                             const std::vector<Mat3>& at, Index face,
                                             const Eigen::Vector3d& b) {
  std::pair<Index, Eigen::Vector3d> best{kInvalidIndex, Eigen::Vector3d::Zero()};
  double best_min = -std::numeric_limits<double>::infinity();
  auto scan = [&](const Index* first, const Index* last) {
    for (const Index* it = first; it != last && best_min < 0.0; ++it) {
      const Eigen::Vector3d l = piece_coordinates(at[std::size_t(*it)], b);
      if (l.minCoeff() > best_min || best.first == kInvalidIndex) {
        best_min = l.minCoeff();
        best = {*it, l};
      }
    }
  };
  const int n = idx.grid_size.empty() ? 0 : idx.grid_size[std::size_t(face)];
  if (n > 0) {
    const int cx = std::clamp(int(std::floor(b[1] * n)), 0, n - 1);
    const int cy = std::clamp(int(std::floor(b[2] * n)), 0, n - 1);
    const Index c = idx.grid_offset[face] + cy * n + cx;
    scan(idx.cell_pieces.data() + idx.cell_begin[std::size_t(c)],
         idx.cell_pieces.data() + idx.cell_begin[std::size_t(c) + 1]);
    if (best_min >= -1e-12) return best;
  }
  scan(idx.pieces.data() + idx.begin[face], idx.pieces.data() + idx.begin[face + 1]);
  return best;
}

// Throws InvalidInput when p is not a point of a face of a triangulation with nf faces.
void check_point(const SurfacePoint& p, Index nf, const char* side) {
  const bool face_ok = p.face >= 0 && p.face < nf;
  if (face_ok && p.bary.allFinite() && p.bary.minCoeff() >= -1e-9 &&
      std::abs(p.bary.sum() - 1.0) <= 1e-9) {
    return;
  }
  std::ostringstream m;  // only on the way out: a stream per point would cost more than locating
  if (!face_ok) {
    m << "face " << p.face << " is not a face of the " << side << " triangulation (" << nf
      << " faces)";
  } else {
    m << "barycentric coordinates (" << p.bary.transpose()
      << ") are not finite, ≥ 0 and summing to 1 (within 1e-9)";
  }
  throw InvalidInput(m.str());
}

// Locates every point of `points` (faces of one side, idx / from) in the other side (to).
std::vector<SurfacePoint> locate(const std::vector<SurfacePoint>& points,
                                 const PointLocator::FaceIndex& idx, const std::vector<Mat3>& from,
                                 const std::vector<Mat3>& to, const std::vector<Index>& to_face,
                                 const char* side, const char* context) {
  const Index nf = Index(idx.begin.size()) - 1;
  std::vector<SurfacePoint> out(points.size());
  FirstError failure;
#pragma omp parallel for schedule(static, 1024) if (points.size() > 4096)
  for (std::ptrdiff_t i = 0; i < std::ptrdiff_t(points.size()); ++i) {
    if (failure.failed()) continue;
    try {
      const SurfacePoint& p = points[std::size_t(i)];
      check_point(p, nf, side);
      const auto [piece, l] = find_piece(idx, from, p.face, p.bary);
      if (piece == kInvalidIndex || !(l.minCoeff() >= -1e-9)) {
        std::ostringstream m;
        m << "lies in no piece of the common subdivision of its face (" << side << " face "
          << p.face << ", the nearest is " << (piece == kInvalidIndex ? 0.0 : -l.minCoeff())
          << " outside in barycentric terms): the subdivision does not cover the face";
        throw InvalidInput(m.str());
      }
      Eigen::Vector3d lam = l.cwiseMax(0.0);
      lam /= lam.sum();
      Eigen::Vector3d b = (to[std::size_t(piece)] * lam).cwiseMax(0.0);
      out[std::size_t(i)] = {to_face[std::size_t(piece)], b / b.sum()};
    } catch (...) {
      failure.record_current("point " + std::to_string(i));
    }
  }
  failure.rethrow_if_any(context);
  return out;
}

}  // namespace

namespace {

using Layout = std::array<Vec2, 3>;

// Piece p's corners in the layout of its input face (face_layout() of input()).
Layout own_layout(const IntrinsicTriangulation& in, Index g, const Mat3& at) {
  Vec2 corner[3];
  face_layout(in, g, corner);
  Layout out;
  for (int j = 0; j < 3; ++j)
    out[j] = at(0, j) * corner[0] + at(1, j) * corner[1] + at(2, j) * corner[2];
  return out;
}

// The pieces `ids` (all of one intrinsic face) laid out in one plane: each from its input face's
// layout, moved rigidly across the sides it shares with pieces already placed (breadth first
// from the first). False when some piece shares no side with the others.
bool unfold(const IntrinsicTriangulation& in, const CommonSubdivision& cs,
            const std::vector<Index>& input_face, const std::vector<Mat3>& at_input,
            const Index* ids, Index m, std::vector<Layout>& placed) {
  placed.resize(std::size_t(m));
  std::vector<std::tuple<Index, Index, Index, int>> sides;  // (low id, high id, piece, corner)
  sides.reserve(3 * std::size_t(m));
  for (Index i = 0; i < m; ++i) {
    const Triangle& t = cs.faces[std::size_t(ids[i])];
    for (int j = 0; j < 3; ++j) {
      sides.emplace_back(std::min(t[j], t[(j + 1) % 3]), std::max(t[j], t[(j + 1) % 3]), i, j);
    }
  }
  std::sort(sides.begin(), sides.end());
  std::vector<char> done(std::size_t(m), 0);
  std::vector<Index> queue{0};
  placed[0] = own_layout(in, input_face[std::size_t(ids[0])], at_input[std::size_t(ids[0])]);
  done[0] = 1;
  for (std::size_t head = 0; head < queue.size(); ++head) {
    const Index i = queue[head];
    const Triangle& t = cs.faces[std::size_t(ids[i])];
    for (int j = 0; j < 3; ++j) {
      const Index a = t[j], b = t[(j + 1) % 3];
      auto it = std::lower_bound(sides.begin(), sides.end(),
                                 std::make_tuple(std::min(a, b), std::max(a, b), Index(-1), 0));
      for (; it != sides.end() && std::get<0>(*it) == std::min(a, b) &&
             std::get<1>(*it) == std::max(a, b);
           ++it) {
        const Index k = std::get<2>(*it);
        if (done[std::size_t(k)]) continue;
        // k's side runs b → a (opposite orientation): its corner c is b, c + 1 is a
        const int c = std::get<3>(*it);
        const Index pk = ids[k];
        const Layout own = own_layout(in, input_face[std::size_t(pk)], at_input[std::size_t(pk)]);
        const Vec2 &pa = placed[std::size_t(i)][j], &pb = placed[std::size_t(i)][(j + 1) % 3];
        const bool flipped = cs.faces[std::size_t(pk)][c] == b;
        const Vec2 qb = own[flipped ? c : (c + 1) % 3], qa = own[flipped ? (c + 1) % 3 : c];
        std::complex<double> rot =
            std::complex<double>(pb.x() - pa.x(), pb.y() - pa.y()) *
            std::conj(std::complex<double>(qb.x() - qa.x(), qb.y() - qa.y()));
        rot = std::abs(rot) > 0.0 ? rot / std::abs(rot) : 1.0;
        for (int r = 0; r < 3; ++r) {
          const std::complex<double> z =
              rot * std::complex<double>(own[r].x() - qa.x(), own[r].y() - qa.y());
          placed[std::size_t(k)][r] = pa + Vec2(z.real(), z.imag());
        }
        placed[std::size_t(k)][flipped ? (c + 1) % 3 : c] = pa;
        placed[std::size_t(k)][flipped ? c : (c + 1) % 3] = pb;
        done[std::size_t(k)] = 1;
        queue.push_back(k);
      }
    }
  }
  return Index(queue.size()) == m;
}

// Where the corners of intrinsic face f lie in the layout `placed` of its pieces: among the
// piece corners that are f's corner vertices, the three places whose distances best match f's
// side lengths (one candidate each unless f repeats a vertex).
std::array<Vec2, 3> face_corners(const IntrinsicTriangulation& tri, Index f,
                                 const CommonSubdivision& cs, const Index* ids, Index m,
                                 const std::vector<Layout>& placed) {
  std::array<std::vector<Vec2>, 3> cand;
  const double tol = 1e-9 * std::max({tri.halfedge_length(3 * f), tri.halfedge_length(3 * f + 1),
                                      tri.halfedge_length(3 * f + 2)});
  for (Index i = 0; i < m; ++i) {
    for (int j = 0; j < 3; ++j) {
      for (int k = 0; k < 3; ++k) {
        if (cs.faces[std::size_t(ids[i])][j] != tri.tail(3 * f + k)) continue;
        const Vec2& x = placed[std::size_t(i)][j];
        auto& list = cand[k];
        if (std::none_of(list.begin(), list.end(),
                         [&](const Vec2& y) { return (x - y).norm() <= tol; })) {
          list.push_back(x);
        }
      }
    }
  }
  for (int k = 0; k < 3; ++k) {
    if (cand[k].empty()) {
      throw InvalidInput("intrinsic face " + std::to_string(f) + ": corner vertex " +
                         std::to_string(tri.tail(3 * f + k)) + " is in none of its pieces");
    }
  }
  std::array<Vec2, 3> best{};
  double best_err = std::numeric_limits<double>::infinity();
  for (const Vec2& a : cand[0]) {
    for (const Vec2& b : cand[1]) {
      for (const Vec2& c : cand[2]) {
        const Vec2 e1 = b - a, e2 = c - a;
        const double err = std::abs((b - a).norm() - tri.halfedge_length(3 * f)) +
                           std::abs((c - b).norm() - tri.halfedge_length(3 * f + 1)) +
                           std::abs((a - c).norm() - tri.halfedge_length(3 * f + 2)) +
                           (e1.x() * e2.y() - e1.y() * e2.x() < 0.0 ? 1e300 : 0.0);
        if (err < best_err) best_err = err, best = {a, b, c};
      }
    }
  }
  return best;
}

// Barycentric coordinates in intrinsic face f of the corners of its pieces `ids`, from their
// unfolded layout (unit vectors at f's corners).
void intrinsic_coordinates(const IntrinsicTriangulation& tri, const IntrinsicTriangulation& in,
                           Index f, const CommonSubdivision& cs,
                           const std::vector<Index>& input_face, const std::vector<Mat3>& at_input,
                           const Index* ids, Index m, std::vector<Mat3>& at_intrinsic) {
  if (m == 0) return;
  std::vector<Layout> placed;
  if (!unfold(in, cs, input_face, at_input, ids, m, placed)) {
    throw InvalidInput("intrinsic face " + std::to_string(f) +
                       ": its pieces of the common subdivision do not form one region");
  }
  const std::array<Vec2, 3> corner = face_corners(tri, f, cs, ids, m, placed);
  const Vec2 c[3] = {corner[0], corner[1], corner[2]};
  const double tol = 1e-7 * (c[1] - c[0]).norm();
  for (Index i = 0; i < m; ++i) {
    Mat3& out = at_intrinsic[std::size_t(ids[i])];
    for (int j = 0; j < 3; ++j) {
      const Vec2& x = placed[std::size_t(i)][j];
      out.col(j) = bary_2d(x, c);
      for (int k = 0; k < 3; ++k) {
        if (cs.faces[std::size_t(ids[i])][j] == tri.tail(3 * f + k) && (x - c[k]).norm() <= tol) {
          out.col(j) = Eigen::Vector3d::Unit(k);
        }
      }
    }
  }
}

}  // namespace

// Long function: the constructor's four steps (input side, grouping, intrinsic side, grids)
PointLocator::PointLocator(const CorrespondenceView& view, double max_memory_bytes) {
  const CommonSubdivision cs = view.common_subdivision(max_memory_bytes);
  const IntrinsicTriangulation& in = view.input();
  const IntrinsicTriangulation& tri = view.intrinsic();
  const Positions& x = view.input_positions();
  const std::vector<Index>& origin = view.signposts() ? view.signposts()->input_face_origin()
                                                      : view.integer()->input_face_origin();
  const std::vector<Index> to_input = given_to_input(origin, in.n_faces(), cs);
  const Index np = Index(cs.faces.size()), n_in = view.n_input_vertices();
  intrinsic_face_ = cs.intrinsic_face;
  input_face_.resize(std::size_t(np));
  at_input_.resize(std::size_t(np));
  at_intrinsic_.resize(std::size_t(np));
  area_.resize(std::size_t(np));
  // ---- input side: from the 3D positions in the input face (exact at input vertices)
  for (Index p = 0; p < np; ++p) {
    const Index g = to_input[std::size_t(cs.input_face[std::size_t(p)])];
    if (g == kInvalidIndex) {
      throw InvalidInput("PointLocator: piece " + std::to_string(p) +
                         " lies in an input face that was dropped");
    }
    input_face_[std::size_t(p)] = g;
    const Eigen::Vector3d a = x.row(in.tail(3 * g)), b = x.row(in.tail(3 * g + 1)),
                          c = x.row(in.tail(3 * g + 2));
    Mat3& at = at_input_[std::size_t(p)];
    for (int j = 0; j < 3; ++j) {
      const Index v = cs.faces[std::size_t(p)][j];
      at.col(j) = bary_3d(cs.positions.row(v).transpose(), a, b, c);
      for (int k = 0; k < 3 && v < n_in; ++k) {
        if (in.tail(3 * g + k) == v) at.col(j) = Eigen::Vector3d::Unit(k);
      }
    }
    area_[std::size_t(p)] = face_area(in, g) * std::abs(det3(at));
  }
  group_by_face(input_face_, in.n_faces(), by_input_);
  group_by_face(intrinsic_face_, tri.n_faces(), by_intrinsic_);
  // ---- intrinsic side: unfold each intrinsic face's pieces
  FirstError failure;
#pragma omp parallel for schedule(dynamic, 256)
  for (Index f = 0; f < tri.n_faces(); ++f) {
    if (failure.failed()) continue;
    try {
      const Index b = by_intrinsic_.begin[std::size_t(f)];
      intrinsic_coordinates(tri, in, f, cs, input_face_, at_input_, by_intrinsic_.pieces.data() + b,
                            by_intrinsic_.begin[std::size_t(f) + 1] - b, at_intrinsic_);
    } catch (...) {
      failure.record_current("intrinsic face " + std::to_string(f));
    }
  }
  failure.rethrow_if_any("PointLocator");
  build_grids(at_input_, by_input_);
  build_grids(at_intrinsic_, by_intrinsic_);
}

std::vector<SurfacePoint> PointLocator::input_to_intrinsic(
    const std::vector<SurfacePoint>& points) const {
  return locate(points, by_input_, at_input_, at_intrinsic_, intrinsic_face_, "input",
                "input_to_intrinsic");
}

std::vector<SurfacePoint> PointLocator::intrinsic_to_input(
    const std::vector<SurfacePoint>& points) const {
  return locate(points, by_intrinsic_, at_intrinsic_, at_input_, input_face_, "intrinsic",
                "intrinsic_to_input");
}

SavedTriangulation load_triangulation(const std::string& path) {
  std::ifstream in(path);
  if (!in) throw IoError(path + ": cannot open the file");
  std::string word;
  in >> word;
  SavedTriangulation out;
  if (word == "ifem-signpost") {
    out.signposts.emplace(SignpostTriangulation::load(path));
  } else if (word == "ifem-integer") {
    out.integer.emplace(NormalCoordinateTriangulation::load(path));
  } else {
    throw IoError(path +
                  ": not a saved intrinsic triangulation (its first line should be "
                  "'ifem-signpost 1' or 'ifem-integer 1', as `ifem refine --save` writes)");
  }
  return out;
}

}  // namespace ifem::intrinsic
