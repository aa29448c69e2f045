// libFuzzer harness: bytes → a mesh reader → solvers::prepare_surface() → fem::cotan_laplacian
// and fem::lumped_mass, which must be finite. A non-finite entry in L or M is the "silent NaN"
// this harness hunts: it aborts, and libFuzzer saves the input.
//
// The format is sniffed from the content, so every reader's seeds are seeds here too: "ply" →
// PLY, "OFF" (with C/N/ST prefixes) → OFF, "solid" or a binary STL whose size matches its
// triangle count → STL, a line starting with an OBJ keyword → OBJ, otherwise XYZ. The high
// nibble of the last byte picks the PrepareOptions (0, e.g. a final '\n': the defaults with a
// small knn), so mutating it reaches the tufted, point-cloud and refinement paths. Inputs over
// kMaxElements vertices or triangles are skipped to keep one run well under a second.
//
// Coordinates up to 1e308 are fair game: lengths, weights and the heat solver are scale-free,
// and a mass that cannot be represented is an ifem::Error (the former finding
// tests/fuzz/seeds/ply/nan-huge-coordinates.ply). IFEM_FUZZ_ALLOW_NONFINITE=1 turns the
// finiteness check into a note on stderr.
#include <cstddef>
#include <cstdint>
#include <cstdlib>
#include <cstring>
#include <string>
#include <string_view>

#include "fem/operators.h"
#include "fuzz_common.h"
#include "intrinsic/io/detail.h"
#include "solvers/recipes/pipeline.h"

namespace {

using ifem::io::SurfaceInput;

constexpr long kMaxElements = 2000;

using Reader = SurfaceInput (*)(const std::string&, const std::string&);

bool starts_with(std::string_view s, std::string_view prefix) {
  return s.substr(0, prefix.size()) == prefix;
}

// The first token of the first line that is neither blank nor a '#' comment.
std::string_view first_token(std::string_view s) {
  std::size_t i = 0;
  while (i < s.size()) {
    while (i < s.size() && (s[i] == ' ' || s[i] == '\t' || s[i] == '\r' || s[i] == '\n')) ++i;
    if (i < s.size() && s[i] == '#') {
      while (i < s.size() && s[i] != '\n') ++i;
      continue;
    }
    break;
  }
  std::size_t j = i;
  while (j < s.size() && s[j] != ' ' && s[j] != '\t' && s[j] != '\r' && s[j] != '\n') ++j;
  return s.substr(i, j - i);
}

Reader sniff_reader(const std::string& bytes, const char** path) {
  const std::string_view s(bytes);
  if (starts_with(s, "ply")) {
    *path = "fuzz.ply";
    return ifem::io::detail::read_ply;
  }
  if (s.size() >= 84) {
    std::uint32_t n = 0;
    std::memcpy(&n, s.data() + 80, 4);
    if (84 + 50 * static_cast<std::uint64_t>(n) == s.size()) {
      *path = "fuzz.stl";
      return ifem::io::detail::read_stl;
    }
  }
  if (starts_with(s, "solid")) {
    *path = "fuzz.stl";
    return ifem::io::detail::read_stl;
  }
  const std::string_view t = first_token(s);
  if (t.size() >= 3 && t.size() <= 6 && t.substr(t.size() - 3) == "OFF") {
    *path = "fuzz.off";
    return ifem::io::detail::read_off;
  }
  for (const char* keyword : {"v", "vn", "vt", "f", "o", "g", "s", "l", "usemtl", "mtllib"}) {
    if (t == keyword) {
      *path = "fuzz.obj";
      // a captureless lambda: read_obj's progress argument has a default a pointer would drop
      return [](const std::string& p, const std::string& bytes) {
        return ifem::io::detail::read_obj(p, bytes);
      };
    }
  }
  *path = "fuzz.xyz";
  return ifem::io::detail::read_xyz;
}

// Options from the high nibble of the last byte: bit 0 force_tufted, bit 1 force_pointcloud
// (both set: neither), bit 2 no intrinsic Delaunay flips, bit 3 refine (few insertions).
ifem::solvers::PrepareOptions options_for(const std::uint8_t* data, std::size_t size) {
  const unsigned bits = size == 0 ? 0u : data[size - 1] >> 4;
  ifem::solvers::PrepareOptions options;
  options.knn = 6;
  options.force_tufted = (bits & 3u) == 1u;
  options.force_pointcloud = (bits & 3u) == 2u;
  options.intrinsic_delaunay = (bits & 4u) == 0u;
  if ((bits & 8u) != 0u) {
    ifem::solvers::SurfaceRefineOptions refine;
    refine.max_insertions = 50;
    options.refine = refine;
  }
  return options;
}

void check_finite(const char* what, bool finite) {
  if (finite) return;
  const char* allow = std::getenv("IFEM_FUZZ_ALLOW_NONFINITE");
  if (allow != nullptr && std::strcmp(allow, "1") == 0) {
    std::fprintf(stderr, "fuzz: note: %s has a non-finite entry (allowed by env)\n", what);
    return;
  }
  ifem::fuzz::fail(std::string(what) + " has a non-finite entry (silent NaN)");
}

int fuzz_one(const std::uint8_t* data, std::size_t size) {
  const std::string bytes = ifem::fuzz::as_bytes(data, size);
  const char* path = "";
  const Reader reader = sniff_reader(bytes, &path);
  SurfaceInput input;
  if (!ifem::fuzz::run_expecting_errors([&] { input = reader(path, bytes); })) return 0;
  ifem::fuzz::check_surface_input(input);
  if (input.positions.rows() > kMaxElements ||
      static_cast<long>(input.triangles.size()) > kMaxElements) {
    return 0;
  }
  const ifem::solvers::PrepareOptions options = options_for(data, size);
  ifem::fuzz::run_expecting_errors([&] {
    const ifem::solvers::PreparedSurface s = ifem::solvers::prepare_surface(input, options);
    const auto L = ifem::fem::cotan_laplacian(s.tri);
    const Eigen::VectorXd M = ifem::fem::lumped_mass(s.tri);
    bool finite = true;
    for (int k = 0; k < L.nonZeros(); ++k) finite = finite && std::isfinite(L.valuePtr()[k]);
    check_finite("L (cotan Laplacian)", finite);
    check_finite("M (lumped mass)", M.allFinite());
  });
  return 0;
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  return fuzz_one(data, size);
}
