#include "core/json_reader.h"

#include <algorithm>
#include <charconv>
#include <cmath>
#include <limits>

namespace penumbra::core {
namespace {

using nlohmann::json;

std::string joinKey(const std::string& path, std::string_view key) {
  return path.empty() ? std::string(key) : path + "." + std::string(key);
}
std::string joinIndex(const std::string& path, size_t i) {
  return path + "[" + std::to_string(i) + "]";
}

// What a value is, for "got Y": numbers and booleans by value (the reader wants to see the
// 3e+20), the rest by kind.
std::string describe(const json& v) {
  switch (v.type()) {
    case json::value_t::null:
      return "null";
    case json::value_t::boolean:
      return v.get<bool>() ? "true" : "false";
    case json::value_t::number_integer:
      return std::to_string(v.get<int64_t>());
    case json::value_t::number_unsigned:
      return std::to_string(v.get<uint64_t>());
    case json::value_t::number_float:
      return formatNumber(v.get<double>());
    case json::value_t::string:
      return "a string";
    case json::value_t::array:
      return "an array of " + std::to_string(v.size());
    case json::value_t::object:
      return "an object";
    default:
      return "a binary value";
  }
}

std::string inQuotes(std::string_view s) {
  constexpr size_t kShown = 40;  // a long wrong string is shown by its start
  std::string out(1, '"');
  out.append(s.substr(0, kShown)).append(s.size() > kShown ? "...\"" : "\"");
  return out;
}

// nlohmann's messages start with "[json.exception.parse_error.101] parse error at line 3,
// column 7: "; the file's message gives the line in its own form, so that prefix goes.
std::string parseProblem(const std::string& what) {
  const size_t column = what.find("column ");
  const size_t colon = column == std::string::npos ? column : what.find(": ", column);
  if (colon != std::string::npos) return what.substr(colon + 2);
  const size_t bracket = what.find("] ");
  return bracket == std::string::npos ? what : what.substr(bracket + 2);
}

// Builds the DOM like nlohmann's own parser and keeps the field path of the value being
// read, so that a number too large for a double (which nlohmann reports as out_of_range.406
// with no place) is reported by field, and a syntax error by line.
class PathTrackingSax : public nlohmann::json_sax<json> {
 public:
  PathTrackingSax(const JsonDocument& doc, std::string_view text, json& root)
      : doc_(doc), text_(text), root_(root) {}

  bool null() override { return add(nullptr); }
  bool boolean(bool v) override { return add(v); }
  bool number_integer(number_integer_t v) override { return add(v); }
  bool number_unsigned(number_unsigned_t v) override { return add(v); }
  bool number_float(number_float_t v, const string_t&) override { return add(v); }
  bool string(string_t& v) override { return add(std::move(v)); }
  bool binary(binary_t& v) override { return add(json::binary(std::move(v))); }
  bool start_object(std::size_t) override { return open(json::object()); }
  bool key(string_t& k) override {
    open_.back().key = k;
    return true;
  }
  bool end_object() override { return close(); }
  bool start_array(std::size_t) override { return open(json::array()); }
  bool end_array() override { return close(); }

  bool parse_error(std::size_t position, const std::string& lastToken,
                   const nlohmann::detail::exception& e) override {
    if (e.id == 406) {  // number overflow: a literal such as 1e400
      doc_.fail(currentField(), "expected a number within double's range, got " + lastToken);
    }
    doc_.fail("", "line " + std::to_string(lineOf(position)) + ": " + parseProblem(e.what()));
  }

 private:
  struct Open {
    json* container;
    std::string key;  // the last key read, for objects
  };

  template <class V>
  json* place(V&& v) {
    if (open_.empty()) {
      root_ = json(std::forward<V>(v));
      return &root_;
    }
    json& parent = *open_.back().container;
    if (parent.is_array()) {
      parent.push_back(json(std::forward<V>(v)));
      return &parent.back();
    }
    json& slot = parent[open_.back().key];
    slot = json(std::forward<V>(v));
    return &slot;
  }
  template <class V>
  bool add(V&& v) {
    place(std::forward<V>(v));
    return true;
  }
  bool open(json empty) {
    json* container = place(std::move(empty));
    open_.push_back({container, {}});
    return true;
  }
  bool close() {
    open_.pop_back();
    return true;
  }

  // The field of the value the parser is reading now. An enclosing array already holds
  // the open element (its last); the innermost one has not received the value yet.
  std::string currentField() const {
    std::string path;
    for (size_t i = 0; i < open_.size(); ++i) {
      const json& c = *open_[i].container;
      const bool innermost = i + 1 == open_.size();
      path = c.is_array() ? joinIndex(path, innermost ? c.size() : c.size() - 1)
                          : joinKey(path, open_[i].key);
    }
    return path;
  }
  size_t lineOf(size_t position) const {
    const size_t end = std::min(position, text_.size());
    return 1 + static_cast<size_t>(std::count(text_.begin(), text_.begin() + end, '\n'));
  }

  const JsonDocument& doc_;
  std::string_view text_;
  json& root_;
  std::vector<Open> open_;
};

}  // namespace

std::string formatNumber(double v) {
  char buf[32];
  const auto [end, ec] = std::to_chars(buf, buf + sizeof buf, v);
  return ec == std::errc() ? std::string(buf, end) : std::string("?");
}

std::string readTextFile(const std::filesystem::path& path, ErrorThrower raise,
                         uintmax_t maxBytes) {
  const std::vector<uint8_t> bytes = readRegularFile(path, maxBytes, "a JSON input file", raise);
  return std::string(bytes.begin(), bytes.end());
}

JsonDocument::JsonDocument(const std::filesystem::path& path, ErrorThrower raise,
                           uintmax_t maxBytes)
    : JsonDocument(readTextFile(path, raise, maxBytes), path.string(), raise) {}

JsonDocument::JsonDocument(std::string_view text, std::string file, ErrorThrower raise)
    : file_(std::move(file)), raise_(raise) {
  PathTrackingSax sax(*this, text, doc_);
  json::sax_parse(text.begin(), text.end(), &sax);
}

void JsonDocument::fail(const std::string& field, const std::string& problem) const {
  const Error e(file_, field, problem);
  raise_(e.what());
  throw Error(e);  // a thrower that returns still ends the read
}

// --- JsonValue ---------------------------------------------------------------------------

void JsonValue::fail(const std::string& problem) const {
  document_->fail(field_, problem);
}

void JsonValue::expected(const std::string& what) const {
  fail("expected " + what + ", got " + describe(*value_));
}

double JsonValue::number() const {
  if (!value_->is_number()) expected("a number");
  return value_->get<double>();  // finite: the parser refuses NaN, Inf and overflow
}

double JsonValue::number(double lo, double hi) const {
  const double v = number();
  if (!(v >= lo && v <= hi)) {
    fail(formatNumber(v) + " is not in [" + formatNumber(lo) + ", " + formatNumber(hi) + "]");
  }
  return v;
}

int64_t JsonValue::integer(int64_t lo, int64_t hi) const {
  if (!value_->is_number_integer()) expected("an integer");
  // nlohmann keeps non-negative integers as unsigned: above INT64_MAX is out of any range.
  if (value_->is_number_unsigned() &&
      value_->get<uint64_t>() > static_cast<uint64_t>(std::numeric_limits<int64_t>::max())) {
    fail(describe(*value_) + " is not in [" + std::to_string(lo) + ", " + std::to_string(hi) + "]");
  }
  const int64_t v = value_->get<int64_t>();
  if (v < lo || v > hi) {
    fail(std::to_string(v) + " is not in [" + std::to_string(lo) + ", " + std::to_string(hi) + "]");
  }
  return v;
}

bool JsonValue::boolean() const {
  if (!value_->is_boolean()) expected("true or false");
  return value_->get<bool>();
}

std::string JsonValue::string() const {
  if (!value_->is_string()) expected("a string");
  return value_->get<std::string>();
}

std::string JsonValue::nonEmptyString() const {
  if (!value_->is_string() || value_->get_ref<const std::string&>().empty()) {
    expected("a non-empty string");
  }
  return value_->get<std::string>();
}

size_t JsonValue::oneOf(std::span<const std::string_view> names) const {
  std::string list;
  for (std::string_view n : names) list += (list.empty() ? "" : ", ") + inQuotes(n);
  if (!value_->is_string()) expected("one of " + list);
  const std::string& s = value_->get_ref<const std::string&>();
  const auto it = std::find(names.begin(), names.end(), s);
  if (it == names.end()) fail("expected one of " + list + ", got " + inQuotes(s));
  return static_cast<size_t>(it - names.begin());
}

std::vector<JsonValue> JsonValue::array(size_t minSize, size_t maxSize) const {
  if (!value_->is_array()) expected("an array");
  if (value_->size() < minSize || value_->size() > maxSize) {
    const std::string bound = maxSize == SIZE_MAX
                                  ? "at least " + std::to_string(minSize)
                                  : std::to_string(minSize) + " to " + std::to_string(maxSize);
    fail("expected an array of " + bound + " elements, got " + std::to_string(value_->size()));
  }
  std::vector<JsonValue> elements;
  elements.reserve(value_->size());
  for (size_t i = 0; i < value_->size(); ++i) {
    elements.push_back(JsonValue(document_, &(*value_)[i], joinIndex(field_, i)));
  }
  return elements;
}

std::vector<double> JsonValue::numbers(size_t count) const {
  if (!value_->is_array() || value_->size() != count) {
    expected("an array of " + std::to_string(count) + " numbers");
  }
  std::vector<double> out;
  out.reserve(count);
  for (const JsonValue& e : array()) out.push_back(e.number());
  return out;
}

void JsonValue::floats(std::span<float> out) const {
  const std::vector<double> v = numbers(out.size());
  constexpr double kMax = std::numeric_limits<float>::max();
  for (size_t i = 0; i < out.size(); ++i) {
    if (!(v[i] >= -kMax && v[i] <= kMax)) {
      JsonValue(document_, &(*value_)[i], joinIndex(field_, i))
          .fail("expected a number within float's range, got " + formatNumber(v[i]));
    }
    out[i] = static_cast<float>(v[i]);
  }
}

const JsonValue& JsonValue::object() const {
  if (!value_->is_object()) expected("an object");
  return *this;
}

const JsonValue& JsonValue::object(std::initializer_list<std::string_view> allowed) const {
  object();
  for (const auto& [key, value] : value_->items()) {
    if (!key.empty() && key[0] == '_') continue;
    if (std::find(allowed.begin(), allowed.end(), key) == allowed.end()) {
      document_->fail(joinKey(field_, key), "unknown field");
    }
  }
  return *this;
}

std::vector<std::pair<std::string, JsonValue>> JsonValue::members() const {
  object();
  std::vector<std::pair<std::string, JsonValue>> out;
  for (auto it = value_->begin(); it != value_->end(); ++it) {
    out.emplace_back(it.key(), JsonValue(document_, &*it, joinKey(field_, it.key())));
  }
  return out;
}

bool JsonValue::has(std::string_view key) const {
  return value_->is_object() && value_->find(key) != value_->end();
}

JsonValue JsonValue::operator[](std::string_view key) const {
  object();
  const auto it = value_->find(key);
  if (it == value_->end()) document_->fail(joinKey(field_, key), "missing");
  return JsonValue(document_, &*it, joinKey(field_, key));
}

std::optional<JsonValue> JsonValue::find(std::string_view key) const {
  object();
  const auto it = value_->find(key);
  if (it == value_->end()) return std::nullopt;
  return JsonValue(document_, &*it, joinKey(field_, key));
}

JsonValue JsonValue::optionalObject(std::string_view key,
                                    std::initializer_list<std::string_view> allowed) const {
  static const nlohmann::json kEmpty = nlohmann::json::object();
  const std::optional<JsonValue> v = find(key);
  JsonValue member = v ? *v : JsonValue(document_, &kEmpty, joinKey(field_, key));
  member.object(allowed);
  return member;
}

std::vector<JsonValue> JsonValue::optionalArray(std::string_view key) const {
  const std::optional<JsonValue> v = find(key);
  return v ? v->array() : std::vector<JsonValue>{};
}

double JsonValue::numberOr(std::string_view key, double fallback, double lo, double hi) const {
  const std::optional<JsonValue> v = find(key);
  return v ? v->number(lo, hi) : fallback;
}

int64_t JsonValue::integerOr(std::string_view key, int64_t fallback, int64_t lo, int64_t hi) const {
  const std::optional<JsonValue> v = find(key);
  return v ? v->integer(lo, hi) : fallback;
}

bool JsonValue::booleanOr(std::string_view key, bool fallback) const {
  const std::optional<JsonValue> v = find(key);
  return v ? v->boolean() : fallback;
}

std::string JsonValue::stringOr(std::string_view key, std::string fallback) const {
  const std::optional<JsonValue> v = find(key);
  return v ? v->string() : std::move(fallback);
}

int64_t requireFileFormat(const JsonValue& root, std::string_view format, int64_t maxVersion) {
  const JsonValue f = root["format"];
  if (!f.json().is_string() || f.json().get<std::string>() != format) {
    f.fail("expected " + inQuotes(format) + ", got " +
           (f.json().is_string() ? inQuotes(f.json().get<std::string>()) : describe(f.json())));
  }
  const JsonValue v = root["version"];
  if (v.json().is_number_integer() && v.json().get<int64_t>() > maxVersion) {
    std::string problem = std::to_string(v.json().get<int64_t>());
    problem.append(": written by a newer Penumbra (this one reads ")
        .append(format)
        .append(" version 1 to ")
        .append(std::to_string(maxVersion))
        .append(")");
    v.fail(problem);
  }
  return v.integer(1, maxVersion);
}

}  // namespace penumbra::core
