// The signpost triangulation FlipOut works on, and given face points on it (input_surface.h).
#include "intrinsic/geodesic/input_surface.h"

#include <algorithm>

#include "intrinsic/core/errors.h"
#include "intrinsic/core/geometry.h"

namespace ifem::intrinsic {

bool has_positive_area(const io::SurfaceInput& in) {
  for (const Triangle& t : in.triangles) {
    double l[3];
    for (int k = 0; k < 3; ++k) {
      l[k] = side_length(in.positions.row(t[k]).data(), in.positions.row(t[(k + 1) % 3]).data());
    }
    const double scale = power_of_two_scale(std::max({l[0], l[1], l[2]}));
    if (triangle_area(l[0] / scale, l[1] / scale, l[2] / scale) > 0.0) return true;
  }
  return false;
}

SignpostTriangulation flipout_surface(const io::SurfaceInput& in, double mollify) {
  if (!has_positive_area(in)) {
    throw InvalidInput(
        "the input has no surface to compute on: zero total area (all vertices coincide, or "
        "every face is degenerate)");
  }
  try {
    return SignpostTriangulation(in.triangles, in.positions, mollify);
  } catch (const NonManifoldInput& e) {
    throw manifold_only(e, "FlipOut needs an edge-manifold, orientable surface (signposts)");
  }
}

NonManifoldInput manifold_only(const NonManifoldInput& e, const std::string& need) {
  std::string why = e.what();
  const std::size_t advice = why.find("; use the tufted cover");
  if (advice != std::string::npos) why.resize(advice);
  return NonManifoldInput(need + ", and this mesh is not: " + why);
}

std::vector<Index> given_face_map(const std::vector<Index>& input_face_origin,
                                  std::size_t n_given_faces) {
  std::vector<Index> map(n_given_faces, kInvalidIndex);
  for (std::size_t f = 0; f < input_face_origin.size(); ++f) {
    map[static_cast<std::size_t>(input_face_origin[f])] = static_cast<Index>(f);
  }
  return map;
}

SurfacePoint given_face_point(const IntrinsicTriangulation& input,
                              const std::vector<Triangle>& given_faces,
                              const std::vector<Index>& face_map, Index face,
                              const Eigen::Vector3d& w, const std::string& name) {
  const Index f = face_map[static_cast<std::size_t>(face)];
  if (f == kInvalidIndex) {
    throw InvalidInput(name + ": face " + std::to_string(face) +
                       " is not part of the surface (it repeats a vertex and was dropped)");
  }
  const Triangle& given = given_faces[static_cast<std::size_t>(face)];
  SurfacePoint sp;
  sp.face = f;
  for (int s = 0; s < 3; ++s) {
    const Index corner = input.tail(3 * f + s);
    for (int k = 0; k < 3; ++k) {
      if (given[static_cast<std::size_t>(k)] == corner) sp.bary[s] = w[k];
    }
  }
  sp.bary /= sp.bary.sum();
  return sp;
}

FlipOutReport shorten_through(SignpostTriangulation& st, const std::vector<CurveThrough>& curves,
                              std::vector<EdgePath>* paths, std::vector<double>* initial_lengths,
                              const FlipOutOptions& options) {
  paths->clear();
  initial_lengths->clear();
  for (const CurveThrough& c : curves) {
    try {
      paths->push_back(
          edge_path_through(st.intrinsic(), c.vertices, c.closed, c.pin, JoinBy::kDijkstra));
    } catch (const InvalidInput& e) {  // e.g. points on different components: say which curve
      throw InvalidInput(c.name + ": " + e.what());
    }
    initial_lengths->push_back(path_length(st.intrinsic(), paths->back()));
  }
  return shorten(st, *paths, options);
}

}  // namespace ifem::intrinsic
