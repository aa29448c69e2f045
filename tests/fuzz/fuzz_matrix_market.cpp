// libFuzzer harness: io::read_matrix_market (path-based: the bytes go through a temporary
// file). A matrix that reads must have its entries inside its declared size (Eigen checks that
// only in debug builds) and be finite.
#include <cstddef>
#include <cstdint>
#include <cstdio>
#include <string>

#include "fuzz_common.h"

namespace {

// A (skew-)symmetric banner with a non-square size line (the known bug above).
bool nonsquare_symmetric(const std::string& bytes) {
  const std::size_t eol = bytes.find('\n');
  if (eol == std::string::npos || bytes.substr(0, eol).find("ymmetric") == std::string::npos) {
    return false;
  }
  std::size_t line = eol + 1;
  while (line < bytes.size() && bytes[line] == '%') {
    const std::size_t next = bytes.find('\n', line);
    if (next == std::string::npos) return false;
    line = next + 1;
  }
  long rows = 0, cols = 0;
  return std::sscanf(bytes.c_str() + line, "%ld %ld", &rows, &cols) == 2 && rows != cols;
}

int fuzz_one(const std::uint8_t* data, std::size_t size) {
  if (!ifem::fuzz::strict() && nonsquare_symmetric(ifem::fuzz::as_bytes(data, size))) return 0;
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
