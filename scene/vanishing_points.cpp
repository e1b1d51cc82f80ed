#include "scene/vanishing_points.h"

#include <cmath>
#include <fstream>
#include <limits>
#include <nlohmann/json.hpp>

namespace penumbra::scene {
namespace {

constexpr const char* kAxisNames[3] = {"x", "y", "z"};

using nlohmann::json;

[[noreturn]] void fail(const std::string& source, const std::string& field,
                       const std::string& problem) {
  throw CalibrationError(source + ": " + field + ": " + problem);
}

double number(const json& j, const std::string& source, const std::string& field) {
  if (!j.is_number()) fail(source, field, "must be a number");
  const double v = j.get<double>();
  if (!std::isfinite(v)) fail(source, field, "is not a finite number");
  return v;
}

glm::dvec2 point(const json& j, const std::string& source, const std::string& field) {
  if (!j.is_array() || j.size() != 2) fail(source, field, "must be [u, v] (pixels)");
  return {number(j[0], source, field + "[0]"), number(j[1], source, field + "[1]")};
}

void onlyKeys(const json& j, std::initializer_list<const char*> keys, const std::string& source,
              const std::string& where) {
  for (auto it = j.begin(); it != j.end(); ++it) {
    bool known = false;
    for (const char* k : keys) known = known || it.key() == k;
    if (!known) fail(source, where + it.key(), "unknown field");
  }
}

const json& member(const json& j, const char* key, const std::string& source,
                   const std::string& where) {
  if (!j.is_object() || !j.contains(key)) fail(source, where + key, "missing");
  return j.at(key);
}

// Homogeneous line through two points, scaled so its normal (a, b) has unit length.
glm::dvec3 lineThrough(const ImageLine& l, const std::string& what) {
  const glm::dvec2 d = l.b - l.a;
  const double len = std::sqrt(d.x * d.x + d.y * d.y);
  if (!(len > 1e-9)) throw CalibrationError(what + ": has zero length");
  const glm::dvec3 h = glm::cross(glm::dvec3(l.a, 1.0), glm::dvec3(l.b, 1.0));
  return h / len;
}

glm::dvec3 orthonormalAxis(const glm::dvec3& v) {
  return glm::normalize(v);
}

}  // namespace

glm::dvec2 vanishingPoint(const ImageLine& l0, const ImageLine& l1, const std::string& what) {
  const glm::dvec3 h0 = lineThrough(l0, what + "[0]"), h1 = lineThrough(l1, what + "[1]");
  // With unit normals, the homogeneous w of the intersection is sin(angle between lines).
  const glm::dvec3 p = glm::cross(h0, h1);
  if (!(std::abs(p.z) > 1e-7)) {
    throw CalibrationError(what +
                           ": the two lines are parallel in the image (vanishing point at "
                           "infinity); mark lines that converge");
  }
  const glm::dvec2 v(p.x / p.z, p.y / p.z);
  if (!std::isfinite(v.x) || !std::isfinite(v.y)) {
    throw CalibrationError(what + ": vanishing point is not finite");
  }
  return v;
}

VanishingMarks loadVanishingMarks(const std::filesystem::path& path) {
  const std::string source = path.filename().string();
  std::ifstream in(path);
  if (!in) throw CalibrationError(source + ": cannot open " + path.string());
  json doc;
  try {
    doc = json::parse(in);
  } catch (const json::exception& e) {
    throw CalibrationError(source + ": not valid JSON: " + e.what());
  }
  if (!doc.is_object()) fail(source, "(document)", "must be a JSON object");
  onlyKeys(doc, {"image", "vanishing_lines", "origin", "axis_points", "comment"}, source, "");
  VanishingMarks m;
  m.source = source;
  const json& image = member(doc, "image", source, "");
  onlyKeys(image, {"width", "height"}, source, "image.");
  const double w = number(member(image, "width", source, "image."), source, "image.width");
  const double h = number(member(image, "height", source, "image."), source, "image.height");
  if (!(w >= 2 && h >= 2 && w <= 1e5 && h <= 1e5) || w != std::floor(w) || h != std::floor(h)) {
    fail(source, "image", "width and height must be whole numbers of pixels in [2, 100000]");
  }
  m.width = int(w);
  m.height = int(h);

  const json& lines = member(doc, "vanishing_lines", source, "");
  if (!lines.is_object()) fail(source, "vanishing_lines", "must be an object");
  onlyKeys(lines, {"x", "y", "z"}, source, "vanishing_lines.");
  if (lines.size() != 2) {
    fail(source, "vanishing_lines", "mark exactly two of the directions x, y, z");
  }
  for (int a = 0; a < 3; ++a) {
    if (!lines.contains(kAxisNames[a])) continue;
    const std::string field = std::string("vanishing_lines.") + kAxisNames[a];
    const json& pair = lines.at(kAxisNames[a]);
    if (!pair.is_array() || pair.size() != 2) {
      fail(source, field, "must hold two lines [[u0, v0], [u1, v1]]");
    }
    std::array<ImageLine, 2> ls;
    for (int i = 0; i < 2; ++i) {
      const std::string lf = field + "[" + std::to_string(i) + "]";
      if (!pair[i].is_array() || pair[i].size() != 2) {
        fail(source, lf, "must be a line [[u0, v0], [u1, v1]]");
      }
      ls[i].a = point(pair[i][0], source, lf + "[0]");
      ls[i].b = point(pair[i][1], source, lf + "[1]");
    }
    m.lines[a] = ls;
  }

  m.origin = point(member(doc, "origin", source, ""), source, "origin");
  const json& axes = member(doc, "axis_points", source, "");
  if (!axes.is_object()) fail(source, "axis_points", "must be an object");
  onlyKeys(axes, {"x", "y", "z"}, source, "axis_points.");
  for (int a = 0; a < 3; ++a) {
    const std::string field = std::string("axis_points.") + kAxisNames[a];
    if (!axes.contains(kAxisNames[a])) {
      if (m.lines[a]) fail(source, field, "missing (needed for every line-marked axis)");
      continue;
    }
    const json& p = axes.at(kAxisNames[a]);
    onlyKeys(p, {"image", "distance"}, source, field + ".");
    AxisPoint ap;
    ap.image = point(member(p, "image", source, field + "."), source, field + ".image");
    ap.distance = number(member(p, "distance", source, field + "."), source, field + ".distance");
    if (!(ap.distance > 0)) fail(source, field + ".distance", "must be positive");
    m.axisPoints[a] = ap;
  }
  return m;
}

VanishingCalibration calibrateFromVanishingPoints(const VanishingMarks& m) {
  const std::string& src = m.source;
  if (m.width < 2 || m.height < 2) fail(src, "image", "size must be at least 2x2 pixels");
  VanishingCalibration out;
  int n = 0;
  for (int a = 0; a < 3; ++a) {
    if (m.lines[a]) {
      if (n == 2) fail(src, "vanishing_lines", "mark exactly two of the directions x, y, z");
      out.markedAxes[n++] = a;
    }
  }
  if (n != 2) fail(src, "vanishing_lines", "mark exactly two of the directions x, y, z");
  out.derivedAxis = 3 - out.markedAxes[0] - out.markedAxes[1];

  // Principal point at the image centre (pixel centres at integers: (w - 1) / 2).
  const glm::dvec2 c(0.5 * (m.width - 1), 0.5 * (m.height - 1));
  for (int i = 0; i < 2; ++i) {
    const int a = out.markedAxes[i];
    out.vanishingPoints[i] = vanishingPoint((*m.lines[a])[0], (*m.lines[a])[1],
                                            src + ": vanishing_lines." + kAxisNames[a]);
  }
  const glm::dvec2 d0 = out.vanishingPoints[0] - c, d1 = out.vanishingPoints[1] - c;
  const double f2 = -(d0.x * d1.x + d0.y * d1.y);  // tutorial §3, eq. 1
  if (!(f2 > 0) || !std::isfinite(f2)) {
    fail(src, "vanishing_lines",
         "f^2 = -(v.v') = " + std::to_string(f2) + " <= 0: the vanishing points of " +
             kAxisNames[out.markedAxes[0]] + " and " + kAxisNames[out.markedAxes[1]] +
             " cannot belong to orthogonal directions (check the marked lines)");
  }
  const double f = std::sqrt(f2);

  // Each marked axis points towards its vanishing point (ray with z > 0) or away from it;
  // the marked axis point decides: going from the origin along +axis the image moves
  // towards v exactly when the axis direction has positive depth.
  std::array<glm::dvec3, 3> r;
  for (int i = 0; i < 2; ++i) {
    const int a = out.markedAxes[i];
    const std::string field = std::string("axis_points.") + kAxisNames[a];
    if (!m.axisPoints[a]) fail(src, field, "missing (needed for every line-marked axis)");
    const glm::dvec2 toAxis = m.axisPoints[a]->image - m.origin;
    const glm::dvec2 toVp = out.vanishingPoints[i] - m.origin;
    const double la = glm::length(toAxis), lv = glm::length(toVp);
    if (!(la > 1e-6)) fail(src, field + ".image", "coincides with the origin");
    const glm::dvec3 q = glm::normalize(glm::dvec3(out.vanishingPoints[i] - c, f));
    if (!(lv > 1e-6)) {
      fail(src, "origin", std::string("lies on the vanishing point of ") + kAxisNames[a]);
    }
    const double cosAngle = glm::dot(toAxis, toVp) / (la * lv);
    // Away from v the image of the axis runs from v through the origin; either way the
    // axis point must lie on the line through the origin and v (|cos| near 1).
    if (std::abs(cosAngle) < 0.9) {
      fail(src, field + ".image",
           std::string("is not on the line from the origin towards the vanishing point of ") +
               kAxisNames[a] + " (the marks disagree by " +
               std::to_string(std::acos(std::abs(cosAngle)) * 180.0 / 3.14159265358979) +
               " degrees)");
    }
    r[a] = cosAngle > 0 ? q : -q;
  }
  // Right-handed world: z = x * y, x = y * z, y = z * x.
  const int d = out.derivedAxis;
  r[d] = glm::cross(r[(d + 1) % 3], r[(d + 2) % 3]);
  // Gram–Schmidt against rounding: r0, r1 are orthogonal by construction of f.
  r[0] = orthonormalAxis(r[0]);
  r[1] = orthonormalAxis(r[1] - glm::dot(r[1], r[0]) * r[0]);
  r[2] = glm::cross(r[0], r[1]);
  for (int a = 0; a < 3; ++a) out.pose.rotation[a] = r[a];  // column a = world axis a

  // Translation t = lambda * (o - c, f): the origin is on its pixel's ray. Each axis point
  // P = t + L r_a must project to its mark u: f P.x - (u - c).x P.z = 0 (and for y), linear
  // in lambda; least squares over all axis points.
  const glm::dvec3 qo(m.origin - c, f);
  double num = 0, den = 0;
  for (int a = 0; a < 3; ++a) {
    if (!m.axisPoints[a]) continue;
    const glm::dvec2 u = m.axisPoints[a]->image - c;
    const double len = m.axisPoints[a]->distance;
    for (int k = 0; k < 2; ++k) {
      const double coeff = f * qo[k] - u[k] * qo.z;
      const double rhs = len * (f * r[a][k] - u[k] * r[a].z);
      num -= coeff * rhs;
      den += coeff * coeff;
    }
  }
  if (!(den > 1e-12 * f2 * f2)) {
    fail(src, "axis_points", "the axis points lie on the origin's line of sight: no scale");
  }
  const double lambda = num / den;
  if (!(lambda > 0) || !std::isfinite(lambda)) {
    fail(src, "axis_points",
         "the marked distances put the origin behind the camera (check the axis points)");
  }
  out.pose.translation = lambda * qo;

  out.intrinsics.width = m.width;
  out.intrinsics.height = m.height;
  out.intrinsics.fx = out.intrinsics.fy = f;
  out.intrinsics.cx = c.x;
  out.intrinsics.cy = c.y;

  auto residual = [&](const glm::dvec3& world, const glm::dvec2& mark) {
    const glm::dvec3 pc = out.pose.toCamera(world);
    if (!(pc.z > 0)) return std::numeric_limits<double>::infinity();
    return glm::length(out.intrinsics.project(pc) - mark);
  };
  out.residualsPx.push_back(residual(glm::dvec3(0.0), m.origin));
  for (int a = 0; a < 3; ++a) {
    if (!m.axisPoints[a]) continue;
    glm::dvec3 w(0.0);
    w[a] = m.axisPoints[a]->distance;
    out.residualsPx.push_back(residual(w, m.axisPoints[a]->image));
  }
  double sum = 0;
  for (double e : out.residualsPx) sum += e * e;
  out.rmsPx = std::sqrt(sum / double(out.residualsPx.size()));
  return out;
}

}  // namespace penumbra::scene
