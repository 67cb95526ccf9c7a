#include "base/json_input.h"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <optional>
#include <set>

#include "base/errors.h"
#include "base/nearest_name.h"

namespace pcbench {
namespace {

using Json = JsonInput::Json;

// "LINE:COLUMN" (1-based) of the byte before offset `byte` of `text`: where nlohmann-json's
// parse_error::byte points, for error messages about JSON input.
std::string line_and_column(std::string_view text, std::size_t byte) {
  std::size_t line = 1, column = 1;
  for (std::size_t i = 0; i + 1 < byte && i < text.size(); ++i) {
    if (text[i] == '\n') {
      ++line;
      column = 1;
    } else {
      ++column;
    }
  }
  return std::to_string(line) + ":" + std::to_string(column);
}

// The message for a number nlohmann-json cannot hold as a double ("1e999", its out_of_range
// error 406), as "FILE:LINE:COLUMN: ..." at the first place `text` has the number its message
// quotes, or "FILE: ..." when it has none.
std::string json_number_error(std::string_view text, std::string_view file,
                              const std::string& message) {
  const std::size_t open = message.find('\''), close = message.rfind('\'');
  const std::size_t at =
      open < close ? text.find(message.substr(open + 1, close - open - 1)) : std::string_view::npos;
  std::string out(file);
  if (at != std::string_view::npos) {
    out += ':';
    out += line_and_column(text, at + 1);
  }
  out += ": ";
  out += message;
  return out;
}

// A key as a JSON pointer token (RFC 6901): '~' and '/' escaped.
std::string json_pointer_token(std::string_view key) {
  std::string out;
  for (char c : key) {
    if (c == '~') {
      out += "~0";
    } else if (c == '/') {
      out += "~1";
    } else {
      out += c;
    }
  }
  return out;
}

// Where the parser is while it reads the document, so that a repeated key can be reported by
// its JSON pointer (nlohmann-json's parse callbacks give no byte offset).
class PointerTracker {
 public:
  // The pointer of a key that repeats in its object, or nothing.
  std::optional<std::string> on_event(Json::parse_event_t event, const Json& parsed) {
    using Event = Json::parse_event_t;
    switch (event) {
      case Event::object_start:
      case Event::array_start:
        frames_.push_back({event == Event::array_start, 0, "", {}});
        break;
      case Event::key:
        frames_.back().key = parsed.get<std::string>();
        if (!frames_.back().keys.insert(frames_.back().key).second) return pointer();
        break;
      case Event::object_end:
      case Event::array_end:
        frames_.pop_back();
        element_done();
        break;
      case Event::value:
        element_done();
        break;
    }
    return std::nullopt;
  }

 private:
  struct Frame {
    bool array;
    std::size_t index;
    std::string key;
    std::set<std::string> keys;
  };

  void element_done() {
    if (!frames_.empty() && frames_.back().array) ++frames_.back().index;
  }

  std::string pointer() const {
    std::string out;
    for (const Frame& frame : frames_) {
      out = frame.array ? JsonInput::element(out, frame.index) : JsonInput::member(out, frame.key);
    }
    return out;
  }

  std::vector<Frame> frames_;
};

}  // namespace

Json JsonInput::parse(std::string_view text) const {
  PointerTracker tracker;
  const auto refuse_duplicates = [&](int, Json::parse_event_t event, Json& parsed) {
    if (const auto repeated = tracker.on_event(event, parsed)) {
      fail(*repeated,
           fmt::format("key '{}' appears twice in one object", parsed.get<std::string>()));
    }
    return true;
  };
  try {
    return Json::parse(text, refuse_duplicates);
  } catch (const Json::parse_error& e) {
    // e.byte is the offset of the error; turn it into a line and column.
    throw InputError(fmt::format("{}:{}: JSON syntax error: {}", source_,
                                 line_and_column(text, e.byte), e.what()));
  } catch (const Json::exception& e) {
    // A number too large for a double ("1e999") is not a syntax error to the parser but an
    // out_of_range error; any other parser error is bad input too.
    throw InputError(json_number_error(text, source_, e.what()));
  }
}

void JsonInput::fail(const std::string& pointer, const std::string& why) const {
  throw InputError(fmt::format("{}: {}: {}", source_, pointer.empty() ? "/" : pointer, why));
}

std::string JsonInput::member(const std::string& pointer, std::string_view key) {
  return pointer + "/" + json_pointer_token(key);
}

std::string JsonInput::element(const std::string& pointer, std::size_t index) {
  return fmt::format("{}/{}", pointer, index);
}

std::string JsonInput::excerpt(const Json& value) {
  std::string text = value.dump();
  return text.size() > 40 ? text.substr(0, 37) + "..." : text;
}

void JsonInput::require_object(const Json& value, const std::string& pointer) const {
  if (!value.is_object()) fail(pointer, fmt::format("must be an object, not {}", excerpt(value)));
}

void JsonInput::require_array(const Json& value, const std::string& pointer) const {
  if (!value.is_array()) fail(pointer, fmt::format("must be an array, not {}", excerpt(value)));
}

void JsonInput::check_keys(const Json& object, const std::string& pointer,
                           const std::vector<std::string>& valid) const {
  for (const auto& item : object.items()) {
    if (std::find(valid.begin(), valid.end(), item.key()) == valid.end()) {
      fail(member(pointer, item.key()),
           fmt::format("unknown key '{}'; valid keys: {}{}", item.key(), join_names(valid),
                       did_you_mean(item.key(), valid)));
    }
  }
}

const Json& JsonInput::required(const Json& object, const std::string& pointer,
                                const char* key) const {
  if (!object.contains(key)) fail(pointer, fmt::format("missing \"{}\"", key));
  return object[key];
}

std::string JsonInput::string_at(const Json& value, const std::string& pointer) const {
  if (!value.is_string()) fail(pointer, fmt::format("must be a string, not {}", excerpt(value)));
  return value.get<std::string>();
}

bool JsonInput::boolean_at(const Json& value, const std::string& pointer) const {
  if (!value.is_boolean()) {
    fail(pointer, fmt::format("must be true or false, not {}", excerpt(value)));
  }
  return value.get<bool>();
}

double JsonInput::number_at(const Json& value, const std::string& pointer) const {
  if (!value.is_number() || !std::isfinite(value.get<double>())) {
    fail(pointer, fmt::format("must be a finite number, not {}", excerpt(value)));
  }
  return value.get<double>();
}

std::uint64_t JsonInput::integer_at(const Json& value, const std::string& pointer,
                                    std::uint64_t min, std::uint64_t max) const {
  const std::string range = fmt::format("must be an integer in [{}, {}]", min, max);
  if (!value.is_number_integer()) fail(pointer, fmt::format("{}, not {}", range, excerpt(value)));
  const bool negative = !value.is_number_unsigned() && value.get<std::int64_t>() < 0;
  if (negative || value.get<std::uint64_t>() < min || value.get<std::uint64_t>() > max) {
    fail(pointer, fmt::format("{}; {} is out of range", range, excerpt(value)));
  }
  return value.get<std::uint64_t>();
}

std::string JsonInput::choice_at(const Json& value, const std::string& pointer, const char* what,
                                 const std::vector<std::string>& choices) const {
  const std::string name = string_at(value, pointer);
  if (std::find(choices.begin(), choices.end(), name) == choices.end()) {
    fail(pointer, fmt::format("unknown {} '{}'; valid: {}{}", what, name, join_names(choices),
                              did_you_mean(name, choices)));
  }
  return name;
}

}  // namespace pcbench
