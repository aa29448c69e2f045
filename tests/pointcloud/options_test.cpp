// pointcloud::Options::validate() (docs/decisions.md, "Every options struct has validate()").
#include <gtest/gtest.h>

#include <limits>
#include <string>

#include "helpers.h"
#include "intrinsic/core/errors.h"
#include "pointcloud/pointcloud_laplacian.h"

namespace ifem::pointcloud {
namespace {

TEST(OptionsValidate, PointCloudOptions) {
  Options{}.validate();
  test::expect_each_rejected(&Options::k, {1}, "Options::k");
  test::expect_each_rejected(&Options::mollify_relative_epsilon,
                             {-1e-5, std::numeric_limits<double>::infinity()},
                             "mollify_relative_epsilon");
  Options a;
  a.k = 1;
  // checked at the entry, before any work
  Positions p = Positions::Random(50, 3);
  EXPECT_THROW(pointcloud_triangulation(p, a), InvalidInput);
}

}  // namespace
}  // namespace ifem::pointcloud
