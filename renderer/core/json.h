// JSON output through nlohmann-json: one place that turns a document into text, so every command
// writes valid JSON whatever bytes a file name holds (invalid UTF-8 becomes U+FFFD, never a throw).
#pragma once

#include <nlohmann/json.hpp>
#include <string>

namespace kiln {

using Json = nlohmann::ordered_json;  // keys in the order written

// indent < 0: one line (JSON lines); otherwise pretty with that indent. Ends without a newline.
inline std::string jsonText(const Json& doc, int indent = 2) {
    return doc.dump(indent, ' ', false, Json::error_handler_t::replace);
}

}  // namespace kiln
