// A structure-aware mutator for the JSON targets (LLVMFuzzerCustomMutator): byte mutations
// of a JSON file mostly break its syntax, so the loader's field checks behind the parser are
// rarely reached. This one parses the input, changes one or two values the way a person
// editing the file by hand (or a damaged copy) would — numbers to extremes, strings
// emptied or bent, arrays shortened or grown, fields dropped, values of the wrong type —
// and writes the document back. One mutation in four stays a libFuzzer byte mutation, so
// the parser's own error paths stay covered; an input that does not parse gets one too.
//
// Input layout shared by the JSON targets: the JSON text, optionally followed by a NUL byte
// and a binary tail (the frame trace's sidecar buffer). The tail is mutated by bytes.
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <cstring>
#include <limits>
#include <random>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

extern "C" size_t LLVMFuzzerMutate(uint8_t* data, size_t size, size_t maxSize);

namespace {

using nlohmann::json;
using Rng = std::minstd_rand;

size_t pick(Rng& rng, size_t n) {
  return n == 0 ? 0 : size_t(rng()) % n;
}

void collect(json& node, std::vector<json*>& out) {
  out.push_back(&node);
  if (node.is_structured()) {
    for (json& child : node) collect(child, out);
  }
}

// Values at the edges of what loaders convert to: integer widths, float range, signs.
double extremeNumber(Rng& rng) {
  static constexpr double kExtremes[] = {
      0.0,          -0.0,          1.0,          -1.0,         0.5,
      255.0,        256.0,         65535.0,      65536.0,      2147483647.0,
      2147483648.0, -2147483648.0, 4294967295.0, 4294967296.0, 9007199254740993.0,
      1e9,          1e20,          1e38,         3.5e38,       1e308,
      -1e308,       1e-300,        5e-324};
  return kExtremes[pick(rng, std::size(kExtremes))];
}

void mutateNumber(json& v, Rng& rng) {
  const double x = v.get<double>();
  switch (pick(rng, 7)) {
    case 0:
      v = -x;
      break;
    case 1:
      v = x * 2;
      break;
    case 2:
      v = x / 2;
      break;
    case 3:
      v = x + 1;
      break;
    case 4:
      v = int64_t(rng()) - int64_t(Rng::max() / 2);
      break;
    case 5:  // an integer field given a fraction, or a float field an integer
      v = std::trunc(x) == x || !(std::fabs(x) < 9e18) ? json(x + 0.25) : json(int64_t(x));
      break;
    default:
      v = extremeNumber(rng);
      break;
  }
  // JSON has no NaN or infinity: nlohmann would write `null`, a type change rather than a
  // number at the edge.
  if (v.is_number_float() && !std::isfinite(v.get<double>())) v = 1e308;
}

void mutateString(json& v, const std::vector<json*>& nodes, Rng& rng) {
  std::string s = v.get<std::string>();
  switch (pick(rng, 5)) {
    case 0:
      s.clear();
      break;
    case 1:
      s += s;
      break;
    case 2: {  // another string of the document (a field name where a path belongs, ...)
      std::vector<const json*> strings;
      for (const json* n : nodes) {
        if (n->is_string()) strings.push_back(n);
      }
      s = strings[pick(rng, strings.size())]->get<std::string>();
      break;
    }
    case 3: {
      static constexpr const char* kPaths[] = {".",     "..",    "/",      "a/../..",
                                               "x.obj", "x.ply", "x.gltf", "x.glb"};
      s = kPaths[pick(rng, std::size(kPaths))];
      break;
    }
    default: {
      const size_t size = s.size();
      s.resize(size + 16);
      s.resize(LLVMFuzzerMutate(reinterpret_cast<uint8_t*>(s.data()), size, s.size()));
      break;
    }
  }
  v = s;
}

void mutateArray(json& v, Rng& rng) {
  if (v.empty()) {
    v.push_back(extremeNumber(rng));
    return;
  }
  const size_t i = pick(rng, v.size());
  switch (pick(rng, 4)) {
    case 0:
      v.erase(i);
      break;
    case 1:
      v.push_back(json(v[i]));
      break;
    case 2:
      v = json::array();
      break;
    default: {  // a long run of one element: counts and sizes past what a loader expects
      const json element = v[i];
      const size_t copies = 1 + pick(rng, 64);
      for (size_t k = 0; k < copies; ++k) v.push_back(element);
      break;
    }
  }
}

void mutateObject(json& v, Rng& rng) {
  if (v.empty()) {
    v["x"] = 1;
    return;
  }
  auto it = v.begin();
  std::advance(it, std::ptrdiff_t(pick(rng, v.size())));
  const std::string key = it.key();
  switch (pick(rng, 3)) {
    case 0:
      v.erase(key);
      break;  // a required field missing
    case 1:
      v[key + "_"] = *it;
      break;  // an unknown field
    default:
      v[key] = nullptr;
      break;
  }
}

void mutateOnce(json& doc, Rng& rng) {
  std::vector<json*> nodes;
  collect(doc, nodes);
  json& v = *nodes[pick(rng, nodes.size())];
  if (pick(rng, 6) == 0) {  // a value of another kind: type confusion
    const json donor = *nodes[pick(rng, nodes.size())];
    v = donor;
    return;
  }
  if (v.is_number()) {
    mutateNumber(v, rng);
  } else if (v.is_string()) {
    mutateString(v, nodes, rng);
  } else if (v.is_array()) {
    mutateArray(v, rng);
  } else if (v.is_object()) {
    mutateObject(v, rng);
  } else {
    v = extremeNumber(rng);
  }
}

}  // namespace

extern "C" size_t LLVMFuzzerCustomMutator(uint8_t* data, size_t size, size_t maxSize,
                                          unsigned int seed) {
  Rng rng(seed);
  const auto* nul = static_cast<const uint8_t*>(std::memchr(data, 0, size));
  const size_t textSize = nul != nullptr ? size_t(nul - data) : size;
  const size_t tailStart = nul != nullptr ? textSize + 1 : size;
  if (pick(rng, 4) == 0) return LLVMFuzzerMutate(data, size, maxSize);
  if (nul != nullptr && pick(rng, 3) == 0 && maxSize > tailStart) {
    const size_t tailSize =
        LLVMFuzzerMutate(data + tailStart, size - tailStart, maxSize - tailStart);
    return tailStart + tailSize;
  }
  json doc = json::parse(data, data + textSize, nullptr, /*allow_exceptions=*/false);
  if (doc.is_discarded()) return LLVMFuzzerMutate(data, size, maxSize);
  const int mutations = 1 + int(pick(rng, 2));
  for (int m = 0; m < mutations; ++m) mutateOnce(doc, rng);
  // Byte-mutated strings may not be UTF-8, which dump() would throw on: such bytes become
  // U+FFFD (raw invalid bytes still reach the loaders through the byte mutations).
  const std::string text = doc.dump(-1, ' ', false, json::error_handler_t::replace);
  const std::vector<uint8_t> tail(data + tailStart, data + size);
  const size_t total = text.size() + (nul != nullptr ? 1 + tail.size() : 0);
  if (total > maxSize) return LLVMFuzzerMutate(data, size, maxSize);
  std::memcpy(data, text.data(), text.size());
  if (nul != nullptr) {
    data[text.size()] = 0;
    if (!tail.empty()) std::memcpy(data + text.size() + 1, tail.data(), tail.size());
  }
  return total;
}
