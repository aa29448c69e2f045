#include "results.h"

#include <algorithm>
#include <cstdio>
#include <stdexcept>

#include "intrinsic/io/mesh_io.h"

namespace ifem::cli {

ResultOutput result_output(const Args& args, const std::string& name) {
  const OptionSpec& spec = args.spec(name);
  const std::vector<std::string>& allowed = spec.extensions;
  if (!args.has(name)) {
    throw UsageError("missing " + spec.display() + " " + spec.placeholder + " (see --help)");
  }
  ResultOutput out;
  out.path = args.get(name);
  const std::string ext = io::file_extension(out.path);
  if (std::find(allowed.begin(), allowed.end(), ext) == allowed.end()) {
    std::string list;
    for (std::size_t i = 0; i < allowed.size(); ++i) {
      list += (i == 0 ? "" : i + 1 == allowed.size() ? " or " : ", ") + allowed[i];
    }
    throw UsageError(spec.display() + " '" + out.path + "': the output must end in " + list);
  }
  out.ply = ext == ".ply";
  return out;
}

void write_results(const ResultOutput& out, const PreparedSurface& s,
                   const std::vector<io::VertexProperty>& properties,
                   const std::vector<io::VertexProperty>& face_properties) {
  write_results(out, s.input, properties, face_properties);
}

void write_results(const ResultOutput& out, const io::SurfaceInput& input,
                   const std::vector<io::VertexProperty>& properties,
                   const std::vector<io::VertexProperty>& face_properties) {
  const Eigen::Index nv = input.positions.rows();
  std::vector<io::VertexProperty> on_input;
  for (const io::VertexProperty& p : properties) {
    if (p.values.size() < nv) {
      throw std::logic_error("write_results: '" + p.name + "' has fewer values than vertices");
    }
    on_input.push_back({p.name, p.values.head(nv)});
  }
  if (out.ply) {
    io::write_ply(out.path, input.positions, input.triangles, on_input, face_properties);
    return;
  }
  if (on_input.size() != 1) throw std::logic_error("write_results: a .txt holds one value");
  io::write_values(out.path, on_input[0].values);
}

void write_rows(const std::string& path, const Eigen::MatrixXd& rows) {
  io::write_rows(path, rows);
}

void write_npy(const std::string& path, const Eigen::MatrixXd& m) {
  std::string header = "{'descr': '<f8', 'fortran_order': True, 'shape': (" +
                       std::to_string(m.rows()) + ", " + std::to_string(m.cols()) + "), }";
  // magic (6) + version (2) + header length (2) + header, padded with spaces to a multiple of 64
  // and ended by a newline
  const std::size_t total = (10 + header.size() + 1 + 63) / 64 * 64;
  header.append(total - 10 - header.size() - 1, ' ');
  header += '\n';
  const unsigned char preamble[10] = {0x93,
                                      'N',
                                      'U',
                                      'M',
                                      'P',
                                      'Y',
                                      1,
                                      0,
                                      static_cast<unsigned char>(header.size() & 0xff),
                                      static_cast<unsigned char>(header.size() >> 8)};
  std::FILE* f = std::fopen(path.c_str(), "wb");
  if (!f) throw IoError(path + ": cannot write");
  static_assert(sizeof(double) == 8, "float64");
  const auto n = std::size_t(m.size());
  const bool ok = std::fwrite(preamble, 1, 10, f) == 10 &&
                  std::fwrite(header.data(), 1, header.size(), f) == header.size() &&
                  std::fwrite(m.data(), sizeof(double), n, f) == n;
  if (std::fclose(f) != 0 || !ok) throw IoError(path + ": cannot write");
}

}  // namespace ifem::cli
