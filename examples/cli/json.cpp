#include "json.h"

namespace ifem::cli {

std::string json_text(const Json& doc) {
  // a path is bytes, not always UTF-8: replace what is not instead of throwing
  return doc.dump(2, ' ', false, nlohmann::json::error_handler_t::replace);
}

}  // namespace ifem::cli
