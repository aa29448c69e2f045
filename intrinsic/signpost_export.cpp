// Export of traced intrinsic edges (the curves of the common subdivision) as a PLY line set.
#include <cstdint>
#include <cstdio>
#include <filesystem>
#include <string>

#include "intrinsic/signpost.h"

namespace ifem::intrinsic {

void write_polylines_ply(const std::string& path,
                         const std::vector<std::vector<Eigen::Vector3d>>& polylines,
                         bool binary) {
  std::size_t nv = 0, ne = 0;
  for (const auto& line : polylines) {
    nv += line.size();
    if (line.size() > 1) ne += line.size() - 1;
  }
  if (nv > static_cast<std::size_t>(INT32_MAX)) {
    throw IoError(path + ": too many polyline vertices for 32-bit ids");
  }
  const std::string tmp = path + ".tmp";
  std::FILE* f = std::fopen(tmp.c_str(), binary ? "wb" : "w");
  if (!f) throw IoError(path + ": cannot open for writing");
  std::fprintf(f,
               "ply\nformat %s 1.0\ncomment ifem: traced intrinsic edges over the input surface\n"
               "element vertex %zu\nproperty double x\nproperty double y\nproperty double z\n"
               "element edge %zu\nproperty int vertex1\nproperty int vertex2\nend_header\n",
               binary ? "binary_little_endian" : "ascii", nv, ne);
  for (const auto& line : polylines) {
    for (const Eigen::Vector3d& x : line) {
      if (binary) {
        const double xyz[3] = {x.x(), x.y(), x.z()};  // x86/ARM hosts: little-endian
        std::fwrite(xyz, sizeof(double), 3, f);
      } else {
        std::fprintf(f, "%.17g %.17g %.17g\n", x.x(), x.y(), x.z());
      }
    }
  }
  std::int32_t base = 0;
  for (const auto& line : polylines) {
    for (std::size_t i = 1; i < line.size(); ++i) {
      const std::int32_t ab[2] = {base + static_cast<std::int32_t>(i - 1),
                                  base + static_cast<std::int32_t>(i)};
      if (binary) {
        std::fwrite(ab, sizeof(std::int32_t), 2, f);
      } else {
        std::fprintf(f, "%d %d\n", ab[0], ab[1]);
      }
    }
    base += static_cast<std::int32_t>(line.size());
  }
  const bool ok = !std::ferror(f);
  if (std::fclose(f) != 0 || !ok) {
    std::remove(tmp.c_str());
    throw IoError(path + ": write failed");
  }
  std::error_code ec;
  std::filesystem::rename(tmp, path, ec);
  if (ec) {
    std::remove(tmp.c_str());
    throw IoError(path + ": cannot rename " + tmp + ": " + ec.message());
  }
}

}  // namespace ifem::intrinsic
