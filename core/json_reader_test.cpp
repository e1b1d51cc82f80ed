#include "core/json_reader.h"

#include <fstream>

#include <gtest/gtest.h>

namespace penumbra::core {
namespace {

class SceneError : public Error {
 public:
  using Error::Error;
};

// The message `text` (parsed as "scene.json") throws when `read` reads it, as SceneError.
template <class Read>
std::string errorOf(const std::string& text, Read read) {
  try {
    const JsonDocument doc(text, "scene.json", throwAs<SceneError>);
    read(doc.root());
  } catch (const SceneError& e) {
    return e.what();
  }
  return "no error";
}

TEST(JsonReader, ReadsTypedFields) {
  const JsonDocument doc(
      R"({"a": {"b": [1.5, -2, 3]}, "n": 7, "ok": true, "s": "x", "mode": "fixed8_8"})", "f.json",
      throwAs<SceneError>);
  const JsonValue root = doc.root();
  EXPECT_EQ(root["a"]["b"].numbers(3), (std::vector<double>{1.5, -2, 3}));
  EXPECT_EQ(root["a"]["b"].floats<3>(), (std::array<float, 3>{1.5f, -2.0f, 3.0f}));
  EXPECT_EQ(root["n"].integer(0, 10), 7);
  EXPECT_EQ(root["n"].number(0, 10), 7.0);
  EXPECT_TRUE(root["ok"].boolean());
  EXPECT_EQ(root["s"].string(), "x");
  EXPECT_EQ(root["mode"].oneOf({"u8", "fixed8_8"}), 1u);
  EXPECT_EQ(root.numberOr("absent", 0.25, 0, 1), 0.25);
  EXPECT_EQ(root.integerOr("n", 3, 0, 10), 7);
  EXPECT_FALSE(root.booleanOr("absent", false));
  EXPECT_EQ(root.stringOr("absent", "d"), "d");
  EXPECT_FALSE(root.find("absent").has_value());
  EXPECT_EQ(root["a"]["b"].array()[2].field(), "a.b[2]");
  EXPECT_EQ(root.optionalObject("absent", {"x"}).integerOr("x", 4, 0, 9), 4);
  EXPECT_EQ(root.optionalObject("a", {"b"})["b"].field(), "a.b");
  EXPECT_TRUE(root.optionalArray("absent").empty());
  EXPECT_EQ(root.optionalArray("a.b").size(), 0u);  // a key, not a path
}

TEST(JsonReader, WrongTypeNamesFileFieldAndBothTypes) {
  EXPECT_EQ(errorOf(R"({"room": {"shell": {"max": "high"}}})",
                    [](const JsonValue& r) { r["room"]["shell"]["max"].number(); }),
            "scene.json: room.shell.max: expected a number, got a string");
  EXPECT_EQ(errorOf(R"({"n": 2.5})", [](const JsonValue& r) { r["n"].integer(0, 9); }),
            "scene.json: n: expected an integer, got 2.5");
  EXPECT_EQ(errorOf(R"({"b": 1})", [](const JsonValue& r) { r["b"].boolean(); }),
            "scene.json: b: expected true or false, got 1");
  EXPECT_EQ(errorOf(R"({"m": [1, "x", 3]})", [](const JsonValue& r) { r["m"].floats<3>(); }),
            "scene.json: m[1]: expected a number, got a string");
  EXPECT_EQ(errorOf(R"({"m": [1, 2]})", [](const JsonValue& r) { r["m"].floats<3>(); }),
            "scene.json: m: expected an array of 3 numbers, got an array of 2");
  EXPECT_EQ(errorOf(R"([])", [](const JsonValue& r) { r["x"]; }),
            "scene.json: expected an object, got an array of 0");
}

TEST(JsonReader, MissingAndUnknownFields) {
  EXPECT_EQ(errorOf(R"({"a": {}})", [](const JsonValue& r) { r["a"]["width"]; }),
            "scene.json: a.width: missing");
  EXPECT_EQ(errorOf(R"({"a": 1, "_note": "free", "typo": 2})",
                    [](const JsonValue& r) { r.object({"a"}); }),
            "scene.json: typo: unknown field");
}

TEST(JsonReader, RangesAreChecked) {
  EXPECT_EQ(errorOf(R"({"x": 3e20})", [](const JsonValue& r) { r["x"].number(-1e6, 1e6); }),
            "scene.json: x: 3e+20 is not in [-1e+06, 1e+06]");
  EXPECT_EQ(errorOf(R"({"w": 70000})", [](const JsonValue& r) { r["w"].integer(1, 16384); }),
            "scene.json: w: 70000 is not in [1, 16384]");
  EXPECT_EQ(errorOf(R"({"w": 18446744073709551615})",
                    [](const JsonValue& r) { r["w"].integer(1, 16384); }),
            "scene.json: w: 18446744073709551615 is not in [1, 16384]");
  EXPECT_EQ(errorOf(R"({"f": [1e39]})", [](const JsonValue& r) { r["f"].floats<1>(); }),
            "scene.json: f[0]: expected a number within float's range, got 1e+39");
  EXPECT_EQ(errorOf(R"({"l": [1, 2, 3]})", [](const JsonValue& r) { r["l"].array(1, 2); }),
            "scene.json: l: expected an array of 1 to 2 elements, got 3");
  EXPECT_EQ(errorOf(R"({"a": "avx3"})",
                    [](const JsonValue& r) {
                      r["a"].oneOf({"scalar", "avx2"});
                    }),
            "scene.json: a: expected one of \"scalar\", \"avx2\", got \"avx3\"");
}

TEST(JsonReader, OverflowingNumberIsReportedByField) {
  EXPECT_EQ(errorOf(R"({"room": {"boxes": [{"min": [0, 1e400, 0]}]}})", [](const JsonValue&) {}),
            "scene.json: room.boxes[0].min[1]: expected a number within double's range, got "
            "1e400");
}

TEST(JsonReader, SyntaxErrorIsReportedByLine) {
  const std::string e = errorOf("{\n  \"a\": 1,\n  \"b\": }\n", [](const JsonValue&) {});
  EXPECT_EQ(e.rfind("scene.json: line 3: syntax error", 0), 0u) << e;
  EXPECT_EQ(e.find("[json.exception"), std::string::npos) << e;
}

TEST(JsonReader, EnumByName) {
  enum class Mode { kA, kB };
  const JsonDocument doc(R"({"m": "b"})", "f.json", throwAs<SceneError>);
  EXPECT_EQ(doc.root()["m"].oneOf<Mode>({{"a", Mode::kA}, {"b", Mode::kB}}), Mode::kB);
}

TEST(JsonReader, FilesAreBoundedAndRegular) {
  const std::filesystem::path dir = std::filesystem::path(::testing::TempDir()) / "json_reader";
  std::filesystem::create_directories(dir);
  const auto messageOf = [](const std::filesystem::path& p, uintmax_t maxBytes) -> std::string {
    try {
      const JsonDocument doc(p, throwAs<SceneError>, maxBytes);
    } catch (const Error& e) {  // the base type catches every domain error
      return e.what();
    }
    return "no error";
  };
  EXPECT_EQ(messageOf(dir, 100), dir.string() + ": is a directory");
  EXPECT_EQ(messageOf("/dev/null", 100),
            "/dev/null: is not a regular file (a device, fifo or socket)");
  EXPECT_EQ(messageOf(dir / "absent.json", 100),
            (dir / "absent.json").string() + ": cannot open file (no such file)");
  const std::filesystem::path big = dir / "big.json";
  std::ofstream(big) << R"({"a": "0123456789"})";
  EXPECT_EQ(messageOf(big, 8),
            big.string() + ": is 19 bytes, more than the 8 a JSON input file may have");
  EXPECT_EQ(messageOf(big, 100), "no error");
}

TEST(JsonReader, FileFormatAndVersion) {
  const auto check = [](const JsonValue& j) { requireFileFormat(j, "penumbra-x", 2); };
  EXPECT_EQ(errorOf(R"({"format": "penumbra-x", "version": 2})", check), "no error");
  EXPECT_EQ(errorOf(R"({"format": "penumbra-y", "version": 1})", check),
            R"(scene.json: format: expected "penumbra-x", got "penumbra-y")");
  EXPECT_EQ(errorOf(R"({"format": 3, "version": 1})", check),
            R"(scene.json: format: expected "penumbra-x", got 3)");
  EXPECT_EQ(errorOf(R"({"version": 1})", check), "scene.json: format: missing");
  EXPECT_EQ(errorOf(R"({"format": "penumbra-x"})", check), "scene.json: version: missing");
  EXPECT_EQ(errorOf(R"({"format": "penumbra-x", "version": 3})", check),
            "scene.json: version: 3: written by a newer Penumbra (this one reads penumbra-x "
            "version 1 to 2)");
  EXPECT_EQ(errorOf(R"({"format": "penumbra-x", "version": 0})", check),
            "scene.json: version: 0 is not in [1, 2]");
  EXPECT_EQ(errorOf(R"({"format": "penumbra-x", "version": 1.5})", check),
            "scene.json: version: expected an integer, got 1.5");
}

}  // namespace
}  // namespace penumbra::core
