// libFuzzer harness: the OBJ reader (io::detail::read_obj) on arbitrary bytes.
#include <cstddef>
#include <cstdint>
#include <string>

#include "fuzz_common.h"
#include "intrinsic/io/detail.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  // a lambda: read_obj's progress argument has a default, which a function pointer drops
  const auto read = [](const std::string& path, const std::string& bytes) {
    return ifem::io::detail::read_obj(path, bytes);
  };
  return ifem::fuzz::fuzz_reader(read, "fuzz.obj", data, size);
}
