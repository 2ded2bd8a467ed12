// Strict JSON parsing for scene files (see json_document.hpp).
#include "io/json_document.hpp"

#include <set>
#include <vector>

#include "io/scene.hpp"

namespace dipc {
namespace {

using json = nlohmann::json;

// Follows the parser's position as a key path ("geometry[1].box.size[0]") through nlohmann's
// parse-callback events. Containers do not raise a `value` event of their own: a scalar
// raises `value`, a container raises `*_end` when it closes; either completes one element
// of the enclosing array.
class KeyPathTracker {
 public:
  bool on_event(json::parse_event_t event, const json& parsed) {
    switch (event) {
      case json::parse_event_t::object_start: frames_.push_back(Frame{false, 0, {}, {}}); break;
      case json::parse_event_t::array_start: frames_.push_back(Frame{true, 0, {}, {}}); break;
      case json::parse_event_t::key: {
        Frame& top = frames_.back();
        top.key = parsed.get<std::string>();
        if (!top.keys_seen.insert(top.key).second) throw DuplicateKey{path()};
        break;
      }
      case json::parse_event_t::value: complete_element(); break;
      case json::parse_event_t::object_end:
      case json::parse_event_t::array_end:
        frames_.pop_back();
        complete_element();
        break;
    }
    return true;
  }

  // The key path of the value being parsed now.
  std::string path() const {
    std::string p;
    for (const Frame& f : frames_) {
      if (f.is_array) {
        p += "[" + std::to_string(f.index) + "]";
      } else if (!f.keys_seen.empty()) {  // past the first key
        p += (p.empty() ? "" : ".") + f.key;
      }
    }
    return p;
  }

  struct DuplicateKey {
    std::string path;
  };

 private:
  struct Frame {
    bool is_array;
    std::size_t index;  // arrays: index of the element being parsed
    std::string key;    // objects: key of the value being parsed
    std::set<std::string> keys_seen;
  };
  void complete_element() {
    if (!frames_.empty() && frames_.back().is_array) ++frames_.back().index;
  }
  std::vector<Frame> frames_;
};

// nlohmann's what() starts with "[json.exception.parse_error.101] "; users need the rest.
std::string without_exception_id(const std::string& what) {
  const auto end = what.find("] ");
  return (what.rfind("[json.exception.", 0) == 0 && end != std::string::npos) ? what.substr(end + 2) : what;
}

}  // namespace

json parse_json_document(const std::string& text, const std::string& source) {
  KeyPathTracker tracker;
  try {
    return json::parse(text, [&tracker](int, json::parse_event_t event, json& parsed) {
      return tracker.on_event(event, parsed);
    });
  } catch (const KeyPathTracker::DuplicateKey& dup) {
    throw SceneError(source + ": " + dup.path + ": duplicate key");
  } catch (const json::parse_error& e) {
    throw SceneError(source + ": invalid JSON: " + without_exception_id(e.what()));
  } catch (const json::out_of_range& e) {
    // A number literal too large for a double (1e999): the lexer read it as inf.
    const std::string where = tracker.path();
    throw SceneError(source + ": " + (where.empty() ? std::string() : where + ": ") + without_exception_id(e.what()) +
                     " (numbers must be finite)");
  }
}

}  // namespace dipc
