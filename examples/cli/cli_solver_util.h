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

}  // namespace ifem::cli
