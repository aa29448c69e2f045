// libFuzzer harness: NormalCoordinateTriangulation under operation sequences. The bytes choose
// a small mesh (byte 0: a closed icosphere or a flat square with boundary) and then up to 64
// operations of 4 bytes (kind, a 16-bit element index, a parameter): a flip of a non-Delaunay
// edge (Delaunay-improving flips keep the geometry sound), an insertion in a face at
// barycentric coordinates in [0.1, 0.9] before normalising, an edge split at t ∈ [0.1, 0.9].
// After every operation the integer invariants hold (validate()); then, when bit 1 of byte 0 is
// set, Delaunay refinement (angle 20°..30° from byte 1, at most 60 insertions: circumcenters
// land on input edges and on the square's boundary); at the end every edge traces and the
// common subdivision builds. Any exception is a finding: inputs are always valid here.
// Bytes starting with "ifem-integer" are a saved file instead (the "ifem-integer 1" format,
// through a temporary file): NormalCoordinateTriangulation::load validates what it reads and
// throws IoError otherwise; what it returns must pass validate(), and its edges trace, its
// common subdivision builds and its directions at input vertices are found, or throw an
// ifem::Error (any other exception, or a sanitizer report, is a finding).
#include <cstddef>
#include <cstdint>
#include <cstring>
#include <string>

#include "fuzz_common.h"
#include "intrinsic/generators/mesh_generators.h"
#include "intrinsic/integer/integer_subdivision.h"
#include "intrinsic/integer/normal_coordinates.h"
#include "intrinsic/refine/delaunay_refine.h"

namespace {

using ifem::Index;
using namespace ifem::intrinsic;

TriangleMesh small_mesh(bool square) {
  if (!square) {
    TriangleMesh m = icosphere(1);
    for (Eigen::Index i = 0; i < m.positions.rows(); ++i) m.positions(i, 2) *= 1.0 + 0.05 * (i % 3);
    return m;
  }
  TriangleMesh m = grid(3, 3, 1.0, 1.0, true);
  for (Eigen::Index i = 0; i < m.positions.rows(); ++i) {
    const double x = m.positions(i, 0), y = m.positions(i, 1);
    if (x > 0.0 && x < 1.0 && y > 0.0 && y < 1.0) m.positions(i, 0) += 0.07 * ((i % 5) - 2.0) / 2.0;
  }
  return m;
}

void apply(NormalCoordinateTriangulation& nc, const std::uint8_t* op) {
  const IntrinsicTriangulation& tri = nc.intrinsic();
  const Index idx = static_cast<Index>(op[1] | (op[2] << 8));
  const double u = 0.1 + 0.8 * op[3] / 255.0;
  switch (op[0] % 3) {
    case 0: {
      const Index e = idx % tri.n_edges();
      if (!tri.is_delaunay(e)) nc.flip_edge(e);
      break;
    }
    case 1: {
      const Index f = idx % tri.n_faces();
      Eigen::Vector3d bary(u, 0.1 + 0.8 * ((op[3] * 37) % 256) / 255.0, 0.5);
      nc.insert_vertex(f, bary / bary.sum());
      break;
    }
    default: {
      const Index e = idx % tri.n_edges();
      if (tri.can_split_edge(e)) nc.split_edge(e, u);
    }
  }
}

void fuzz_load(const std::uint8_t* data, std::size_t size) {
  const std::string& path = ifem::fuzz::write_temporary(".integer", data, size);
  ifem::fuzz::run_expecting_errors([&] {
    const NormalCoordinateTriangulation nc = NormalCoordinateTriangulation::load(path);
    try {
      nc.validate();
    } catch (const std::exception& e) {
      ifem::fuzz::fail(std::string("a loaded file fails validate(): ") + e.what());
    }
    const IntrinsicTriangulation& tri = nc.intrinsic();
    for (Index e = 0; e < tri.n_edges(); ++e) (void)nc.trace_edge(e);
    for (Index h = 0; h < tri.n_halfedges(); ++h) {
      if (tri.tail(h) < nc.n_input_vertices()) (void)nc.halfedge_direction_3d(h);
    }
    (void)common_subdivision(nc);
  });
}

int fuzz_one(const std::uint8_t* data, std::size_t size) {
  constexpr char kSaved[] = "ifem-integer";
  if (size >= sizeof kSaved - 1 && std::memcmp(data, kSaved, sizeof kSaved - 1) == 0) {
    fuzz_load(data, size);
    return 0;
  }
  if (size < 1) return 0;
  const TriangleMesh m = small_mesh(data[0] % 2 == 1);
  try {
    NormalCoordinateTriangulation nc(m.faces, m.positions);
    for (std::size_t k = 1; k + 4 <= size && k < 1 + 4 * 64; k += 4) {
      apply(nc, data + k);
      nc.validate();
    }
    if ((data[0] & 2) != 0 && size >= 2) {
      RefineOptions o;
      o.min_angle_degrees = 20.0 + 10.0 * data[1] / 255.0;
      o.max_insertions = 60;
      delaunay_refine(nc, o);
      nc.validate();
    }
    for (Index e = 0; e < nc.intrinsic().n_edges(); ++e) (void)nc.trace_edge(e);
    (void)common_subdivision(nc);
  } catch (const std::exception& e) {
    ifem::fuzz::fail(std::string("integer coordinates: ") + e.what());
  }
  return 0;
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  return fuzz_one(data, size);
}
