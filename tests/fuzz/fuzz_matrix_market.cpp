// libFuzzer harness: io::read_matrix_market (path-based: the bytes go through a temporary
// file). A matrix that reads must have its entries inside its declared size (Eigen checks that
// only in debug builds) and be finite.
#include <cstddef>
#include <cstdint>
#include <cstdio>
#include <string>

#include "fuzz_common.h"

namespace {

int fuzz_one(const std::uint8_t* data, std::size_t size) {
  const std::string& path = ifem::fuzz::write_temporary(".mtx", data, size);
  Eigen::SparseMatrix<double> A;
  if (!ifem::fuzz::run_expecting_errors([&] { A = ifem::io::read_matrix_market(path); })) {
    return 0;
  }
  for (Eigen::Index k = 0; k < A.outerSize(); ++k) {
    for (Eigen::SparseMatrix<double>::InnerIterator it(A, k); it; ++it) {
      if (it.row() < 0 || it.row() >= A.rows() || it.col() < 0 || it.col() >= A.cols()) {
        ifem::fuzz::fail("matrix entry outside its declared size");
      }
    }
  }
  return 0;
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  return fuzz_one(data, size);
}
