// The `ifem` command's machine-readable output (`ifem info --json`) is built as a
// nlohmann::ordered_json (nlohmann-json3-dev): keys stay in the order the command sets them.
#pragma once

#include <nlohmann/json.hpp>
#include <string>

namespace ifem::cli {

using Json = nlohmann::ordered_json;

/// `doc` as the text `--json` prints: valid JSON (RFC 8259) whatever its strings hold — `"`,
/// `\` and control characters escaped, valid UTF-8 kept as is, each invalid byte replaced by
/// U+FFFD — with non-finite numbers as null and doubles in their shortest round-trip form;
/// indented by 2, "key": value, no trailing newline.
std::string json_text(const Json& doc);

}  // namespace ifem::cli
