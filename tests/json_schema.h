// The JSON schema of docs/output.md (its "| `document` | `field` | type |" table) and a check of a
// document against it: every field present (unless its type ends in '?'), of its type, and no
// field the table does not list.
#pragma once

#include <fstream>
#include <map>
#include <nlohmann/json.hpp>
#include <regex>
#include <string>
#include <vector>

#include "test_support.h"

namespace kiln::test {

// document -> field -> type ("string", "integer", "number", "boolean", "array", "object", with a
// trailing '?' when the field may be absent), in the table's order.
using JsonSchema = std::map<std::string, std::vector<std::pair<std::string, std::string>>>;

inline JsonSchema readJsonSchema() {
    std::ifstream in(repo("docs/output.md"));
    std::regex row(R"(^\| `([a-z-]+)` \| `([a-z_]+)` \| ([a-z]+\??) \|$)");
    JsonSchema schema;
    for (std::string line; std::getline(in, line);)
        if (std::smatch m; std::regex_match(line, m, row)) schema[m[1]].push_back({m[2], m[3]});
    return schema;
}

inline bool hasJsonType(const nlohmann::json& v, std::string type) {
    if (type == "string") return v.is_string();
    if (type == "integer") return v.is_number_integer();
    if (type == "number") return v.is_number();
    if (type == "boolean") return v.is_boolean();
    if (type == "array") return v.is_array();
    if (type == "object") return v.is_object();
    return false;
}

// Empty when doc fits the document's schema; else what is wrong.
inline std::string schemaErrors(const JsonSchema& schema, const std::string& document,
                                const nlohmann::json& doc) {
    auto it = schema.find(document);
    if (it == schema.end()) return "no document '" + document + "' in docs/output.md";
    if (!doc.is_object()) return document + ": not an object: " + doc.dump();
    std::string errors;
    std::map<std::string, bool> listed;
    for (const auto& [field, type] : it->second) {
        listed[field] = true;
        const bool optional = type.back() == '?';
        if (!doc.contains(field)) {
            if (!optional) errors += document + ": no '" + field + "'; ";
            continue;
        }
        if (!hasJsonType(doc[field], optional ? type.substr(0, type.size() - 1) : type))
            errors += document + ": '" + field + "' is not " + type + "; ";
    }
    for (const auto& [key, value] : doc.items())
        if (!listed.count(key)) errors += document + ": '" + key + "' is not documented; ";
    return errors;
}

}  // namespace kiln::test
