// libFuzzer harness: SignpostTriangulation::load, the "ifem-signpost 1" save format
// (path-based: the bytes go through a temporary file). The loader validates everything it
// reads (counts, ids, the gluing) and throws IoError otherwise; anything else is a finding.
//
// Known open bug, stepped around unless IFEM_FUZZ_STRICT=1: a huge declared count is allocated
// before any line of it is read ("input_vertices 499999995" → a 12 GB Positions;
// tests/fuzz/crashes/signpost/oom-huge-vertex-count.signpost).
#include <cstddef>
#include <cstdint>
#include <cstdlib>
#include <cstring>
#include <string>

#include "fuzz_common.h"
#include "intrinsic/refine/signpost.h"

namespace {

// True when a count line (input_vertices, input_faces, intrinsic, edges) declares more than
// kMaxCount of anything (the known bug above).
constexpr long kMaxCount = 1000000;
bool huge_count(const std::string& bytes) {
  std::size_t line = 0;
  while (line < bytes.size()) {
    std::size_t end = bytes.find('\n', line);
    if (end == std::string::npos) end = bytes.size();
    const std::string text = bytes.substr(line, end - line);
    for (const char* word : {"input_vertices", "input_faces", "intrinsic", "edges"}) {
      if (text.rfind(word, 0) != 0) continue;
      const char* p = text.c_str() + std::strlen(word);
      char* after = nullptr;
      for (long n = std::strtol(p, &after, 10); after != p; n = std::strtol(p, &after, 10)) {
        if (n > kMaxCount) return true;
        p = after;
      }
    }
    line = end + 1;
  }
  return false;
}

int fuzz_one(const std::uint8_t* data, std::size_t size) {
  if (!ifem::fuzz::strict() && huge_count(ifem::fuzz::as_bytes(data, size))) return 0;
  const std::string& path = ifem::fuzz::write_temporary(".signpost", data, size);
  ifem::fuzz::run_expecting_errors(
      [&] { (void)ifem::intrinsic::SignpostTriangulation::load(path); });
  return 0;
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  return fuzz_one(data, size);
}
