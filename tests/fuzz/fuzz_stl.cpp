// libFuzzer harness: the STL reader (io::detail::read_stl) on arbitrary bytes, ASCII
// ("solid ...") and binary (80-byte header, count, 50-byte records) alike.
#include <cstddef>
#include <cstdint>

#include "fuzz_common.h"
#include "intrinsic/io/detail.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  return ifem::fuzz::fuzz_reader(ifem::io::detail::read_stl, "fuzz.stl", data, size);
}
