// libFuzzer harness: io::read_values (one number per line, '#' comments; path-based: the
// bytes go through a temporary file). NaN and inf are accepted values, so nothing is checked
// beyond "reads or throws an ifem::Error".
#include <cstddef>
#include <cstdint>

#include "fuzz_common.h"

namespace {

int fuzz_one(const std::uint8_t* data, std::size_t size) {
  const std::string& path = ifem::fuzz::write_temporary(".txt", data, size);
  ifem::fuzz::run_expecting_errors([&] { (void)ifem::io::read_values(path); });
  return 0;
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  return fuzz_one(data, size);
}
