// Small helpers shared by the bench_<name>.cpp sections: timing, medians, peak memory.
#pragma once

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <fstream>
#include <string>
#include <vector>

namespace ifem::bench {

inline double seconds_now() {
  return std::chrono::duration<double>(std::chrono::steady_clock::now().time_since_epoch()).count();
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

/// Peak resident set size of this process so far, in MiB (VmHWM from /proc/self/status).
inline double peak_rss_mib() {
  std::ifstream in("/proc/self/status");
  std::string line;
  while (std::getline(in, line)) {
    if (line.rfind("VmHWM:", 0) == 0) return std::stod(line.substr(6)) / 1024.0;
  }
  return 0.0;
}

/// Parses "--repeat N" style integer options from argv (returns fallback when absent).
inline long int_option(int argc, char** argv, const char* name, long fallback) {
  for (int i = 1; i + 1 < argc; ++i) {
    if (std::string(argv[i]) == name) return std::stol(argv[i + 1]);
  }
  return fallback;
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
