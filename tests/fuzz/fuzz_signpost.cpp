// libFuzzer harness: SignpostTriangulation::load, the "ifem-signpost 1" save format
// (path-based: the bytes go through a temporary file). The loader validates everything it
// reads (counts, ids, the gluing) and throws IoError otherwise; anything else is a finding.
// (A declared count the file is too short to hold is refused before allocating: the former
// finding tests/fuzz/seeds/signpost/oom-huge-vertex-count.signpost.)
#include <cstddef>
#include <cstdint>
#include <cstdlib>
#include <cstring>
#include <string>

#include "fuzz_common.h"
#include "intrinsic/refine/signpost.h"

namespace {

int fuzz_one(const std::uint8_t* data, std::size_t size) {
  const std::string& path = ifem::fuzz::write_temporary(".signpost", data, size);
  ifem::fuzz::run_expecting_errors(
      [&] { (void)ifem::intrinsic::SignpostTriangulation::load(path); });
  return 0;
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  return fuzz_one(data, size);
}
