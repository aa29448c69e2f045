// Small helpers shared by the solver commands (distance, eigen, poisson).
#pragma once

#include <string>

#include "cli.h"

namespace ifem::cli {

/// Lowercased extension of a path, with the dot ("" when none).
inline std::string extension_of(const std::string& path) {
  const auto dot = path.find_last_of('.');
  const auto slash = path.find_last_of('/');
  if (dot == std::string::npos || (slash != std::string::npos && dot < slash)) return "";
  std::string e = path.substr(dot);
  for (char& c : e) c = char(std::tolower(static_cast<unsigned char>(c)));
  return e;
}

/// Mean edge length of the input's triangles (as given, before any flip).
inline double input_mean_edge_length(const io::SurfaceInput& in) {
  double sum = 0.0;
  long n = 0;
  for (const auto& t : in.triangles) {
    for (int i = 0; i < 3; ++i) {
      sum += (in.positions.row(t[i]) - in.positions.row(t[(i + 1) % 3])).norm();
      ++n;
    }
  }
  return n ? sum / double(n) : 0.0;
}

}  // namespace ifem::cli
