// The files of render.h: PNG out (chunks written here, deflate and CRC-32 from zlib) and the OBJ
// polylines in (curves drawn over the surface).
#include <zlib.h>

#include <sstream>
#include <string>
#include <vector>

#include "intrinsic/core/errors.h"
#include "intrinsic/io/detail.h"
#include "intrinsic/io/tokens.h"
#include "solvers/recipes/render.h"

namespace ifem::solvers {

namespace {

void put_u32(std::vector<std::uint8_t>& out, std::uint32_t v) {
  for (int shift = 24; shift >= 0; shift -= 8) out.push_back(static_cast<std::uint8_t>(v >> shift));
}

/// length, type, data, CRC-32 of type + data (PNG spec, section 5.3)
void put_chunk(std::vector<std::uint8_t>& out, const char type[4],
               const std::vector<std::uint8_t>& data) {
  put_u32(out, static_cast<std::uint32_t>(data.size()));
  const std::size_t start = out.size();
  out.insert(out.end(), type, type + 4);
  out.insert(out.end(), data.begin(), data.end());
  const uLong crc = crc32(0L, out.data() + start, static_cast<uInt>(out.size() - start));
  put_u32(out, static_cast<std::uint32_t>(crc));
}

}  // namespace

std::vector<std::uint8_t> encode_png(const Image& image) {
  if (image.width <= 0 || image.height <= 0 ||
      image.rgb.size() != static_cast<std::size_t>(image.width) * image.height * 3) {
    throw InvalidInput("encode_png: the image's size does not match its pixels");
  }
  std::vector<std::uint8_t> out = {0x89, 'P', 'N', 'G', '\r', '\n', 0x1a, '\n'};
  std::vector<std::uint8_t> header;
  put_u32(header, static_cast<std::uint32_t>(image.width));
  put_u32(header, static_cast<std::uint32_t>(image.height));
  header.insert(header.end(), {8, 2, 0, 0, 0});  // 8 bits, RGB, deflate, filter set 0, no interlace
  put_chunk(out, "IHDR", header);
  const std::size_t row = static_cast<std::size_t>(image.width) * 3;
  std::vector<std::uint8_t> raw;
  raw.reserve((row + 1) * image.height);
  for (int y = 0; y < image.height; ++y) {
    raw.push_back(0);  // filter type 0 (none)
    raw.insert(raw.end(), image.rgb.begin() + y * row, image.rgb.begin() + (y + 1) * row);
  }
  uLongf packed_size = compressBound(static_cast<uLong>(raw.size()));
  std::vector<std::uint8_t> packed(packed_size);
  if (compress2(packed.data(), &packed_size, raw.data(), static_cast<uLong>(raw.size()), 6) !=
      Z_OK) {
    throw Error("encode_png: zlib failed to compress the image");
  }
  packed.resize(packed_size);
  put_chunk(out, "IDAT", packed);
  put_chunk(out, "IEND", {});
  return out;
}

void write_png(const std::string& path, const Image& image) {
  const std::vector<std::uint8_t> bytes = encode_png(image);
  io::detail::write_file_atomically(path, std::string(bytes.begin(), bytes.end()));
}

std::vector<std::vector<Eigen::Vector3d>> read_polylines_obj(const std::string& path) {
  std::istringstream text(io::detail::read_file(path));
  std::vector<Eigen::Vector3d> points;
  std::vector<std::vector<Eigen::Vector3d>> lines;
  std::size_t line_no = 0;
  for (std::string line; std::getline(text, line);) {
    ++line_no;
    const std::vector<std::string> tokens = io::line_tokens(line);
    if (tokens.empty()) continue;
    if (tokens[0] == "v") {
      Eigen::Vector3d p;
      if (tokens.size() < 4 || !io::parse_whole_real(tokens[1], p.x()) ||
          !io::parse_whole_real(tokens[2], p.y()) || !io::parse_whole_real(tokens[3], p.z())) {
        io::detail::fail_line(
            path, line_no,
            "a 'v' line needs three finite numbers, got " + io::quoted_excerpt(line));
      }
      points.push_back(p);
    } else if (tokens[0] == "l") {
      std::vector<Eigen::Vector3d> polyline;
      for (std::size_t k = 1; k < tokens.size(); ++k) {
        long long id = 0;
        // "i/t" (a texture coordinate after the point's id) is allowed; the id comes first
        const std::string head = tokens[k].substr(0, tokens[k].find('/'));
        const long long n = static_cast<long long>(points.size());
        if (!io::parse_whole_integer(head, id) || id == 0 || id > n || id < -n) {
          io::detail::fail_line(path, line_no,
                                "point id " + io::quoted_excerpt(tokens[k]) + " is not in 1.." +
                                    std::to_string(n) + " (or -" + std::to_string(n) + "..-1)");
        }
        polyline.push_back(points[id > 0 ? id - 1 : n + id]);
      }
      if (polyline.size() >= 2) lines.push_back(std::move(polyline));
    }
  }
  return lines;
}

}  // namespace ifem::solvers
