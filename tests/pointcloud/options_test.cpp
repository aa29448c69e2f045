// pointcloud::Options::validate() (docs/decisions.md, "Every options struct has validate()").
#include <gtest/gtest.h>

#include <limits>
#include <string>

#include "intrinsic/core/errors.h"
#include "pointcloud/pointcloud_laplacian.h"

namespace ifem::pointcloud {
namespace {

template <class Options>
void expect_rejected(const Options& o, const std::string& what) {
  try {
    o.validate();
    ADD_FAILURE() << "accepted bad " << what;
  } catch (const InvalidInput& e) {
    EXPECT_NE(std::string(e.what()).find(what), std::string::npos) << e.what();
  }
}

TEST(OptionsValidate, PointCloudOptions) {
  Options{}.validate();
  Options a;
  a.k = 1;
  expect_rejected(a, "Options::k");
  Options b;
  b.mollify_relative_epsilon = -1e-5;
  expect_rejected(b, "mollify_relative_epsilon");
  b.mollify_relative_epsilon = std::numeric_limits<double>::infinity();
  expect_rejected(b, "mollify_relative_epsilon");
  // checked at the entry, before any work
  Positions p = Positions::Random(50, 3);
  EXPECT_THROW(pointcloud_triangulation(p, a), InvalidInput);
}

}  // namespace
}  // namespace ifem::pointcloud
