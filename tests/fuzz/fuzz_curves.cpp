// libFuzzer harness: a curves file (solvers::read_curves_file, path-based: the bytes go through a
// temporary file), checked against a small jittered grid (validate_curves) and, when it fits,
// the whole curves path on it: FlipOut insertion, constrained Delaunay flips, constrained
// refinement, curve_poisson and curve_distance. Reading or solving may throw an ifem::Error;
// anything else (a crash, a sanitizer report, a non-finite value solved without an error) fails.
#include <cmath>
#include <cstddef>
#include <cstdint>

#include "fuzz_common.h"
#include "intrinsic/generators/mesh_generators.h"
#include "solvers/recipes/curves.h"

namespace {

// 6×6 cells, 49 vertices, interior vertices moved so that curves cross triangles.
ifem::io::SurfaceInput grid_input() {
  const ifem::intrinsic::TriangleMesh m = ifem::intrinsic::grid(6, 6);
  ifem::io::SurfaceInput in;
  in.positions = m.positions;
  in.triangles = m.faces;
  for (ifem::Index v = 0; v < in.positions.rows(); ++v) {
    const int i = v % 7, j = v / 7;
    if (i > 0 && i < 6 && j > 0 && j < 6) in.positions(v, 0) += 0.03 * std::sin(3.0 * v);
  }
  return in;
}

void solve(std::vector<ifem::solvers::CurveCondition> curves) {
  static const ifem::io::SurfaceInput input = grid_input();
  ifem::solvers::CurveSurfaceOptions opt;
  opt.refine = ifem::solvers::SurfaceRefineOptions{};
  opt.refine->max_insertions = 2000;
  const ifem::solvers::CurveSurface s =
      ifem::solvers::prepare_curve_surface(input, std::move(curves), opt);
  const Eigen::VectorXd d = ifem::solvers::curve_distance(s);
  if (d.hasNaN()) ifem::fuzz::fail("curve_distance returned NaN");
  bool values = true;
  for (const auto& c : s.curves) values = values && !c.values.empty();
  if (!values) return;
  const ifem::solvers::CurvePoissonResult r = ifem::solvers::curve_poisson(s, Eigen::VectorXd());
  if (!r.u.allFinite()) ifem::fuzz::fail("curve_poisson returned a non-finite value");
}

int fuzz_one(const std::uint8_t* data, std::size_t size) {
  const std::string& path = ifem::fuzz::write_temporary(".txt", data, size);
  ifem::fuzz::run_expecting_errors([&] {
    std::vector<ifem::solvers::CurveCondition> curves = ifem::solvers::read_curves_file(path);
    if (curves.size() > 8) return;  // keep one input cheap
    for (const ifem::solvers::CurveCondition& c : curves) {
      // a Bézier curve of d + 1 control points has d·2^rounds + 1 points: at most 1025 here
      const bool bezier = c.shape == ifem::intrinsic::CurveShape::kBezier;
      if (bezier && (c.vertices.size() - 1) << c.bezier_rounds > 1024) return;
    }
    solve(std::move(curves));
  });
  return 0;
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  return fuzz_one(data, size);
}
