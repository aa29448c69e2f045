// validate() of the solvers' options (docs/decisions.md, "Every options struct has
// validate()"): defaults pass, out-of-range fields throw InvalidInput naming the field, and the
// solvers reject bad options at their entry.
#include <gtest/gtest.h>

#include <limits>
#include <string>

#include "fem/operators.h"
#include "helpers.h"
#include "intrinsic/core/errors.h"
#include "intrinsic/generators/mesh_generators.h"
#include "solvers/linalg/cholesky.h"
#include "solvers/scalar/eigen.h"
#include "solvers/scalar/heat_distance.h"
#include "solvers/scalar/poisson.h"

namespace ifem::solvers {
namespace {

constexpr double kNan = std::numeric_limits<double>::quiet_NaN();

using test::expect_each_rejected;
using test::expect_rejected;

TEST(OptionsValidate, HeatDistanceOptions) {
  HeatDistanceOptions{}.validate();
  RefinedDistanceOptions{}.heat_options(0.1).validate();
  expect_each_rejected(&HeatDistanceOptions::time_factor, {0.0}, "time_factor");
  expect_each_rejected(&HeatDistanceOptions::mean_edge_length, {-1.0}, "mean_edge_length");
  HeatDistanceOptions c;
  c.resolved_heat = 1e-100;
  c.trusted_heat = 1e-200;  // below resolved_heat
  expect_rejected(c, "trusted_heat");
  expect_each_rejected(&HeatDistanceOptions::correction_steps, {-1}, "correction_steps");
  expect_each_rejected(&HeatDistanceOptions::max_constrained_sources, {-1},
                       "max_constrained_sources");
  expect_each_rejected(&HeatDistanceOptions::band_span, {-1.0, kNan}, "band_span");
}

TEST(OptionsValidate, PoissonAndCholeskyOptions) {
  PoissonOptions{}.validate();
  expect_each_rejected(&PoissonOptions::screening, {-1.0, kNan}, "screening");
  CholeskyOptions{}.validate();
  expect_each_rejected(&CholeskyOptions::min_rcond, {-1.0}, "min_rcond");
  expect_each_rejected(&CholeskyOptions::solve_blas_threads, {-1}, "thread");
  PoissonOptions nested;
  nested.cholesky.factor_blas_threads = -1;
  expect_rejected(nested, "thread");
}

TEST(OptionsValidate, EigenOptions) {
  EigenOptions{}.validate();
  expect_each_rejected(&EigenOptions::extra_pairs, {-1}, "extra_pairs");
  expect_each_rejected(&EigenOptions::max_iterations, {0}, "max_iterations");
  expect_each_rejected(&EigenOptions::tolerance, {0.0}, "tolerance");
  expect_each_rejected(&EigenOptions::shift_scale, {-1.0}, "shift_scale");
}

TEST(OptionsValidate, CheckedAtTheEntry) {
  const auto m = intrinsic::icosphere(3);
  const auto tri = intrinsic::IntrinsicTriangulation::from_positions(m.faces, m.positions);
  HeatDistanceOptions h;
  h.time_factor = -1.0;
  EXPECT_THROW(HeatDistanceSolver(tri, h), InvalidInput);
  PoissonOptions p;
  p.screening = -1.0;
  EXPECT_THROW(PoissonSolver(tri, {0}, p), InvalidInput);
  EigenOptions e;
  e.tolerance = -1.0;
  EXPECT_THROW(eigenpairs(tri, 3, e), InvalidInput);
  CholeskyOptions c;
  c.min_rcond = -1.0;
  EXPECT_THROW(CholeskySolver(fem::cotan_laplacian(tri), c), InvalidInput);
}

// solvers::SurfacePoint is intrinsic::SurfacePoint; solvers::mean_edge_length the intrinsic one.
TEST(OptionsValidate, SharedTypes) {
  static_assert(std::is_same_v<SurfacePoint, intrinsic::SurfacePoint>);
  const auto m = intrinsic::tetrahedron();
  const auto tri = intrinsic::IntrinsicTriangulation::from_positions(m.faces, m.positions);
  EXPECT_EQ(mean_edge_length(tri), intrinsic::mean_edge_length(tri));
  const HeatDistanceSolver solver(tri);
  EXPECT_THROW(solver.compute_distance_from_points({SurfacePoint{}}), InvalidInput);
}

}  // namespace
}  // namespace ifem::solvers
