// Small helpers shared by the bench_<name>.cpp sections: timing, medians, peak memory.
#pragma once

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <functional>
#include <string>
#include <vector>

#include "fem/operators.h"
#include "intrinsic/core/triangulation.h"

namespace ifem::bench {

inline double seconds_now() {
  return std::chrono::duration<double>(std::chrono::steady_clock::now().time_since_epoch()).count();
}

/// Prints the load average (first line of a section: wall times are noisy on a shared machine).
inline void print_load_average() {
  double load[3] = {0.0, 0.0, 0.0};
  if (getloadavg(load, 3) != 3) return;
  std::printf(
      "load average at start: %.2f %.2f %.2f (wall times are noisy on a shared machine)\n\n",
      load[0], load[1], load[2]);
}

/// M + L of the mollified intrinsic Delaunay triangulation of a mesh: the pattern (and, up to t,
/// the values) of the heat method's matrix, for the factorization experiments.
inline fem::SparseMatrix idt_mass_plus_laplacian(const std::vector<Triangle>& faces,
                                                 const Positions& pos, Index* n_faces = nullptr) {
  auto tri = intrinsic::IntrinsicTriangulation::from_positions(faces, pos);
  tri.mollify();
  tri.flip_to_delaunay();
  if (n_faces) *n_faces = tri.n_faces();
  fem::SparseMatrix A = fem::cotan_laplacian(tri);
  const Eigen::VectorXd m = fem::lumped_mass(tri);
  for (Eigen::Index j = 0; j < A.outerSize(); ++j) {
    for (fem::SparseMatrix::InnerIterator it(A, j); it; ++it) {
      if (it.row() == j) it.valueRef() += m[j];
    }
  }
  return A;
}

/// Median of a sample (copies it).
inline double median(std::vector<double> v) {
  if (v.empty()) return 0.0;
  std::sort(v.begin(), v.end());
  const std::size_t n = v.size();
  return n % 2 ? v[n / 2] : 0.5 * (v[n / 2 - 1] + v[n / 2]);
}

/// Runs f() `repeat` times and returns the median wall time in seconds.
template <class F>
double time_median(int repeat, F&& f) {
  std::vector<double> t;
  for (int r = 0; r < repeat; ++r) {
    const double t0 = seconds_now();
    f();
    t.push_back(seconds_now() - t0);
  }
  return median(t);
}

/// Times of several functions timed in turn: each one's median and minimum over the rounds.
struct InterleavedTimes {
  std::vector<double> median, min;
};

/// Several functions timed in turn, `repeat` rounds; in each round every function runs once
/// untimed (its steady state: caches, helper threads, pages as its own previous call left them,
/// not as the other function did) and then once timed. The functions share the machine's state
/// of the moment, so a ratio of two medians does not move with the drift of a shared machine
/// between one measurement and the next. The minimum is each function's quietest round: a busy
/// neighbour slows a bandwidth-bound call more than a compute-bound one, so a ratio of minima
/// is the one it cannot inflate.
inline InterleavedTimes time_interleaved(int repeat, const std::vector<std::function<void()>>& fs) {
  std::vector<std::vector<double>> t(fs.size());
  for (int r = 0; r < repeat; ++r) {
    for (std::size_t i = 0; i < fs.size(); ++i) {
      fs[i]();
      const double t0 = seconds_now();
      fs[i]();
      t[i].push_back(seconds_now() - t0);
    }
  }
  InterleavedTimes out;
  for (auto& ti : t) {
    out.min.push_back(*std::min_element(ti.begin(), ti.end()));
    out.median.push_back(median(ti));
  }
  return out;
}

/// A size field of /proc/self/status ("VmHWM:", "VmRSS:"), in MiB (0 if absent).
inline double status_mib(const char* field) {
  std::ifstream in("/proc/self/status");
  std::string line;
  const std::size_t n = std::char_traits<char>::length(field);
  while (std::getline(in, line)) {
    if (line.rfind(field, 0) == 0) return std::stod(line.substr(n)) / 1024.0;
  }
  return 0.0;
}

/// Peak resident set size of this process so far, in MiB (VmHWM).
inline double peak_rss_mib() { return status_mib("VmHWM:"); }

/// Resident set size now, in MiB (VmRSS).
inline double rss_mib() { return status_mib("VmRSS:"); }

/// Parses "--repeat N" style integer options from argv (returns fallback when absent).
inline long int_option(int argc, char** argv, const char* name, long fallback) {
  for (int i = 1; i + 1 < argc; ++i) {
    if (std::string(argv[i]) == name) return std::stol(argv[i + 1]);
  }
  return fallback;
}

/// True when the flag `name` (no value) is among the arguments.
inline bool has_flag(int argc, char** argv, const char* name) {
  for (int i = 1; i < argc; ++i) {
    if (std::string(argv[i]) == name) return true;
  }
  return false;
}

/// Returns the value after `name` in argv, or fallback.
inline std::string string_option(int argc, char** argv, const char* name,
                                 const std::string& fallback) {
  for (int i = 1; i + 1 < argc; ++i) {
    if (std::string(argv[i]) == name) return argv[i + 1];
  }
  return fallback;
}

}  // namespace ifem::bench
