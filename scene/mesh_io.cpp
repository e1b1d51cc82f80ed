#include "scene/mesh_io.h"

#include <algorithm>
#include <bit>
#include <charconv>
#include <cmath>
#include <cstring>
#include <fstream>
#include <iterator>
#include <limits>
#include <optional>
#include <sstream>
#include <system_error>

#include "core/json_reader.h"
#include "scene/gltf_io.h"

namespace penumbra::scene {

Aabb TriangleMesh::bounds() const {
  Aabb b = Aabb::emptyBox();
  for (const glm::dvec3& p : positions) b.extend(p);
  return b;
}

namespace {

[[noreturn]] void fail(const std::string& name, const std::string& where, const std::string& what) {
  throw MeshError(name + ": " + (where.empty() ? "" : where + ": ") + what);
}

std::string lineRef(size_t line) {
  return "line " + std::to_string(line);
}

// Whitespace-separated tokens of one line, at most `maxTokens` + 1 of them: a caller that
// gets more than maxTokens refuses the line, so a 200 MB line of numbers costs no more than
// a short one.
std::vector<std::string_view> tokenize(std::string_view line, size_t maxTokens) {
  std::vector<std::string_view> out;
  size_t i = 0;
  while (i < line.size() && out.size() <= maxTokens) {
    while (i < line.size() && (line[i] == ' ' || line[i] == '\t' || line[i] == '\v' ||
                               line[i] == '\f' || line[i] == '\r')) {
      ++i;
    }
    const size_t start = i;
    while (i < line.size() && !(line[i] == ' ' || line[i] == '\t' || line[i] == '\v' ||
                                line[i] == '\f' || line[i] == '\r')) {
      ++i;
    }
    if (i > start) out.push_back(line.substr(start, i - start));
  }
  return out;
}

// from_chars is locale-independent (strtod is not: a kiosk with a German locale would
// read "0.5" as 0) but rejects a leading '+', which some exporters write.
std::optional<double> parseDouble(std::string_view s) {
  if (!s.empty() && s.front() == '+') s.remove_prefix(1);
  double v = 0;
  const auto [end, ec] = std::from_chars(s.data(), s.data() + s.size(), v);
  if (ec != std::errc() || end != s.data() + s.size()) return std::nullopt;
  return v;
}

std::optional<int64_t> parseInt(std::string_view s) {
  if (!s.empty() && s.front() == '+') s.remove_prefix(1);
  int64_t v = 0;
  const auto [end, ec] = std::from_chars(s.data(), s.data() + s.size(), v);
  if (ec != std::errc() || end != s.data() + s.size()) return std::nullopt;
  return v;
}

// Splits `text` into lines without their terminators; the last line may lack '\n'.
template <typename F>
void forEachLine(std::string_view text, F&& f) {
  size_t lineNo = 1, pos = 0;
  while (pos < text.size()) {
    size_t end = text.find('\n', pos);
    if (end == std::string_view::npos) end = text.size();
    f(lineNo++, text.substr(pos, end - pos));
    pos = end + 1;
  }
}

// A coordinate within the limits of mesh_io.h (the message prints the value as written).
void checkCoordinate(double v, const std::string& name, const std::string& where) {
  if (!std::isfinite(v)) fail(name, where, "non-finite coordinate '" + core::formatNumber(v) + "'");
  if (std::abs(v) > kMaxModelCoordinate) {
    fail(name, where,
         "coordinate " + core::formatNumber(v) +
             " is outside [-1e6, 1e6] (model units: a kilometre in millimetres is the largest " +
             "model read)");
  }
}

void checkVertexCount(size_t count, const std::string& name, const std::string& where) {
  if (count > kMaxMeshVertices) {
    fail(name, where,
         std::to_string(count) + " vertices, more than the " + std::to_string(kMaxMeshVertices) +
             " a model may have");
  }
}

void checkTriangleCount(size_t count, const std::string& name, const std::string& where) {
  if (count > kMaxMeshTriangles) {
    fail(name, where,
         "more than " + std::to_string(kMaxMeshTriangles) +
             " triangles (the most a product model may have)");
  }
}

void checkFaceCorners(size_t corners, const std::string& name, const std::string& where) {
  if (corners > kMaxFaceCorners) {
    fail(name, where,
         "face with more than the " + std::to_string(kMaxFaceCorners) +
             " corners a polygon may have");
  }
}

}  // namespace

// ---------------------------------------------------------------------------------------
// OBJ

TriangleMesh parseObj(std::string_view text, const std::string& name) {
  TriangleMesh mesh;
  std::vector<uint32_t> corners;
  forEachLine(text, [&](size_t lineNo, std::string_view line) {
    if (const size_t hash = line.find('#'); hash != std::string_view::npos) {
      line = line.substr(0, hash);
    }
    const std::vector<std::string_view> tok = tokenize(line, kMaxFaceCorners + 1);
    if (tok.empty()) return;
    if (tok[0] == "v") {
      // x y z, optionally w or an r g b vertex colour: all must be numbers.
      if (tok.size() < 4) fail(name, lineRef(lineNo), "vertex needs x, y and z");
      glm::dvec3 p(0.0);
      for (size_t k = 1; k < tok.size(); ++k) {
        const std::optional<double> v = parseDouble(tok[k]);
        if (!v) fail(name, lineRef(lineNo), "bad number '" + std::string(tok[k]) + "'");
        checkCoordinate(*v, name, lineRef(lineNo));
        if (k <= 3) p[static_cast<int>(k - 1)] = *v;
      }
      mesh.positions.push_back(p);
      checkVertexCount(mesh.positions.size(), name, lineRef(lineNo));
    } else if (tok[0] == "f") {
      if (tok.size() < 4) {
        fail(name, lineRef(lineNo),
             "face needs at least 3 vertices, has " + std::to_string(tok.size() - 1));
      }
      checkFaceCorners(tok.size() - 1, name, lineRef(lineNo));
      corners.clear();
      const int64_t count = static_cast<int64_t>(mesh.positions.size());
      for (size_t k = 1; k < tok.size(); ++k) {
        // Only the position index (before the first '/') matters here.
        const std::string_view ref = tok[k].substr(0, tok[k].find('/'));
        const std::optional<int64_t> idx = parseInt(ref);
        if (!idx) fail(name, lineRef(lineNo), "bad vertex index '" + std::string(tok[k]) + "'");
        // Negative indices count back from the last vertex defined so far (-1 = last).
        const int64_t resolved = *idx > 0 ? *idx - 1 : count + *idx;
        if (*idx == 0 || resolved < 0 || resolved >= count) {
          fail(name, lineRef(lineNo),
               "vertex index " + std::to_string(*idx) + " out of range (" + std::to_string(count) +
                   " vertices defined so far)");
        }
        corners.push_back(static_cast<uint32_t>(resolved));
      }
      checkTriangleCount(mesh.triangleCount() + corners.size() - 2, name, lineRef(lineNo));
      for (size_t k = 1; k + 1 < corners.size(); ++k) {
        mesh.indices.insert(mesh.indices.end(), {corners[0], corners[k], corners[k + 1]});
      }
    }
    // Everything else (vt, vn, g, o, s, usemtl, mtllib, l, p, ...) carries no geometry the
    // shadow pipeline uses.
  });
  if (mesh.indices.empty()) fail(name, "", "no faces");
  return mesh;
}

// ---------------------------------------------------------------------------------------
// PLY

namespace {

enum class PlyType { kInt8, kUInt8, kInt16, kUInt16, kInt32, kUInt32, kFloat32, kFloat64 };

std::optional<PlyType> plyType(std::string_view s) {
  if (s == "char" || s == "int8") return PlyType::kInt8;
  if (s == "uchar" || s == "uint8") return PlyType::kUInt8;
  if (s == "short" || s == "int16") return PlyType::kInt16;
  if (s == "ushort" || s == "uint16") return PlyType::kUInt16;
  if (s == "int" || s == "int32") return PlyType::kInt32;
  if (s == "uint" || s == "uint32") return PlyType::kUInt32;
  if (s == "float" || s == "float32") return PlyType::kFloat32;
  if (s == "double" || s == "float64") return PlyType::kFloat64;
  return std::nullopt;
}

size_t plySize(PlyType t) {
  switch (t) {
    case PlyType::kInt8:
    case PlyType::kUInt8:
      return 1;
    case PlyType::kInt16:
    case PlyType::kUInt16:
      return 2;
    case PlyType::kInt32:
    case PlyType::kUInt32:
    case PlyType::kFloat32:
      return 4;
    case PlyType::kFloat64:
      return 8;
  }
  return 0;
}

bool plyIsInteger(PlyType t) {
  return t != PlyType::kFloat32 && t != PlyType::kFloat64;
}

struct PlyProperty {
  std::string name;
  bool isList = false;
  PlyType countType = PlyType::kUInt8;
  PlyType type = PlyType::kFloat32;
};

struct PlyElement {
  std::string name;
  size_t count = 0;
  std::vector<PlyProperty> properties;
  size_t headerLine = 0;  // of its `element` line, for messages

  // The fewest bytes one record can take: binary, a scalar's size and a list's count (the
  // list may be empty); ASCII, a line of one character and its newline.
  size_t minimumRecordBytes(bool binary) const {
    if (!binary) return 2;
    size_t bytes = 0;
    for (const PlyProperty& p : properties) bytes += plySize(p.isList ? p.countType : p.type);
    return bytes;
  }
};

// One ASCII line holds one record: its scalars and lists of at most kMaxFaceCorners values.
constexpr size_t kMaxPlyLineValues = 4 * kMaxFaceCorners;

// Every element's count is bounded before a record is read: by the stated limits (vertices,
// faces, and kMaxMeshVertices for any other element, which the reader only skips) and by
// the bytes actually present, since each record takes at least minimumRecordBytes(). A
// header announcing 10^12 records of an element without properties is refused here
// instead of being looped over.
void checkElementCounts(const std::vector<PlyElement>& elements, bool binary, size_t bodyBytes,
                        const std::string& name) {
  // ASCII: the last line may lack its newline.
  size_t remaining = binary ? bodyBytes : bodyBytes + 1;
  for (const PlyElement& e : elements) {
    const std::string where = lineRef(e.headerLine) + ": element " + e.name;
    const size_t limit = e.name == "face" ? kMaxMeshTriangles : kMaxMeshVertices;
    if (e.count > limit) {
      fail(name, where,
           std::to_string(e.count) + " records, more than the " + std::to_string(limit) +
               " a model may have");
    }
    const size_t record = e.minimumRecordBytes(binary);
    if (record > 0 && e.count > remaining / record) {
      fail(name, where,
           std::to_string(e.count) + " records of at least " + std::to_string(record) +
               " bytes do not fit in the " + std::to_string(remaining) + " bytes left in the file");
    }
    remaining -= e.count * record;
  }
}

template <typename T>
T loadLittleEndian(const char* p) {
  T v;
  std::memcpy(&v, p, sizeof(T));
  if constexpr (std::endian::native == std::endian::big && sizeof(T) > 1) {
    char b[sizeof(T)];
    std::memcpy(b, &v, sizeof(T));
    std::reverse(b, b + sizeof(T));
    std::memcpy(&v, b, sizeof(T));
  }
  return v;
}

// Reads the values of one element instance either from binary data or from one line of
// ASCII tokens; every value is widened to double (exact for all PLY scalar types).
class PlyReader {
 public:
  PlyReader(std::string_view body, bool binary, const std::string& name)
      : body_(body), binary_(binary), name_(name) {}

  // Positions at the next instance of element `elem` (index `i`).
  void beginInstance(const std::string& elem, size_t i) {
    where_ = elem + " " + std::to_string(i);
    if (binary_) return;
    // ASCII: one instance per line; blank lines are skipped.
    tokens_.clear();
    next_ = 0;
    while (pos_ < body_.size() && tokens_.empty()) {
      size_t end = body_.find('\n', pos_);
      if (end == std::string_view::npos) end = body_.size();
      tokens_ = tokenize(body_.substr(pos_, end - pos_), kMaxPlyLineValues);
      pos_ = end + 1;
      ++line_;
    }
    if (tokens_.size() > kMaxPlyLineValues) {
      fail(name_, location(),
           "more than " + std::to_string(kMaxPlyLineValues) + " values on one line");
    }
    if (tokens_.empty()) fail(name_, where_, "unexpected end of file");
  }

  void endInstance() {
    if (!binary_ && next_ != tokens_.size()) {
      fail(name_, location(),
           std::to_string(tokens_.size() - next_) + " extra value(s) at the end of the line");
    }
  }

  double read(PlyType t) {
    if (binary_) {
      const size_t n = plySize(t);
      if (body_.size() - pos_ < n) {
        fail(name_, where_,
             "truncated binary data (" + std::to_string(body_.size()) + " bytes after the header)");
      }
      const char* p = body_.data() + pos_;
      pos_ += n;
      switch (t) {
        case PlyType::kInt8:
          return loadLittleEndian<int8_t>(p);
        case PlyType::kUInt8:
          return loadLittleEndian<uint8_t>(p);
        case PlyType::kInt16:
          return loadLittleEndian<int16_t>(p);
        case PlyType::kUInt16:
          return loadLittleEndian<uint16_t>(p);
        case PlyType::kInt32:
          return loadLittleEndian<int32_t>(p);
        case PlyType::kUInt32:
          return loadLittleEndian<uint32_t>(p);
        case PlyType::kFloat32:
          return loadLittleEndian<float>(p);
        case PlyType::kFloat64:
          return loadLittleEndian<double>(p);
      }
      return 0;
    }
    if (next_ >= tokens_.size()) fail(name_, location(), "too few values on the line");
    const std::string_view tok = tokens_[next_++];
    if (plyIsInteger(t)) {
      const std::optional<int64_t> v = parseInt(tok);
      if (!v) fail(name_, location(), "bad integer '" + std::string(tok) + "'");
      return static_cast<double>(*v);
    }
    const std::optional<double> v = parseDouble(tok);
    if (!v) fail(name_, location(), "bad number '" + std::string(tok) + "'");
    return *v;
  }

  // After the last element: nothing but whitespace may follow.
  void finish() {
    if (binary_) {
      if (pos_ != body_.size()) {
        fail(name_, "",
             std::to_string(body_.size() - pos_) + " unexpected bytes after the last element");
      }
      return;
    }
    if (pos_ < body_.size() &&
        body_.find_first_not_of(" \t\r\n\v\f", pos_) != std::string_view::npos) {
      fail(name_, "", "unexpected content after the last element");
    }
  }

  // "line N (vertex i)" for ASCII, "vertex i" for binary.
  std::string location() const {
    return binary_ ? where_ : lineRef(headerLines_ + line_) + " (" + where_ + ")";
  }
  void setHeaderLines(size_t n) { headerLines_ = n; }

 private:
  std::string_view body_;
  bool binary_;
  const std::string& name_;
  size_t pos_ = 0;
  std::string where_;
  std::vector<std::string_view> tokens_;
  size_t next_ = 0;
  size_t line_ = 0;
  size_t headerLines_ = 0;
};

}  // namespace

TriangleMesh parsePly(std::string_view bytes, const std::string& name) {
  // Header: ASCII lines up to end_header; the body starts after its '\n'.
  std::vector<PlyElement> elements;
  std::optional<bool> binary;
  size_t pos = 0, lineNo = 0;
  bool ended = false;
  while (pos < bytes.size() && !ended) {
    size_t end = bytes.find('\n', pos);
    if (end == std::string_view::npos) end = bytes.size();
    const std::string_view line = bytes.substr(pos, end - pos);
    pos = std::min(end + 1, bytes.size());
    ++lineNo;
    // A header line has at most 5 tokens; comments may be longer and are skipped.
    const std::vector<std::string_view> tok = tokenize(line, 8);
    const std::string where = lineRef(lineNo);
    if (lineNo == 1) {
      if (tok.size() != 1 || tok[0] != "ply") fail(name, where, "not a PLY file (no 'ply' magic)");
      continue;
    }
    if (tok.empty() || tok[0] == "comment" || tok[0] == "obj_info") continue;
    if (tok[0] == "format") {
      if (tok.size() != 3 || tok[2] != "1.0") fail(name, where, "bad format line");
      if (tok[1] == "ascii") {
        binary = false;
      } else if (tok[1] == "binary_little_endian") {
        binary = true;
      } else {
        fail(name, where,
             "unsupported format '" + std::string(tok[1]) +
                 "' (ascii and binary_little_endian are read)");
      }
    } else if (tok[0] == "element") {
      const std::optional<int64_t> count = tok.size() == 3 ? parseInt(tok[2]) : std::nullopt;
      if (!count || *count < 0) fail(name, where, "bad element line");
      elements.push_back(PlyElement{std::string(tok[1]), static_cast<size_t>(*count), {}, lineNo});
    } else if (tok[0] == "property") {
      if (elements.empty()) fail(name, where, "property before any element");
      PlyProperty prop;
      if (tok.size() == 5 && tok[1] == "list") {
        const auto countType = plyType(tok[2]), type = plyType(tok[3]);
        if (!countType || !type) fail(name, where, "unknown property type");
        if (!plyIsInteger(*countType)) fail(name, where, "list count type must be an integer");
        prop = PlyProperty{std::string(tok[4]), true, *countType, *type};
      } else if (tok.size() == 3) {
        const auto type = plyType(tok[1]);
        if (!type) fail(name, where, "unknown property type '" + std::string(tok[1]) + "'");
        prop = PlyProperty{std::string(tok[2]), false, PlyType::kUInt8, *type};
      } else {
        fail(name, where, "bad property line");
      }
      elements.back().properties.push_back(prop);
    } else if (tok[0] == "end_header") {
      ended = true;
    } else {
      fail(name, where, "unknown header keyword '" + std::string(tok[0]) + "'");
    }
  }
  if (lineNo == 0) fail(name, "", "empty file");
  if (!ended) fail(name, "", "header has no end_header");
  if (!binary) fail(name, "", "header has no format line");

  // Where x, y, z and the face indices sit among the element's properties.
  const PlyElement* vertexElem = nullptr;
  const PlyElement* faceElem = nullptr;
  int xyz[3] = {-1, -1, -1};
  int faceList = -1;
  for (const PlyElement& e : elements) {
    if (e.name == "vertex") {
      vertexElem = &e;
      for (size_t p = 0; p < e.properties.size(); ++p) {
        const PlyProperty& prop = e.properties[p];
        for (int k = 0; k < 3; ++k) {
          if (prop.name == std::string(1, static_cast<char>('x' + k))) {
            if (prop.isList) fail(name, "vertex", "property " + prop.name + " is a list");
            xyz[k] = static_cast<int>(p);
          }
        }
      }
      for (int k = 0; k < 3; ++k) {
        if (xyz[k] < 0) {
          fail(name, "vertex", std::string("no property ") + static_cast<char>('x' + k));
        }
      }
    } else if (e.name == "face") {
      faceElem = &e;
      for (size_t p = 0; p < e.properties.size(); ++p) {
        const PlyProperty& prop = e.properties[p];
        if (prop.name == "vertex_indices" || prop.name == "vertex_index") {
          if (!prop.isList || !plyIsInteger(prop.type)) {
            fail(name, "face", prop.name + " must be a list of integers");
          }
          faceList = static_cast<int>(p);
        }
      }
      if (faceList < 0) fail(name, "face", "no vertex_indices list");
    }
  }
  if (!vertexElem) fail(name, "", "no vertex element");
  if (!faceElem) fail(name, "", "no face element");
  checkElementCounts(elements, *binary, bytes.size() - pos, name);

  TriangleMesh mesh;
  // Faces may precede the vertices in PLY, so indices are checked after reading.
  struct Face {
    size_t first, count;
    std::string location;
  };
  std::vector<int64_t> faceIndices;
  std::vector<Face> faces;
  PlyReader reader(bytes.substr(pos), *binary, name);
  reader.setHeaderLines(lineNo);
  size_t triangles = 0;
  for (const PlyElement& e : elements) {
    const bool isVertex = &e == vertexElem, isFace = &e == faceElem;
    // The count was bounded by checkElementCounts().
    if (isVertex) mesh.positions.reserve(e.count);
    for (size_t i = 0; i < e.count; ++i) {
      reader.beginInstance(e.name, i);
      glm::dvec3 p(0.0);
      for (size_t k = 0; k < e.properties.size(); ++k) {
        const PlyProperty& prop = e.properties[k];
        if (prop.isList) {
          const double n = reader.read(prop.countType);
          if (n < 0) fail(name, reader.location(), "negative list length");
          const bool keep = isFace && static_cast<int>(k) == faceList;
          if (keep) {
            if (n < 3) {
              fail(
                  name, reader.location(),
                  "face needs at least 3 vertices, has " + std::to_string(static_cast<int64_t>(n)));
            }
            checkFaceCorners(static_cast<size_t>(n), name, reader.location());
            triangles += static_cast<size_t>(n) - 2;
            checkTriangleCount(triangles, name, reader.location());
            faces.push_back(Face{faceIndices.size(), static_cast<size_t>(n), reader.location()});
          }
          for (size_t j = 0; j < static_cast<size_t>(n); ++j) {
            const double v = reader.read(prop.type);
            if (keep) faceIndices.push_back(static_cast<int64_t>(v));
          }
        } else {
          const double v = reader.read(prop.type);
          if (isVertex) {
            for (int c = 0; c < 3; ++c) {
              if (static_cast<int>(k) != xyz[c]) continue;
              checkCoordinate(v, name, reader.location());
              p[c] = v;
            }
          }
        }
      }
      reader.endInstance();
      if (isVertex) mesh.positions.push_back(p);
    }
  }
  reader.finish();

  const int64_t vertexCount = static_cast<int64_t>(mesh.positions.size());
  for (const Face& f : faces) {
    for (size_t j = 0; j < f.count; ++j) {
      const int64_t idx = faceIndices[f.first + j];
      if (idx < 0 || idx >= vertexCount) {
        fail(name, f.location,
             "vertex index " + std::to_string(idx) + " out of range (" +
                 std::to_string(vertexCount) + " vertices)");
      }
    }
    for (size_t j = 1; j + 1 < f.count; ++j) {
      mesh.indices.insert(mesh.indices.end(),
                          {static_cast<uint32_t>(faceIndices[f.first]),
                           static_cast<uint32_t>(faceIndices[f.first + j]),
                           static_cast<uint32_t>(faceIndices[f.first + j + 1])});
    }
  }
  if (mesh.indices.empty()) fail(name, "", "no faces");
  return mesh;
}

// ---------------------------------------------------------------------------------------
// Files

TriangleMesh loadMesh(const std::filesystem::path& path) {
  const std::string name = path.string();
  std::string ext = path.extension().string();
  std::transform(ext.begin(), ext.end(), ext.begin(),
                 [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
  if (ext == ".gltf" || ext == ".glb") {
#ifdef PENUMBRA_HAVE_GLTF
    return loadGltf(path).mesh;
#else
    fail(name, "", "this build has no glTF support (PENUMBRA_WITH_GLTF)");
#endif
  }
  if (ext != ".obj" && ext != ".ply") {
    fail(name, "", "unknown mesh format '" + ext + "' (expected .obj, .ply, .gltf or .glb)");
  }
  // Regular files of bounded size only: a product path pointing at /dev/zero or a folder is
  // refused before a byte is read.
  const std::string bytes = core::readTextFile(path, core::throwAs<MeshError>, kMaxModelFileBytes);
  return ext == ".obj" ? parseObj(bytes, name) : parsePly(bytes, name);
}

void saveObj(const TriangleMesh& mesh, const std::filesystem::path& path) {
  std::ofstream out(path, std::ios::binary);
  if (!out) fail(path.string(), "", "cannot create file");
  char buf[64];
  // Shortest round-trip form: the file reloads to the same doubles.
  auto number = [&](double v) {
    const auto r = std::to_chars(buf, buf + sizeof(buf), v);
    out << ' ' << std::string_view(buf, static_cast<size_t>(r.ptr - buf));
  };
  for (const glm::dvec3& p : mesh.positions) {
    out << 'v';
    number(p.x);
    number(p.y);
    number(p.z);
    out << '\n';
  }
  for (size_t t = 0; t < mesh.triangleCount(); ++t) {
    out << "f " << mesh.indices[3 * t] + 1 << ' ' << mesh.indices[3 * t + 1] + 1 << ' '
        << mesh.indices[3 * t + 2] + 1 << '\n';
  }
  out.flush();
  if (!out) fail(path.string(), "", "write error");
}

}  // namespace penumbra::scene
