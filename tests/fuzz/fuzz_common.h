// Shared by the libFuzzer harnesses (tests/fuzz/fuzz_*.cpp): running a reader on the fuzzer's
// bytes with the expected outcomes told apart from the findings, a temporary file for the
// path-based readers, and the invariants every successful read must satisfy.
//
// Expected: a reader returns, or throws an ifem::Error (IoError, InvalidInput, ...) for bad
// input. Findings: any other exception, a sanitizer report, a broken invariant (abort() with a
// message, so libFuzzer saves the input as crash-<hash>).
#pragma once

#include <unistd.h>

#include <cmath>
#include <cstddef>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <exception>
#include <string>
#include <typeinfo>

#include "intrinsic/core/errors.h"
#include "intrinsic/io/mesh_io.h"

namespace ifem::fuzz {

/// Prints "fuzz: <what>" and aborts: libFuzzer reports it as a crash and saves the input.
[[noreturn]] inline void fail(const std::string& what) {
  std::fprintf(stderr, "fuzz: %s\n", what.c_str());
  std::fflush(stderr);
  std::abort();
}

/// IFEM_FUZZ_STRICT=1: also report the known open bugs that the harnesses step around by
/// default (each listed with its reproducer in tests/fuzz/crashes/README.md).
inline bool strict() {
  const char* env = std::getenv("IFEM_FUZZ_STRICT");
  return env != nullptr && env[0] == '1';
}

/// The fuzzer's bytes as the whole-file string the detail:: readers take.
inline std::string as_bytes(const std::uint8_t* data, std::size_t size) {
  return std::string(reinterpret_cast<const char*>(data), size);
}

/// Runs f(); an ifem::Error is an expected outcome (returns false), any other exception is a
/// finding (aborts naming its type and message). True when f() returned normally.
template <class F>
bool run_expecting_errors(F&& f) {
  try {
    f();
    return true;
  } catch (const Error&) {
    return false;
  } catch (const std::exception& e) {
    fail(std::string("unexpected exception ") + typeid(e).name() + ": " + e.what());
  } catch (...) {
    fail("unexpected non-std exception");
  }
}

/// A file of this process's own for the readers that take a path, rewritten on every input:
/// under $TMPDIR, else /dev/shm (in memory: /tmp on an overlay file system made these harnesses
/// 50× slower), else /tmp.
inline const std::string& temporary_path(const char* extension) {
  static const std::string path = [extension] {
    const char* env = std::getenv("TMPDIR");
    std::string dir = env != nullptr && *env != '\0' ? env : "";
    if (dir.empty()) dir = access("/dev/shm", W_OK) == 0 ? "/dev/shm" : "/tmp";
    return dir + "/ifem_fuzz_" + std::to_string(static_cast<long>(getpid())) + extension;
  }();
  return path;
}

/// Writes the bytes to temporary_path(extension) and returns that path.
inline const std::string& write_temporary(const char* extension, const std::uint8_t* data,
                                          std::size_t size) {
  const std::string& path = temporary_path(extension);
  std::FILE* f = std::fopen(path.c_str(), "wb");
  if (f == nullptr) fail("cannot write " + path);
  if (size > 0 && std::fwrite(data, 1, size, f) != size) fail("short write to " + path);
  std::fclose(f);
  return path;
}

/// What every successful mesh read promises (mesh_io.h): finite positions, face indices in
/// [0, #V), one polygon id per triangle, below n_polygons, per-vertex arrays of #V rows.
inline void check_surface_input(const io::SurfaceInput& s) {
  const Index nv = static_cast<Index>(s.positions.rows());
  if (!s.positions.allFinite()) fail("reader returned a non-finite position");
  if (s.triangle_polygon.size() != s.triangles.size()) fail("triangle_polygon size != #T");
  for (std::size_t t = 0; t < s.triangles.size(); ++t) {
    for (const Index v : s.triangles[t]) {
      if (v < 0 || v >= nv) fail("reader returned a face index out of [0, #V)");
    }
    const Index p = s.triangle_polygon[t];
    if (p < 0 || p >= s.n_polygons) fail("reader returned a polygon id out of [0, n_polygons)");
  }
  if (s.n_non_triangles > s.n_polygons) fail("n_non_triangles > n_polygons");
  if (s.normals.rows() != 0 && s.normals.rows() != nv) fail("normals rows != #V");
  for (const io::VertexProperty& p : s.vertex_properties) {
    if (p.values.size() != nv) fail("vertex property '" + p.name + "' size != #V");
  }
}

/// A harness for one detail:: reader: read, and check the result when it reads.
template <class Reader>
int fuzz_reader(Reader reader, const char* path, const std::uint8_t* data, std::size_t size) {
  const std::string bytes = as_bytes(data, size);
  io::SurfaceInput s;
  if (run_expecting_errors([&] { s = reader(path, bytes); })) check_surface_input(s);
  return 0;
}

}  // namespace ifem::fuzz
