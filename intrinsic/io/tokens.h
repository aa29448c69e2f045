// Whole-token number parsing for the line-based text formats (Dirichlet files, curves files,
// surface points on the command line): a token is a number only if all of it is; and the
// whitespace tokens of such a line.
#pragma once

#include <charconv>
#include <cmath>
#include <sstream>
#include <string>
#include <vector>

namespace ifem::io {

/// True, with v set, when all of `t` is an integer (no sign-less garbage, no "3x", no "1.5").
inline bool parse_whole_integer(const std::string& t, long long& v) {
  const auto [ptr, ec] = std::from_chars(t.data(), t.data() + t.size(), v);
  return !t.empty() && ec == std::errc() && ptr == t.data() + t.size();
}

/// True, with x set, when all of `t` is a finite number ("nan", "inf", "1e400" are refused).
inline bool parse_whole_real(const std::string& t, double& x) {
  const auto [ptr, ec] = std::from_chars(t.data(), t.data() + t.size(), x);
  return !t.empty() && ec == std::errc() && ptr == t.data() + t.size() && std::isfinite(x);
}

/// The whitespace-separated tokens of a line of a text format, without its comment ('#' to the
/// end of the line); empty for a blank or comment line.
inline std::vector<std::string> line_tokens(const std::string& line) {
  std::istringstream ss(line.substr(0, line.find('#')));
  std::vector<std::string> tokens;
  for (std::string t; ss >> t;) tokens.push_back(t);
  return tokens;
}

}  // namespace ifem::io
