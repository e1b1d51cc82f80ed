#include "scene/vanishing_points.h"

#include <cmath>
#include <limits>
#include <optional>

#include "core/json_reader.h"

namespace penumbra::scene {
namespace {

constexpr const char* kAxisNames[3] = {"x", "y", "z"};

glm::dvec2 point(const core::JsonValue& v) {
  const std::vector<double> p = v.numbers(2);  // [u, v] in pixels
  return {p[0], p[1]};
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
  const core::JsonDocument doc(path, core::throwAs<CalibrationError>);
  const core::JsonValue root =
      doc.root().object({"image", "vanishing_lines", "origin", "axis_points", "comment"});
  VanishingMarks m;
  m.source = path.filename().string();
  const core::JsonValue image = root["image"].object({"width", "height"});
  const double w = image["width"].number(2, 1e5);
  const double h = image["height"].number(2, 1e5);
  if (w != std::floor(w) || h != std::floor(h)) {
    image.fail("width and height must be whole numbers of pixels in [2, 100000]");
  }
  m.width = int(w);
  m.height = int(h);

  const core::JsonValue lines = root["vanishing_lines"].object({"x", "y", "z"});
  if (lines.json().size() != 2) lines.fail("mark exactly two of the directions x, y, z");
  for (int a = 0; a < 3; ++a) {
    const std::optional<core::JsonValue> pair = lines.find(kAxisNames[a]);
    if (!pair) continue;
    if (!pair->json().is_array() || pair->json().size() != 2) {
      pair->fail("must hold two lines [[u0, v0], [u1, v1]]");
    }
    std::array<ImageLine, 2> ls;
    for (int i = 0; i < 2; ++i) {
      const core::JsonValue line = pair->array()[static_cast<size_t>(i)];
      if (!line.json().is_array() || line.json().size() != 2) {
        line.fail("must be a line [[u0, v0], [u1, v1]]");
      }
      ls[i].a = point(line.array()[0]);
      ls[i].b = point(line.array()[1]);
    }
    m.lines[a] = ls;
  }

  m.origin = point(root["origin"]);
  const core::JsonValue axes = root["axis_points"].object({"x", "y", "z"});
  for (int a = 0; a < 3; ++a) {
    const std::optional<core::JsonValue> p = axes.find(kAxisNames[a]);
    if (!p) {
      if (m.lines[a]) {
        doc.fail(std::string("axis_points.") + kAxisNames[a],
                 "missing (needed for every line-marked axis)");
      }
      continue;
    }
    p->object({"image", "distance"});
    AxisPoint ap;
    ap.image = point((*p)["image"]);
    ap.distance = (*p)["distance"].number();
    if (!(ap.distance > 0)) (*p)["distance"].fail("must be positive");
    m.axisPoints[a] = ap;
  }
  return m;
}

VanishingCalibration calibrateFromVanishingPoints(const VanishingMarks& m) {
  const std::string& src = m.source;
  if (m.width < 2 || m.height < 2)
    throw CalibrationError(src, "image", "size must be at least 2x2 pixels");
  VanishingCalibration out;
  int n = 0;
  for (int a = 0; a < 3; ++a) {
    if (m.lines[a]) {
      if (n == 2)
        throw CalibrationError(src, "vanishing_lines",
                               "mark exactly two of the directions x, y, z");
      out.markedAxes[n++] = a;
    }
  }
  if (n != 2)
    throw CalibrationError(src, "vanishing_lines", "mark exactly two of the directions x, y, z");
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
    throw CalibrationError(src, "vanishing_lines",
                           "f^2 = -(v.v') = " + std::to_string(f2) +
                               " <= 0: the vanishing points of " + kAxisNames[out.markedAxes[0]] +
                               " and " + kAxisNames[out.markedAxes[1]] +
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
    if (!m.axisPoints[a])
      throw CalibrationError(src, field, "missing (needed for every line-marked axis)");
    const glm::dvec2 toAxis = m.axisPoints[a]->image - m.origin;
    const glm::dvec2 toVp = out.vanishingPoints[i] - m.origin;
    const double la = glm::length(toAxis), lv = glm::length(toVp);
    if (!(la > 1e-6)) throw CalibrationError(src, field + ".image", "coincides with the origin");
    const glm::dvec3 q = glm::normalize(glm::dvec3(out.vanishingPoints[i] - c, f));
    if (!(lv > 1e-6)) {
      throw CalibrationError(src, "origin",
                             std::string("lies on the vanishing point of ") + kAxisNames[a]);
    }
    const double cosAngle = glm::dot(toAxis, toVp) / (la * lv);
    // Away from v the image of the axis runs from v through the origin; either way the
    // axis point must lie on the line through the origin and v (|cos| near 1).
    if (std::abs(cosAngle) < 0.9) {
      throw CalibrationError(
          src, field + ".image",
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
    throw CalibrationError(src, "axis_points",
                           "the axis points lie on the origin's line of sight: no scale");
  }
  const double lambda = num / den;
  if (!(lambda > 0) || !std::isfinite(lambda)) {
    throw CalibrationError(
        src, "axis_points",
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
