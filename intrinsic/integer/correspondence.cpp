// The correspondence view over signposts or integer coordinates, and loading either file.
#include "intrinsic/integer/correspondence.h"

#include <fstream>

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
