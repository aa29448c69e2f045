// Shared I/O helpers: whole-file reading, number parsing with std::from_chars, error messages
// with file and line / byte offset, atomic writes.
#include <cerrno>
#include <charconv>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <system_error>

#include "intrinsic/io/detail.h"

namespace ifem::io::detail {

std::string read_file(const std::string& path, const ProgressCallback* on_progress) {
  std::error_code ec;
  const auto status = std::filesystem::status(path, ec);
  if (ec || !std::filesystem::exists(status)) fail_file(path, "cannot open: no such file");
  if (std::filesystem::is_directory(status)) fail_file(path, "cannot open: is a directory");
  std::FILE* f = std::fopen(path.c_str(), "rb");
  if (f == nullptr) fail_file(path, std::string("cannot open: ") + std::strerror(errno));
  std::string bytes;
  char buffer[1 << 16];
  const auto size = std::filesystem::file_size(path, ec);
  if (!ec) bytes.reserve(static_cast<std::size_t>(size));
  static const ProgressCallback kNone;
  ProgressMeter meter(on_progress ? *on_progress : kNone, "read", ec ? 1.0 : double(size) + 1.0);
  for (;;) {
    const std::size_t got = std::fread(buffer, 1, sizeof(buffer), f);
    bytes.append(buffer, got);
    meter.update(double(bytes.size()));
    if (got < sizeof(buffer)) break;
  }
  const bool failed = std::ferror(f) != 0;
  std::fclose(f);
  if (failed) fail_file(path, "read error");
  meter.finish();
  return bytes;
}

void write_file_atomically(const std::string& path, const std::string& bytes) {
  std::FILE* f = open_temporary(path, true);
  const bool wrote = std::fwrite(bytes.data(), 1, bytes.size(), f) == bytes.size();
  close_and_rename(f, wrote, path);
}

std::FILE* open_temporary(const std::string& path, bool binary) {
  const std::string tmp = path + ".tmp";
  std::FILE* f = std::fopen(tmp.c_str(), binary ? "wb" : "w");
  if (f == nullptr) {
    fail_file(path, "cannot write " + tmp + ": " + std::strerror(errno));
  }
  return f;
}

void close_and_rename(std::FILE* f, bool ok, const std::string& path) {
  const std::string tmp = path + ".tmp";
  ok = ok && std::ferror(f) == 0;
  const int saved_errno = errno;
  const bool closed = std::fclose(f) == 0;
  if (!ok || !closed) {
    std::remove(tmp.c_str());
    fail_file(path, "cannot write " + tmp + ": " + std::strerror(ok ? errno : saved_errno));
  }
  if (std::rename(tmp.c_str(), path.c_str()) != 0) {
    const int rename_errno = errno;
    std::remove(tmp.c_str());
    fail_file(path, "cannot rename " + tmp + ": " + std::strerror(rename_errno));
  }
}

void fail_line(const std::string& path, std::size_t line, const std::string& problem) {
  throw IoError(path + ", line " + std::to_string(line) + ": " + problem);
}

void fail_offset(const std::string& path, std::size_t offset, const std::string& problem) {
  throw IoError(path + ", byte offset " + std::to_string(offset) + ": " + problem);
}

void fail_file(const std::string& path, const std::string& problem) {
  throw IoError(path + ": " + problem);
}

std::string quoted(std::string_view token) {
  constexpr std::size_t kMax = 40;
  std::string out = "'";
  out += token.substr(0, kMax);
  if (token.size() > kMax) out += "...";
  out += "'";
  return out;
}

void append_double(std::string& out, double v) {
  char buffer[64];
  const auto r = std::to_chars(buffer, buffer + sizeof(buffer), v);
  out.append(buffer, r.ptr);
}

std::string_view TextCursor::peek_token() const {
  const char* q = p_;
  while (q != end_ && !ends_token(q)) ++q;
  return {p_, static_cast<std::size_t>(q - p_)};
}

double TextCursor::number_any(const char* what) {
  if (at_line_end()) fail(std::string("missing ") + what + " (line ends early)");
  const char* b = p_;
  if (*b == '+' && b + 1 != end_ && *(b + 1) != '-') ++b;
  double value = 0;
  const auto r = std::from_chars(b, end_, value);
  if (r.ec == std::errc::invalid_argument || !ends_token(r.ptr)) {
    fail("malformed number " + quoted(peek_token()) + " for " + what);
  }
  if (r.ec == std::errc::result_out_of_range) {
    fail("number out of range " + quoted(peek_token()) + " for " + what);
  }
  p_ = r.ptr;
  return value;
}

double TextCursor::number(const char* what) {
  const char* start = p_;
  const double value = number_any(what);
  if (!std::isfinite(value)) {
    p_ = start;
    skip_blanks();
    fail("NaN or infinite " + std::string(what) + " " + quoted(peek_token()));
  }
  return value;
}

std::int64_t TextCursor::integer(const char* what) {
  if (at_line_end()) fail(std::string("missing ") + what + " (line ends early)");
  const char* b = p_;
  if (*b == '+' && b + 1 != end_ && *(b + 1) != '-') ++b;
  std::int64_t value = 0;
  const auto r = std::from_chars(b, end_, value);
  if (r.ec == std::errc::invalid_argument || !ends_token(r.ptr)) {
    fail("malformed integer " + quoted(peek_token()) + " for " + what);
  }
  if (r.ec == std::errc::result_out_of_range) {
    fail("integer out of range " + quoted(peek_token()) + " for " + what);
  }
  p_ = r.ptr;
  return value;
}

void check_max_index(const std::string& path, const PolygonSink& sink, Index n_vertices,
                     bool binary, int index_base) {
  if (sink.max_index() < n_vertices) return;
  const std::string problem =
      "face index " + std::to_string(std::int64_t{sink.max_index()} + index_base) +
      " out of range (the file has " + std::to_string(n_vertices) + " vertices)";
  if (binary) fail_offset(path, sink.max_where(), problem);
  fail_line(path, sink.max_where(), problem);
}

void set_positions(SurfaceInput& out, const std::vector<double>& xyz) {
  const Index n = checked_index(xyz.size() / 3, "read_surface: vertex count");
  out.positions = Eigen::Map<const Positions>(xyz.data(), n, 3);
}

void set_normals(SurfaceInput& out, const std::vector<double>& nxyz) {
  const Index n = checked_index(nxyz.size() / 3, "read_surface: normal count");
  out.normals = Eigen::Map<const Positions>(nxyz.data(), n, 3);
}

}  // namespace ifem::io::detail
