// Reading JSON input files (scene files, traces, sessions, capture manifests, kiosk
// configuration): one helper, so every loader refuses the same mistakes with the same
// kind of message, `file: field: problem`:
//
//   scene.json: line 12: syntax error while parsing object - unexpected '}'
//   scene.json: room.shell.max[1]: expected a number, got a string
//   scene.json: image.width: 70000 is not in [1, 16384]
//   trace.json: width: expected a number within double's range, got 1e400
//
// JsonDocument::read() bounds the file's size, refuses directories and other non-regular
// files, and parses with nlohmann_json; a JsonValue is one node of the document together
// with its field path ("room.boxes[0].min"), and its typed accessors check the type and
// the range before they convert. Errors are thrown as the loader's own type (throwAs<E>,
// E derived from core::Error), so callers catch TraceError, SceneFileError, ... or
// core::Error.
//
// Cost: the document is held in memory as nlohmann::json; accessors copy the field path
// (a short string) per node. Meant for descriptions, not bulk data (traces keep their
// arrays in a binary sidecar).
#pragma once

#include <array>
#include <cstddef>
#include <cstdint>
#include <filesystem>
#include <initializer_list>
#include <optional>
#include <span>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

#include <nlohmann/json.hpp>

#include "core/error.h"
#include "core/regular_file.h"

namespace penumbra::core {

// A JSON input file larger than this is refused before it is read: every file the project
// reads is a description written by hand or by a tool (the largest, a capture manifest,
// is a few kilobytes), so a bigger one is the wrong file.
inline constexpr uintmax_t kMaxJsonFileBytes = uintmax_t{16} << 20;

class JsonDocument;

// One node of a JsonDocument and its field path. Valid while the document lives.
class JsonValue {
 public:
  const std::string& field() const { return field_; }
  const nlohmann::json& json() const { return *value_; }
  // Throws `file: field: problem` as the document's error type.
  [[noreturn]] void fail(const std::string& problem) const;

  // --- this value, typed --------------------------------------------------------------
  double number() const;
  double number(double lo, double hi) const;  // lo <= v <= hi
  int64_t integer(int64_t lo, int64_t hi) const;
  bool boolean() const;
  std::string string() const;
  std::string nonEmptyString() const;
  // The index in `names` of this string ("expected one of "a", "b", got "c"").
  size_t oneOf(std::span<const std::string_view> names) const;
  size_t oneOf(std::initializer_list<std::string_view> names) const {
    return oneOf(std::span<const std::string_view>(names.begin(), names.size()));
  }
  template <class Enum>
  Enum oneOf(std::initializer_list<std::pair<std::string_view, Enum>> named) const;
  // The elements of an array (fields "path[0]", "path[1]", ...), between minSize and
  // maxSize of them.
  std::vector<JsonValue> array(size_t minSize = 0, size_t maxSize = SIZE_MAX) const;
  // An array of exactly `count` numbers.
  std::vector<double> numbers(size_t count) const;
  // An array of exactly N numbers, each within float's range, converted to float.
  template <size_t N>
  std::array<float, N> floats() const;
  void floats(std::span<float> out) const;
  // Checks that this is an object; returns *this for chaining.
  const JsonValue& object() const;
  // Also refuses keys not in `allowed` ("unknown field"); keys starting with '_' are
  // free-form notes (JSON has no comments).
  const JsonValue& object(std::initializer_list<std::string_view> allowed) const;
  // An object's members in the document's order (nlohmann's: sorted by key).
  std::vector<std::pair<std::string, JsonValue>> members() const;

  // --- members of an object -----------------------------------------------------------
  bool has(std::string_view key) const;
  JsonValue operator[](std::string_view key) const;  // required: "missing" otherwise
  std::optional<JsonValue> find(std::string_view key) const;
  // An optional object member (checked against `allowed` like object()); an absent one
  // reads as {}, so every field of it takes its default.
  JsonValue optionalObject(std::string_view key,
                           std::initializer_list<std::string_view> allowed) const;
  // The elements of an optional array member; none when it is absent.
  std::vector<JsonValue> optionalArray(std::string_view key) const;
  double numberOr(std::string_view key, double fallback, double lo, double hi) const;
  int64_t integerOr(std::string_view key, int64_t fallback, int64_t lo, int64_t hi) const;
  bool booleanOr(std::string_view key, bool fallback) const;
  std::string stringOr(std::string_view key, std::string fallback) const;

 private:
  friend class JsonDocument;
  JsonValue(const JsonDocument* document, const nlohmann::json* value, std::string field)
      : document_(document), value_(value), field_(std::move(field)) {}
  [[noreturn]] void expected(const std::string& what) const;  // "expected X, got Y"

  const JsonDocument* document_;
  const nlohmann::json* value_;
  std::string field_;
};

// A parsed JSON file. Not copyable or movable: its JsonValues point into it.
class JsonDocument {
 public:
  // Reads and parses `path`; its errors name the file as path.string().
  JsonDocument(const std::filesystem::path& path, ErrorThrower raise,
               uintmax_t maxBytes = kMaxJsonFileBytes);
  // Parses `text`, which came from `file`.
  JsonDocument(std::string_view text, std::string file, ErrorThrower raise);
  JsonDocument(const JsonDocument&) = delete;
  JsonDocument& operator=(const JsonDocument&) = delete;

  const std::string& file() const { return file_; }
  JsonValue root() const { return JsonValue(this, &doc_, ""); }
  // Throws `file: field: problem` (`file: problem` when field is empty).
  [[noreturn]] void fail(const std::string& field, const std::string& problem) const;

 private:
  std::string file_;
  ErrorThrower raise_;
  nlohmann::json doc_;
};

// The text of a file of at most maxBytes (core::readRegularFile: refuses directories and
// non-regular files, `file: is a directory`); used by JsonDocument, and by loaders that
// read other text.
std::string readTextFile(const std::filesystem::path& path, ErrorThrower raise,
                         uintmax_t maxBytes = kMaxJsonFileBytes);

// The "format" and "version" every Penumbra file starts with: throws `file: format: expected
// "penumbra-fisheye-lens", got "x"` when the format is another, `file: version: ...` when the
// version is not an integer in [1, maxVersion] (a newer file says so: "written by a newer
// Penumbra"). Returns the version. The caller lists both keys in its object(...) check.
int64_t requireFileFormat(const JsonValue& root, std::string_view format, int64_t maxVersion);

// A number as the messages print it: the shortest text that reads back the same double.
std::string formatNumber(double v);

template <class Enum>
Enum JsonValue::oneOf(std::initializer_list<std::pair<std::string_view, Enum>> named) const {
  std::vector<std::string_view> names;
  for (const auto& n : named) names.push_back(n.first);
  return (named.begin() + oneOf(std::span<const std::string_view>(names)))->second;
}

template <size_t N>
std::array<float, N> JsonValue::floats() const {
  std::array<float, N> out;
  floats(out);
  return out;
}

}  // namespace penumbra::core
