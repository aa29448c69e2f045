// pointcloud::PointCloudOptions::validate() (docs/decisions.md, "Every options struct has
// validate()").
#include <gtest/gtest.h>

#include <limits>
#include <string>

#include "helpers.h"
#include "intrinsic/core/errors.h"
#include "pointcloud/pointcloud_laplacian.h"

namespace ifem::pointcloud {
namespace {

TEST(OptionsValidate, PointCloudOptions) {
  PointCloudOptions{}.validate();
  test::expect_each_rejected(&PointCloudOptions::k, {1}, "Options::k");
  test::expect_each_rejected(&PointCloudOptions::mollify_relative_epsilon,
                             {-1e-5, std::numeric_limits<double>::infinity()},
                             "mollify_relative_epsilon");
  PointCloudOptions a;
  a.k = 1;
  // checked at the entry, before any work
  Positions p = Positions::Random(50, 3);
  EXPECT_THROW(pointcloud_triangulation(p, a), InvalidInput);
}

}  // namespace
}  // namespace ifem::pointcloud
