// Whole-token number parsing for the line-based text formats (Dirichlet files, curves files,
// surface points on the command line): a token is a number only if all of it is; and the
// whitespace tokens of such a line; and how an error message shows a piece of a file.
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

/// `text` (a token or a line of a file) as an error message may show it: in single quotes, on
/// one line, every byte printable. Printable ASCII and well-formed UTF-8 are kept; \t \r \n \0
/// and \\ are written so, every other byte as \xNN (control bytes, DEL, malformed UTF-8). At most
/// max_chars characters of it are shown; a longer text ends in "..." and its size in bytes.
/// One helper for every file error, so binary garbage never spreads over several lines of
/// stderr nor truncates a message at a NUL.
inline std::string quoted_excerpt(const std::string& text, std::size_t max_chars = 40) {
  std::string out = "'";
  std::size_t shown = 0, i = 0;
  auto hex = [](unsigned char c) {
    const char* digits = "0123456789abcdef";
    return std::string("\\x") + digits[c >> 4] + digits[c & 15];
  };
  while (i < text.size() && shown < max_chars) {
    const unsigned char c = static_cast<unsigned char>(text[i]);
    std::size_t n = c < 0x80 ? 1 : (c >> 5) == 6 ? 2 : (c >> 4) == 14 ? 3 : (c >> 3) == 30 ? 4 : 0;
    for (std::size_t k = 1; k < n; ++k) {  // continuation bytes 10xxxxxx, else malformed
      if (i + k >= text.size() || (static_cast<unsigned char>(text[i + k]) >> 6) != 2) n = 0;
    }
    if (n > 1) {
      out.append(text, i, n);
    } else if (c == '\t' || c == '\r' || c == '\n' || c == 0 || c == '\\') {
      out += c == '\t' ? "\\t" : c == '\r' ? "\\r" : c == '\n' ? "\\n" : c == 0 ? "\\0" : "\\\\";
    } else if (n == 1 && c >= 0x20 && c != 0x7f) {
      out += static_cast<char>(c);
    } else {
      out += hex(c);
    }
    i += n > 1 ? n : 1;
    ++shown;
  }
  out += "'";
  if (i < text.size()) out += "... (" + std::to_string(text.size()) + " bytes)";
  return out;
}

}  // namespace ifem::io
