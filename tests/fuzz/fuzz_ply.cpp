// libFuzzer harness: the PLY reader (io::detail::read_ply) on arbitrary bytes; ASCII and
// binary (little- and big-endian) headers all reach this one entry.
#include <cstddef>
#include <cstdint>

#include "fuzz_common.h"
#include "intrinsic/io/detail.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  return ifem::fuzz::fuzz_reader(ifem::io::detail::read_ply, "fuzz.ply", data, size);
}
