// One reader for the JSON files a user writes (suites, scenes, files of estimates): every
// problem is an InputError "SOURCE: POINTER: WHY", where POINTER is the RFC 6901 JSON pointer
// of the value at fault ("/" for the whole document) and SOURCE the file name; syntax errors are
// "SOURCE:LINE:COLUMN: ...". A key that repeats in one object is refused (JSON would let the
// last value silently win), unknown keys get the valid keys and a did-you-mean.
#pragma once

#include <cstdint>
#include <nlohmann/json.hpp>
#include <string>
#include <string_view>
#include <vector>

namespace pcbench {

class JsonInput {
 public:
  using Json = nlohmann::json;

  // `source` names the input in every message (a path, or "fuzz.json").
  explicit JsonInput(std::string source) : source_(std::move(source)) {}

  const std::string& source() const { return source_; }

  // The document in `text`, refusing a repeated key by its pointer.
  Json parse(std::string_view text) const;

  [[noreturn]] void fail(const std::string& pointer, const std::string& why) const;

  // The pointer of member `key` of the object at `pointer`, with '~' and '/' escaped.
  static std::string member(const std::string& pointer, std::string_view key);
  // The pointer of element `index` of the array at `pointer`.
  static std::string element(const std::string& pointer, std::size_t index);
  // A value as the messages quote it: its JSON text, cut to 40 characters.
  static std::string excerpt(const Json& value);

  void require_object(const Json& value, const std::string& pointer) const;
  void require_array(const Json& value, const std::string& pointer) const;
  // Fails on the first key of `object` that is not in `valid`, naming the valid keys and the
  // nearest one.
  void check_keys(const Json& object, const std::string& pointer,
                  const std::vector<std::string>& valid) const;
  // Member `key` of `object`; fails with 'missing "key"' at `pointer` if it is absent.
  const Json& required(const Json& object, const std::string& pointer, const char* key) const;

  std::string string_at(const Json& value, const std::string& pointer) const;
  bool boolean_at(const Json& value, const std::string& pointer) const;
  // A finite number.
  double number_at(const Json& value, const std::string& pointer) const;
  // An integer in [min, max].
  std::uint64_t integer_at(const Json& value, const std::string& pointer, std::uint64_t min,
                           std::uint64_t max) const;
  // A string from the closed set `choices`; `what` names the set ("shape type") in the message.
  std::string choice_at(const Json& value, const std::string& pointer, const char* what,
                        const std::vector<std::string>& choices) const;

 private:
  std::string source_;
};

}  // namespace pcbench
