#include "polylines.h"

#include <stdexcept>

#include "intrinsic/io/detail.h"
#include "intrinsic/io/mesh_io.h"
#include "intrinsic/refine/common_subdivision.h"

namespace ifem::cli {

std::string polylines_obj(const std::vector<Polyline>& lines, const std::vector<char>& closed,
                          const std::string& title) {
  std::string out = "# " + title + "\n";
  std::string l_lines;
  std::size_t base = 0;
  for (std::size_t c = 0; c < lines.size(); ++c) {
    const Polyline& p = lines[c];
    if (p.size() < 2) continue;
    const bool loop = c < closed.size() && closed[c];
    const std::size_t n = p.size() - (loop ? 1 : 0);
    l_lines += 'l';
    for (std::size_t i = 0; i < n; ++i) {
      out += 'v';
      for (int d = 0; d < 3; ++d) {
        out += ' ';
        io::detail::append_double(out, p[i][d]);
      }
      out += '\n';
      l_lines += ' ' + std::to_string(base + i + 1);
    }
    if (loop) l_lines += ' ' + std::to_string(base + 1);
    l_lines += '\n';
    base += n;
  }
  return out + l_lines;
}

void write_polylines_obj(const std::string& path, const std::vector<Polyline>& lines,
                         const std::vector<char>& closed, const std::string& title) {
  io::detail::write_file_atomically(path, polylines_obj(lines, closed, title));
}

void write_polylines(const std::string& path, const std::vector<Polyline>& lines,
                     const std::vector<char>& closed, const std::string& title) {
  const std::string ext = io::file_extension(path);
  if (ext == ".obj") return write_polylines_obj(path, lines, closed, title);
  if (ext != ".ply") throw std::logic_error("write_polylines: " + path + " is not .obj or .ply");
  intrinsic::write_polylines_ply(path, lines, false, title);
}

}  // namespace ifem::cli
