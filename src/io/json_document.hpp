// Strict JSON parsing for scene files: nlohmann's parser plus the checks it leaves out.
// A syntax error keeps nlohmann's line/column, a number that overflows a double names the key
// path where it sits, and a key repeated within one object is an error (nlohmann would keep
// the last value silently, hiding a typo such as two "E" entries).
#pragma once
#include <nlohmann/json.hpp>

#include <string>

namespace dipc {

// Throws SceneError "<source>: ..." on any of the problems above.
nlohmann::json parse_json_document(const std::string& text, const std::string& source);

}  // namespace dipc
