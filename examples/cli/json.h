// A small JSON writer for the `ifem` command's machine-readable output (`ifem info --json`).
// The output is always valid JSON (RFC 8259), whatever the strings hold: `"` `\` and control
// characters are escaped, valid UTF-8 passes through, invalid bytes become U+FFFD, and
// non-finite numbers are written as null.
#pragma once

#include <cstdint>
#include <string>
#include <string_view>
#include <vector>

namespace ifem::cli {

/// `s` as a JSON string literal, quotes included.
std::string json_quote(std::string_view s);

/// `v` as a JSON number: shortest round-trip form; "null" when not finite.
std::string json_number(double v);

/// Builds one JSON document on one line ("key": value, separated by ", "). Calls must nest
/// properly: inside an object, key() before every value; throws std::logic_error otherwise.
class JsonWriter {
 public:
  JsonWriter& begin_object();
  JsonWriter& end_object();
  JsonWriter& begin_array();
  JsonWriter& end_array();
  JsonWriter& key(std::string_view k);
  JsonWriter& value(std::string_view s);
  JsonWriter& value(const char* s) { return value(std::string_view(s)); }
  JsonWriter& value(double v);
  JsonWriter& value(std::int64_t v);
  JsonWriter& value(int v) { return value(std::int64_t{v}); }
  JsonWriter& value(std::size_t v) { return value(static_cast<std::int64_t>(v)); }
  JsonWriter& value(bool v);
  JsonWriter& null();
  /// key(k).value(v)
  template <class T>
  JsonWriter& field(std::string_view k, const T& v) {
    return key(k).value(v);
  }
  /// The document; throws std::logic_error while an object or array is still open.
  const std::string& str() const;

 private:
  void before_value();
  std::string out_;
  std::vector<char> open_;  // '{' or '['
  bool first_ = true;       // no element yet in the innermost container
  bool after_key_ = false;
};

}  // namespace ifem::cli
