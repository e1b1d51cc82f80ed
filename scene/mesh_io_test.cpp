#include "scene/mesh_io.h"

#include <gtest/gtest.h>

#include <chrono>
#include <cmath>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <functional>
#include <initializer_list>
#include <limits>
#include <set>
#include <string>
#include <utility>
#include <vector>
#include "tests/test_data.h"

namespace penumbra::scene {
namespace {

namespace fs = std::filesystem;

using penumbra::testing::dataDir;

// A fresh folder per test, removed afterwards.
class MeshIo : public ::testing::Test {
 protected:
  void SetUp() override {
    const auto* info = ::testing::UnitTest::GetInstance()->current_test_info();
    dir_ = fs::temp_directory_path() / ("penumbra_mesh_io_" + std::string(info->name()));
    fs::remove_all(dir_);
    fs::create_directories(dir_);
  }
  void TearDown() override { fs::remove_all(dir_); }

  fs::path write(const std::string& name, const std::string& bytes) const {
    const fs::path p = dir_ / name;
    std::ofstream(p, std::ios::binary) << bytes;
    return p;
  }

  fs::path dir_;
};

// The MeshError message of `f`, or "" when it does not throw one.
std::string errorOf(const std::function<void()>& f) {
  try {
    f();
  } catch (const MeshError& e) {
    return e.what();
  }
  return "";
}

void expectError(const std::function<void()>& f, std::initializer_list<const char*> parts) {
  const std::string msg = errorOf(f);
  ASSERT_FALSE(msg.empty()) << "no MeshError";
  for (const char* part : parts) EXPECT_NE(msg.find(part), std::string::npos) << msg;
}

// Binary little-endian body builder.
struct Bytes {
  std::string data;
  template <typename T>
  Bytes& put(T v) {
    char b[sizeof(T)];
    std::memcpy(b, &v, sizeof(T));
    data.append(b, sizeof(T));
    return *this;
  }
};

// Each triangle corner's position, in index order: what a mesh draws, whatever its vertex
// numbering.
std::vector<glm::dvec3> cornerPositions(const TriangleMesh& m) {
  std::vector<glm::dvec3> out;
  for (uint32_t i : m.indices) out.push_back(m.positions[i]);
  return out;
}

TEST_F(MeshIo, ObjPolygonsBecomeFansAndNegativeIndicesCountBack) {
  write("shape.mtl", "newmtl red\nKd 1 0 0\n");
  const fs::path p = write("shape.obj",
                           "# a square and a triangle\r\n"
                           "mtllib shape.mtl\n"
                           "v 0 0 0\nv 1 0 0\nv 1 1 0   # trailing comment\nv 0 1 0\n"
                           "vt 0 0\nvn 0 0 1\n"
                           "o square\nusemtl red\ns off\n"
                           "f 1/1/1 2/1/1 3/1/1 4/1/1\n"
                           "v 0 0 +2.5e0 1.0\n"
                           "f -5//1 -4//1 -1//1\n");
  const TriangleMesh m = loadMesh(p);
  ASSERT_EQ(m.positions.size(), 5u);
  EXPECT_EQ(m.positions[4], glm::dvec3(0, 0, 2.5));
  EXPECT_EQ(m.indices, (std::vector<uint32_t>{0, 1, 2, 0, 2, 3, 0, 1, 4}));
  EXPECT_EQ(m.triangleCount(), 3u);
  // Every corner names the one vn: the file's normal; the material's Kd on every vertex.
  EXPECT_EQ(m.normals, std::vector<glm::dvec3>(5, glm::dvec3(0, 0, 1)));
  EXPECT_EQ(m.reflectances, std::vector<glm::dvec3>(5, glm::dvec3(1, 0, 0)));
  EXPECT_TRUE(m.warnings.empty());
}

TEST_F(MeshIo, ObjErrorsNameFileLineAndProblem) {
  const std::string v3 = "v 0 0 0\nv 1 0 0\nv 0 1 0\n";
  expectError([&] { loadMesh(write("zero.obj", v3 + "f 0 1 2\n")); },
              {"zero.obj", "line 4", "vertex index 0 out of range"});
  expectError([&] { loadMesh(write("big.obj", v3 + "f 1 2 4\n")); },
              {"big.obj", "line 4", "vertex index 4 out of range", "3 vertices"});
  expectError([&] { loadMesh(write("neg.obj", v3 + "f -1 -2 -4\n")); },
              {"line 4", "vertex index -4 out of range"});
  expectError([&] { loadMesh(write("nan.obj", "v 0 nan 0\n")); },
              {"nan.obj", "line 1", "non-finite coordinate"});
  expectError([&] { loadMesh(write("inf.obj", "v 0 0 -inf\n")); }, {"non-finite coordinate"});
  expectError([&] { loadMesh(write("num.obj", "v 0 0x1 0\n")); }, {"line 1", "bad number"});
  expectError([&] { loadMesh(write("short.obj", "v 0 1\n")); },
              {"line 1", "vertex needs x, y and z"});
  expectError([&] { loadMesh(write("two.obj", v3 + "f 1 2\n")); },
              {"line 4", "at least 3 vertices"});
  expectError([&] { loadMesh(write("idx.obj", v3 + "f 1 two 3\n")); },
              {"line 4", "bad vertex index 'two'"});
  expectError([&] { loadMesh(write("empty.obj", v3)); }, {"empty.obj", "no faces"});
}

TEST_F(MeshIo, UnknownFormatAndMissingFile) {
  expectError([&] { loadMesh(write("model.stl", "solid x\n")); },
              {"model.stl", "unknown mesh format '.stl'"});
  expectError([&] { loadMesh(dir_ / "absent.ply"); }, {"absent.ply", "cannot open"});
  expectError([&] { loadMesh(write("fake.ply", "solid x\n")); }, {"fake.ply", "not a PLY"});
}

const char* const kAsciiHeader =
    "ply\r\n"
    "format ascii 1.0\r\n"
    "comment written by hand\r\n"
    "element vertex 4\r\n"
    "property double x\r\nproperty double y\r\nproperty double z\r\n"
    "property uchar red\r\n"
    "element face 2\r\n"
    "property list uchar int vertex_indices\r\n"
    "property float quality\r\n"
    "element edge 1\r\n"
    "property int vertex1\r\nproperty int vertex2\r\n"
    "end_header\r\n";

TEST_F(MeshIo, AsciiPlyWithExtraPropertiesAndElements) {
  const TriangleMesh m = loadMesh(write("a.PLY", std::string(kAsciiHeader) +
                                                     "0 0 0 255\n1 0 0 0\n\n1 1 0 0\n0 1 1.5 7\n"
                                                     "4 0 1 2 3 0.5\n3 3 2 1 1\n"
                                                     "0 1\n"));
  // The quad is not planar and the triangle lies back to back with half of it (a crease of
  // 180 degrees): vertices split, the corners keep their positions.
  const glm::dvec3 p0(0, 0, 0), p1(1, 0, 0), p2(1, 1, 0), p3(0, 1, 1.5);
  EXPECT_EQ(cornerPositions(m), (std::vector<glm::dvec3>{p0, p1, p2, p0, p2, p3, p3, p2, p1}));
  EXPECT_EQ(m.normals.size(), m.positions.size());
}

TEST_F(MeshIo, AsciiPlyErrors) {
  const std::string h = kAsciiHeader;  // 15 header lines
  const std::string verts = "0 0 0 1\n1 0 0 1\n1 1 0 1\n0 1 0 1\n";
  expectError([&] { loadMesh(write("i.ply", h + verts + "3 0 1 9 0\n3 0 1 2 0\n0 1\n")); },
              {"i.ply", "face 0", "vertex index 9 out of range (4 vertices)"});
  expectError([&] { loadMesh(write("n.ply", h + "0 0 0 1\n1 nan 0 1\n")); },
              {"n.ply", "line 17", "vertex 1", "non-finite coordinate"});
  expectError([&] { loadMesh(write("f.ply", h + "0 0 0 1\n1 0 0\n")); },
              {"line 17", "too few values"});
  expectError([&] { loadMesh(write("x.ply", h + verts + "3 0 1 2 0 5\n")); },
              {"line 20", "face 0", "extra value"});
  expectError([&] { loadMesh(write("t.ply", h + verts + "3 0 1 2 0\n")); },
              {"face 1", "unexpected end of file"});
  expectError([&] { loadMesh(write("c.ply", h + verts + "3 0 1.5 2 0\n")); },
              {"face 0", "bad integer '1.5'"});
  expectError([&] { loadMesh(write("l.ply", h + verts + "2 0 1 0\n")); },
              {"face 0", "at least 3 vertices"});
  expectError([&] { loadMesh(write("z.ply", h + verts + "3 0 1 2 0\n3 0 1 2 0\n0 1\nmore\n")); },
              {"unexpected content after the last element"});
}

TEST_F(MeshIo, PlyHeaderErrors) {
  expectError([&] { loadMesh(write("be.ply", "ply\nformat binary_big_endian 1.0\nend_header\n")); },
              {"be.ply", "line 2", "unsupported format 'binary_big_endian'"});
  expectError([&] { loadMesh(write("eh.ply", "ply\nformat ascii 1.0\nelement vertex 0\n")); },
              {"no end_header"});
  expectError([&] { loadMesh(write("nf.ply", "ply\nelement vertex 0\nend_header\n")); },
              {"no format line"});
  expectError(
      [&] {
        loadMesh(write("nv.ply",
                       "ply\nformat ascii 1.0\nelement face 0\n"
                       "property list uchar int vertex_indices\nend_header\n"));
      },
      {"no vertex element"});
  expectError(
      [&] {
        loadMesh(write("ny.ply",
                       "ply\nformat ascii 1.0\nelement vertex 0\nproperty float x\n"
                       "property float z\nend_header\n"));
      },
      {"vertex", "no property y"});
  expectError(
      [&] {
        loadMesh(write("ty.ply",
                       "ply\nformat ascii 1.0\nelement vertex 1\n"
                       "property float128 x\nend_header\n"));
      },
      {"line 4", "unknown property type 'float128'"});
  expectError([&] { loadMesh(write("kw.ply", "ply\nformat ascii 1.0\nbogus\nend_header\n")); },
              {"line 3", "unknown header keyword 'bogus'"});
}

std::string binaryHeader(int vertices, int faces, const char* coordType, const char* listTypes) {
  return std::string("ply\nformat binary_little_endian 1.0\nelement vertex ") +
         std::to_string(vertices) + "\nproperty " + coordType + " x\nproperty " + coordType +
         " y\nproperty " + coordType + " z\nelement face " + std::to_string(faces) +
         "\nproperty list " + listTypes + " vertex_indices\nend_header\n";
}

TEST_F(MeshIo, BinaryPlyFloatAndDouble) {
  Bytes f;
  for (float v : {0.f, 0.f, 0.f, 1.f, 0.f, 0.f, 0.f, 1.f, 0.25f}) f.put(v);
  f.put<uint8_t>(3).put<int32_t>(0).put<int32_t>(1).put<int32_t>(2);
  const TriangleMesh a =
      loadMesh(write("f.ply", binaryHeader(3, 1, "float", "uchar int") + f.data));
  EXPECT_EQ(a.positions[2], glm::dvec3(0, 1, 0.25));
  EXPECT_EQ(a.indices, (std::vector<uint32_t>{0, 1, 2}));

  Bytes d;
  for (double v : {0.0, 0.0, 0.0, 1.0, 0.0, 0.0, 1.0, 1.0, 0.1, 0.0, 1.0, 0.0}) d.put(v);
  d.put<uint8_t>(4).put<uint32_t>(0).put<uint32_t>(1).put<uint32_t>(2).put<uint32_t>(3);
  const TriangleMesh b =
      loadMesh(write("d.ply", binaryHeader(4, 1, "double", "uint8 uint32") + d.data));
  EXPECT_EQ(b.positions[2], glm::dvec3(1, 1, 0.1));  // doubles are kept exactly
  EXPECT_EQ(b.indices, (std::vector<uint32_t>{0, 1, 2, 0, 2, 3}));
}

TEST_F(MeshIo, BinaryPlyErrors) {
  Bytes verts;
  for (float v : {0.f, 0.f, 0.f, 1.f, 0.f, 0.f, 0.f, 1.f, 0.f}) verts.put(v);
  const std::string h = binaryHeader(3, 1, "float", "uchar int");
  Bytes face;
  face.put<uint8_t>(3).put<int32_t>(0).put<int32_t>(1).put<int32_t>(2);
  const std::string good = h + verts.data + face.data;
  expectError([&] { loadMesh(write("t.ply", good.substr(0, good.size() - 2))); },
              {"t.ply", "face 0", "truncated binary data"});
  // Counts are checked against the bytes present before any record is read.
  expectError([&] { loadMesh(write("tv.ply", h + verts.data.substr(0, 20))); },
              {"tv.ply: line 3: element vertex: 3 records of at least 12 bytes do not fit in the "
               "20 bytes left in the file"});
  expectError([&] { loadMesh(write("x.ply", good + "junk")); },
              {"x.ply", "4 unexpected bytes after the last element"});
  Bytes bad;
  bad.put<uint8_t>(3).put<int32_t>(0).put<int32_t>(-1).put<int32_t>(2);
  expectError([&] { loadMesh(write("i.ply", h + verts.data + bad.data)); },
              {"i.ply", "face 0", "vertex index -1 out of range"});
  Bytes nanVerts;
  for (float v : {0.f, 0.f, 0.f, 1.f, 0.f, 0.f, 0.f, std::numeric_limits<float>::infinity(), 0.f}) {
    nanVerts.put(v);
  }
  expectError([&] { loadMesh(write("n.ply", h + nanVerts.data + face.data)); },
              {"n.ply", "vertex 2", "non-finite coordinate"});
  expectError(
      [&] { loadMesh(write("z.ply", binaryHeader(3, 0, "float", "uchar int") + verts.data)); },
      {"z.ply", "no faces"});
  expectError([&] { loadMesh(write("lf.ply", binaryHeader(0, 0, "float", "float int"))); },
              {"line 8", "list count type must be an integer"});
}

// Issue 18: a 230-byte binary PLY announcing 10^12 records of an element without
// properties hung the kiosk (the parser looped that many times). Element counts are
// bounded by the stated limits and by the bytes present before any record is read.
TEST_F(MeshIo, PlyElementCountsAreBoundedBeforeReading) {
  const std::string header =
      "ply\nformat binary_little_endian 1.0\nelement foo 1000000000000\n"
      "element vertex 3\nproperty float x\nproperty float y\nproperty float z\n"
      "element face 1\nproperty list uchar int vertex_indices\nend_header\n";
  const auto start = std::chrono::steady_clock::now();
  expectError([&] { loadMesh(write("foo.ply", header)); },
              {"foo.ply: line 3: element foo: 1000000000000 records, more than the 3000000 a model "
               "may have"});
  EXPECT_LT(std::chrono::steady_clock::now() - start, std::chrono::seconds(1));
  // Within the limit but more than the bytes can hold: 2,000,000 vertices of 12 bytes.
  expectError([&] { loadMesh(write("lie.ply", binaryHeader(2000000, 1, "float", "uchar int"))); },
              {"lie.ply: line 3: element vertex: 2000000 records of at least 12 bytes do not fit "
               "in the 0 bytes left in the file"});
  expectError([&] { loadMesh(write("ascii.ply", std::string(kAsciiHeader) + "0")); },
              {"ascii.ply: line 4: element vertex: 4 records of at least 2 bytes do not fit"});
  // A face list longer than kMaxFaceCorners.
  Bytes verts, face;
  for (float v : {0.f, 0.f, 0.f, 1.f, 0.f, 0.f, 0.f, 1.f, 0.f}) verts.put(v);
  face.put<uint16_t>(2000);
  for (int i = 0; i < 2000; ++i) face.put<int32_t>(i % 3);
  expectError(
      [&] {
        loadMesh(
            write("big.ply", binaryHeader(3, 1, "float", "ushort int") + verts.data + face.data));
      },
      {"big.ply: face 0: face with more than the 1024 corners a polygon may have"});
  Bytes far;
  for (float v : {0.f, 0.f, 0.f, 1.f, 0.f, 0.f, 0.f, 3e9f, 0.f}) far.put(v);
  face = Bytes();
  face.put<uint8_t>(3).put<int32_t>(0).put<int32_t>(1).put<int32_t>(2);
  expectError(
      [&] {
        loadMesh(write("far.ply", binaryHeader(3, 1, "float", "uchar int") + far.data + face.data));
      },
      {"far.ply: vertex 2: coordinate 3e+09 is outside [-1e6, 1e6]"});
}

// Issue 18: an OBJ vertex of 1e308 passed `precompute` and was refused only by `render`;
// huge faces and counts drove precompute to 24 GB. Refused by the loader now.
TEST_F(MeshIo, ObjLimits) {
  expectError([&] { parseObj("v 0 0 0\nv 1 0 0\nv 1e308 1 0\nf 1 2 3\n", "big.obj"); },
              {"big.obj: line 3: coordinate 1e+308 is outside [-1e6, 1e6]"});
  std::string face = "v 0 0 0\nv 1 0 0\nv 0 1 0\nf";
  for (int i = 0; i < 5000; ++i) face.append({' ', static_cast<char>('1' + i % 3)});
  expectError([&] { parseObj(face, "face.obj"); },
              {"face.obj: line 4: face with more than the 1024 corners a polygon may have"});
  std::string many = "v 0 0 0\nv 1 0 0\nv 0 1 0\n";
  many.reserve(many.size() + 8 * (kMaxMeshTriangles + 1));
  for (size_t i = 0; i <= kMaxMeshTriangles; ++i) many += "f 1 2 3\n";
  expectError([&] { parseObj(many, "many.obj"); },
              {"many.obj: line 1000004: more than 1000000 triangles"});
  fs::create_directories(dir_ / "folder.obj");
  expectError([&] { loadMesh(dir_ / "folder.obj"); }, {"folder.obj: is a directory"});
  fs::create_symlink("/dev/zero", dir_ / "zero.ply");
  expectError([&] { loadMesh(dir_ / "zero.ply"); }, {"zero.ply: is not a regular file"});
}

TEST_F(MeshIo, SaveObjRoundTripsExactly) {
  TriangleMesh m;
  m.positions = {glm::dvec3(0.1, -2.0 / 3.0, 1e-9), glm::dvec3(1, 0, 0), glm::dvec3(0, 1, 0)};
  m.indices = {0, 1, 2};
  const fs::path p = dir_ / "out.obj";
  saveObj(m, p);
  const TriangleMesh back = loadMesh(p);
  EXPECT_EQ(back.positions, m.positions);
  EXPECT_EQ(back.indices, m.indices);
}

// A unit box with 8 shared corners and 6 outward quads, as modelling tools export it.
const char* const kBoxPositions =
    "v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nv 0 0 1\nv 1 0 1\nv 1 1 1\nv 0 1 1\n";
const char* const kBoxFaces = "f 1 4 3 2\nf 5 6 7 8\nf 1 2 6 5\nf 4 8 7 3\nf 1 5 8 4\nf 2 3 7 6\n";

// The face normal of each triangle, from its positions.
glm::dvec3 triangleNormal(const TriangleMesh& m, size_t t) {
  const glm::dvec3 &a = m.positions[m.indices[3 * t]], &b = m.positions[m.indices[3 * t + 1]],
                   &c = m.positions[m.indices[3 * t + 2]];
  return glm::normalize(glm::cross(b - a, c - a));
}

TEST_F(MeshIo, BoxWithSharedCornersGetsFlatFacesByCreaseAngle) {
  // Issue 15 item 6: 8 shared corners averaged into 8 diagonal normals shaded the faces in
  // bands. At the 60 degree default every 90 degree edge is a crease: 24 vertices, and every
  // corner of a face carries exactly that face's normal.
  const TriangleMesh m = loadMesh(write("box.obj", std::string(kBoxPositions) + kBoxFaces));
  EXPECT_EQ(m.positions.size(), 24u);
  ASSERT_EQ(m.triangleCount(), 12u);
  ASSERT_EQ(m.normals.size(), 24u);
  for (size_t t = 0; t < 12; ++t) {
    const glm::dvec3 n = triangleNormal(m, t);
    for (int k = 0; k < 3; ++k) EXPECT_EQ(m.normals[m.indices[3 * t + k]], n) << "triangle " << t;
    // Axis-aligned and outward.
    EXPECT_EQ(std::abs(n.x) + std::abs(n.y) + std::abs(n.z), 1.0);
    const glm::dvec3 centre = (m.positions[m.indices[3 * t]] + m.positions[m.indices[3 * t + 1]] +
                               m.positions[m.indices[3 * t + 2]]) /
                              3.0;
    EXPECT_GT(glm::dot(n, centre - glm::dvec3(0.5)), 0.0);
  }
  // A crease angle above 90 degrees joins the faces again: 8 smooth corners.
  MeshOptions wide;
  wide.creaseAngleDegrees = 100;
  const TriangleMesh smooth = loadMesh(dir_ / "box.obj", wide);
  EXPECT_EQ(smooth.positions.size(), 8u);
}

TEST_F(MeshIo, SmoothingGroupsDecideOverTheCreaseAngle) {
  // `s 1` on every face: one group, smooth across the 90 degree edges; each corner's normal
  // is the mean of its three faces' (equal areas): the diagonal.
  const TriangleMesh smooth =
      loadMesh(write("s1.obj", std::string(kBoxPositions) + "s 1\n" + kBoxFaces));
  ASSERT_EQ(smooth.positions.size(), 8u);
  for (size_t v = 0; v < 8; ++v) {
    const glm::dvec3 diagonal = glm::normalize(smooth.positions[v] - glm::dvec3(0.5));
    EXPECT_NEAR(glm::length(smooth.normals[v] - diagonal), 0.0, 1e-15) << v;
  }
  // `s off`: flat, whatever the crease angle.
  MeshOptions wide;
  wide.creaseAngleDegrees = 180;
  EXPECT_EQ(loadMesh(write("off.obj", std::string(kBoxPositions) + "s off\n" + kBoxFaces), wide)
                .positions.size(),
            24u);
  // Two groups: the top and bottom (group 2) are smooth among themselves only where they
  // share positions, which they do not: 4 side faces smooth (8 vertices) + top and bottom
  // flat against them (8 more).
  const TriangleMesh two = loadMesh(write(
      "two.obj", std::string(kBoxPositions) + "s 1\nf 1 2 6 5\nf 4 8 7 3\nf 1 5 8 4\nf 2 3 7 6\n"
                                              "s 2\nf 1 4 3 2\nf 5 6 7 8\n"));
  EXPECT_EQ(two.positions.size(), 16u);
}

TEST_F(MeshIo, ObjNormalsAreHonoured) {
  // One vn per face (what exporters write for a flat box), corners i//n: the file's normals,
  // normalized, 24 vertices. A deliberately tilted normal proves they are not recomputed.
  const std::string normals = "vn 0 0 -2\nvn 0 0 1\nvn 0 -1 0\nvn 0 1 0\nvn -1 0 0\nvn 1 0.5 0\n";
  std::string faces;
  const int quad[6][4] = {{1, 4, 3, 2}, {5, 6, 7, 8}, {1, 2, 6, 5},
                          {4, 8, 7, 3}, {1, 5, 8, 4}, {2, 3, 7, 6}};
  for (int f = 0; f < 6; ++f) {
    faces += "f";
    for (int k = 0; k < 4; ++k) {
      faces += " " + std::to_string(quad[f][k]) + "//" + std::to_string(f + 1);
    }
    faces += "\n";
  }
  const TriangleMesh m = loadMesh(write("vn.obj", std::string(kBoxPositions) + normals + faces));
  ASSERT_EQ(m.positions.size(), 24u);
  EXPECT_EQ(m.normals[m.indices[0]], glm::dvec3(0, 0, -1));  // (0, 0, -2) normalized
  EXPECT_EQ(m.normals[m.indices[3 * 10]], glm::normalize(glm::dvec3(1, 0.5, 0)));
  // A vn index out of range, a zero normal: named with file and line.
  expectError(
      [&] {
        loadMesh(write("badn.obj", std::string(kBoxPositions) + "vn 0 1 0\nf 1//1 2//2 3//1\n"));
      },
      {"badn.obj", "line 10", "normal index 2 out of range", "1 normals"});
  expectError([&] { loadMesh(write("zeron.obj", std::string(kBoxPositions) + "vn 0 0 0\n")); },
              {"zeron.obj", "line 9", "zero length"});
  expectError(
      [&] { loadMesh(write("badt.obj", std::string(kBoxPositions) + "vt 0 0\nf 1/2 2/1 3/1\n")); },
      {"badt.obj", "line 10", "texture coordinate index 2 out of range"});
}

// A w x h binary PPM from rows of RGB bytes.
std::string ppm(int w, int h, const std::vector<uint8_t>& rgb) {
  return "P6\n# written by the test\n" + std::to_string(w) + " " + std::to_string(h) + "\n255\n" +
         std::string(rgb.begin(), rgb.end());
}

TEST_F(MeshIo, TexturedMaterialGivesPerVertexColours) {
  // A 2 x 1 texture, red | blue, clamped; a quad whose left corners sit at u = 0 and right
  // corners at u = 1: the left vertices read the red texel's centre region (Kd x red), the
  // right ones blue. A second material without texture gives its Kd.
  write("wood.ppm", ppm(2, 1, {255, 0, 0, 0, 0, 255}));
  write("m.mtl",
        "# materials\nnewmtl painted wood\nKd 0.5 1 1\nmap_Kd -clamp on wood.ppm\n"
        "newmtl grey\nKd 0.25\n");
  const TriangleMesh m =
      loadMesh(write("quad.obj",
                     "mtllib m.mtl\nv 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nv 2 0 0\n"
                     "vt 0 0\nvt 1 0\nvt 1 1\nvt 0 1\n"
                     "usemtl painted wood\nf 1/1 2/2 3/3 4/4\nusemtl grey\nf 2 5 3\n"));
  ASSERT_EQ(m.reflectances.size(), m.positions.size());
  EXPECT_TRUE(m.warnings.empty());
  std::set<std::pair<double, double>> seen;  // (x, red) per vertex
  for (size_t v = 0; v < m.positions.size(); ++v) {
    const glm::dvec3& p = m.positions[v];
    const glm::dvec3& r = m.reflectances[v];
    if (r == glm::dvec3(0.25)) continue;  // the grey triangle's
    if (p.x == 0) {
      EXPECT_EQ(r, glm::dvec3(0.5, 0, 0)) << v;
    } else {
      EXPECT_EQ(r, glm::dvec3(0, 0, 1)) << v;
    }
    seen.insert({p.x, r.x});
  }
  EXPECT_EQ(seen.size(), 2u);  // the colours differ across the model
  // Positions 2 and 3 carry both materials: split into two vertices each.
  EXPECT_EQ(m.positions.size(), 7u);
}

TEST_F(MeshIo, MissingAndBadMaterialFilesAreNamed) {
  const std::string tri = "v 0 0 0\nv 1 0 0\nv 0 1 0\nvt 0.5 0.5\n";
  expectError([&] { loadMesh(write("nomtl.obj", "mtllib absent.mtl\n" + tri)); },
              {"nomtl.obj", "line 1", "absent.mtl"});
  write("notex.mtl", "newmtl a\nKd 1 1 1\nmap_Kd missing.png\n");
  expectError([&] { loadMesh(write("notex.obj", "mtllib notex.mtl\n" + tri)); },
              {"notex.mtl", "line 3", "missing.png"});
  write("kd.mtl", "newmtl a\nKd 2 0 0\n");
  expectError([&] { loadMesh(write("kd.obj", "mtllib kd.mtl\n" + tri)); },
              {"kd.mtl", "line 2", "Kd value '2'"});
  write("early.mtl", "Kd 1 1 1\n");
  expectError([&] { loadMesh(write("early.obj", "mtllib early.mtl\n" + tri)); },
              {"early.mtl", "line 1", "before newmtl"});
  write("opt.mtl", "newmtl a\nmap_Kd -zoom 2 t.ppm\n");
  expectError([&] { loadMesh(write("opt.obj", "mtllib opt.mtl\n" + tri)); },
              {"opt.mtl", "line 2", "unknown option '-zoom'"});
  write("junk.ppm", "this is not an image");
  write("junk.mtl", "newmtl a\nmap_Kd junk.ppm\n");
  expectError([&] { loadMesh(write("junk.obj", "mtllib junk.mtl\n" + tri)); },
              {"junk.mtl", "line 2", "junk.ppm", "not a PNG, JPEG or PPM"});
  write("short.ppm", "P6 4 4 255\nabc");
  write("short.mtl", "newmtl a\nmap_Kd short.ppm\n");
  expectError([&] { loadMesh(write("short.obj", "mtllib short.mtl\n" + tri)); },
              {"short.ppm", "truncated"});
  write("ok.mtl", "newmtl a\nKd 1 0 0\n");
  expectError([&] { loadMesh(write("use.obj", "mtllib ok.mtl\n" + tri + "usemtl b\nf 1 2 3\n")); },
              {"use.obj", "line 6", "no material named 'b'", "ok.mtl"});
  // Faces before the first usemtl: Blender's default grey, said in a warning.
  const TriangleMesh mixed =
      loadMesh(write("mixed.obj", "mtllib ok.mtl\n" + tri + "f 1 2 3\nusemtl a\nf 3 2 1\n"));
  EXPECT_EQ(mixed.reflectances[mixed.indices[0]], glm::dvec3(0.8));
  EXPECT_EQ(mixed.reflectances[mixed.indices[3]], glm::dvec3(1, 0, 0));
  ASSERT_EQ(mixed.warnings.size(), 1u);
  EXPECT_NE(mixed.warnings[0].find("mixed.obj"), std::string::npos);
  // usemtl without any mtllib: the materials are ignored, with a warning.
  const TriangleMesh bare = loadMesh(write("bare.obj", tri + "usemtl a\nf 1 2 3\n"));
  EXPECT_TRUE(bare.reflectances.empty());
  ASSERT_EQ(bare.warnings.size(), 1u);
  EXPECT_NE(bare.warnings[0].find("no mtllib"), std::string::npos);
}

// The bundled models (data/models/NOTICE.md) load with the counts of their sources.
TEST(BundledModels, LoadWithTheirTriangleCounts) {
  const fs::path models = dataDir() / "models";
  // Vertices: the files' positions (bunny 1,839, teapot 792, chair 128), split where faces
  // meet at more than the 60 degree crease angle (mesh_attributes.h); at 180 degrees
  // (smooth everywhere) none is.
  const TriangleMesh bunny = loadMesh(models / "bunny.ply");
  EXPECT_EQ(bunny.positions.size(), 1878u);
  EXPECT_EQ(bunny.triangleCount(), 3674u);
  MeshOptions smooth;
  smooth.creaseAngleDegrees = 180;
  EXPECT_EQ(loadMesh(models / "bunny.ply", smooth).positions.size(), 1839u);
  const TriangleMesh teapot = loadMesh(models / "teapot.ply");
  EXPECT_EQ(teapot.positions.size(), 872u);
  EXPECT_EQ(teapot.triangleCount(), 992u);
  EXPECT_EQ(loadMesh(models / "teapot.ply", smooth).positions.size(), 792u);
  const TriangleMesh chair = loadMesh(models / "chair.obj");
  EXPECT_EQ(chair.positions.size(), 288u);
  EXPECT_EQ(chair.triangleCount(), 216u);
  EXPECT_EQ(loadMesh(models / "chair.obj", smooth).positions.size(), 128u);
  for (const TriangleMesh* m : {&bunny, &teapot, &chair}) {
    ASSERT_EQ(m->normals.size(), m->positions.size());
    for (const glm::dvec3& n : m->normals) EXPECT_NEAR(glm::length(n), 1.0, 1e-12);
    EXPECT_TRUE(m->reflectances.empty());  // no materials: the scene file's colour
  }
}

}  // namespace
}  // namespace penumbra::scene
