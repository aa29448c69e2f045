#include "intrinsic/integer/replay.h"

#include "intrinsic/core/errors.h"

namespace ifem::intrinsic {

NormalCoordinateTriangulation replay_on_integer(const SignpostTriangulation& st) {
  NormalCoordinateTriangulation nc(st.input_faces(), st.input_positions(), st.mollify_epsilon());
  using Kind = SignpostTriangulation::Operation::Kind;
  for (const SignpostTriangulation::Operation& op : st.operation_log()) {
    switch (op.kind) {
      case Kind::kFlip:
        if (!nc.flip_edge(op.index)) {
          throw InvalidInput("integer coordinates: replaying the signposts' operations, edge " +
                             std::to_string(op.index) + " cannot be flipped");
        }
        break;
      case Kind::kInsertVertex:
        nc.insert_vertex(op.index, op.bary);
        break;
      case Kind::kSplitEdge:
        nc.split_edge(op.index, op.t);
        break;
    }
  }
  require_same_gluing(nc.intrinsic(), st.intrinsic(),
                      "integer coordinates replaying the signposts' operations");
  return nc;
}

void require_same_gluing(const IntrinsicTriangulation& a, const IntrinsicTriangulation& b,
                         const std::string& what) {
  auto fail = [&](const std::string& detail) {
    throw InvalidInput(what + ": the triangulations differ (" + detail + ")");
  };
  if (a.n_vertices() != b.n_vertices() || a.n_halfedges() != b.n_halfedges() ||
      a.n_edges() != b.n_edges()) {
    fail(std::to_string(a.n_vertices()) + " vs " + std::to_string(b.n_vertices()) + " vertices, " +
         std::to_string(a.n_halfedges()) + " vs " + std::to_string(b.n_halfedges()) + " halfedges");
  }
  for (Index h = 0; h < a.n_halfedges(); ++h) {
    if (a.tail(h) != b.tail(h)) fail("tail of halfedge " + std::to_string(h));
    if (a.twin(h) != b.twin(h)) fail("twin of halfedge " + std::to_string(h));
    if (a.edge(h) != b.edge(h)) fail("edge of halfedge " + std::to_string(h));
    if (a.halfedge_length(h) != b.halfedge_length(h)) {
      fail("length of halfedge " + std::to_string(h));
    }
  }
  for (Index e = 0; e < a.n_edges(); ++e) {
    if (a.edge_halfedge(e) != b.edge_halfedge(e)) fail("halfedge of edge " + std::to_string(e));
  }
}

}  // namespace ifem::intrinsic
