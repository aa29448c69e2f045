// libFuzzer harness: the XYZ reader (io::detail::read_xyz) on arbitrary bytes.
#include <cstddef>
#include <cstdint>

#include "fuzz_common.h"
#include "intrinsic/io/detail.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  return ifem::fuzz::fuzz_reader(ifem::io::detail::read_xyz, "fuzz.xyz", data, size);
}
