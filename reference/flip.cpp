#include "reference/flip.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <numbers>
#include <stdexcept>
#include <string>

namespace penumbra::reference {
namespace {

using Vec3 = std::array<double, 3>;

constexpr double kPi = std::numbers::pi;

// FLIP constants (Andersson et al. 2020, Table 1 / §4).
constexpr double kQc = 0.7;    // colour-difference exponent
constexpr double kPc = 0.4;    // knee of the colour compression
constexpr double kPt = 0.95;   // value at the knee
constexpr double kQf = 0.5;    // feature-difference exponent
constexpr double kGw = 0.082;  // feature-detector width in degrees

double srgbToLinear(double c) {
  return c <= 0.04045 ? c / 12.92 : std::pow((c + 0.055) / 1.055, 2.4);
}

// Linear sRGB (D65) <-> CIE XYZ; the reference white is XYZ(1, 1, 1 linear RGB).
constexpr Vec3 linearToXyz(const Vec3& c) {
  return {0.4124564 * c[0] + 0.3575761 * c[1] + 0.1804375 * c[2],
          0.2126729 * c[0] + 0.7151522 * c[1] + 0.0721750 * c[2],
          0.0193339 * c[0] + 0.1191920 * c[1] + 0.9503041 * c[2]};
}
Vec3 xyzToLinear(const Vec3& x) {
  return {3.2404542 * x[0] - 1.5371385 * x[1] - 0.4985314 * x[2],
          -0.9692660 * x[0] + 1.8760108 * x[1] + 0.0415560 * x[2],
          0.0556434 * x[0] - 0.2040259 * x[1] + 1.0572252 * x[2]};
}
constexpr Vec3 kWhite = linearToXyz({1.0, 1.0, 1.0});

// YyCxCz (§4.1): like CIELAB without the cube root, so filtering in it is linear in XYZ.
Vec3 xyzToYcxcz(const Vec3& x) {
  const double xr = x[0] / kWhite[0], yr = x[1] / kWhite[1], zr = x[2] / kWhite[2];
  return {116.0 * yr - 16.0, 500.0 * (xr - yr), 200.0 * (yr - zr)};
}
Vec3 ycxczToXyz(const Vec3& c) {
  const double yr = (c[0] + 16.0) / 116.0;
  const double xr = c[1] / 500.0 + yr;
  const double zr = yr - c[2] / 200.0;
  return {xr * kWhite[0], yr * kWhite[1], zr * kWhite[2]};
}

Vec3 xyzToLab(const Vec3& x) {
  auto f = [](double t) {
    constexpr double d = 6.0 / 29.0;
    return t > d * d * d ? std::cbrt(t) : t / (3.0 * d * d) + 4.0 / 29.0;
  };
  const double fx = f(x[0] / kWhite[0]), fy = f(x[1] / kWhite[1]), fz = f(x[2] / kWhite[2]);
  return {116.0 * fy - 16.0, 500.0 * (fx - fy), 200.0 * (fy - fz)};
}

// Hunt effect (§4.2): chroma is perceived weaker in the dark.
Vec3 hunt(const Vec3& lab) {
  return {lab[0], 0.01 * lab[0] * lab[1], 0.01 * lab[0] * lab[2]};
}

double hyab(const Vec3& p, const Vec3& q) {
  const double da = p[1] - q[1], db = p[2] - q[2];
  return std::abs(p[0] - q[0]) + std::sqrt(da * da + db * db);
}

// Clamp-to-edge separable convolution of a planar float image with a 1-D kernel of odd
// length (centre in the middle), first along x, then along y.
std::vector<double> convolveSeparable(const std::vector<double>& in, uint32_t w, uint32_t h,
                                      const std::vector<double>& kx,
                                      const std::vector<double>& ky) {
  const int rx = int(kx.size() / 2), ry = int(ky.size() / 2);
  std::vector<double> tmp(in.size()), out(in.size());
  for (uint32_t y = 0; y < h; ++y) {
    for (uint32_t x = 0; x < w; ++x) {
      double s = 0;
      for (size_t t = 0; t < kx.size(); ++t) {  // tap t is offset t - rx
        const int xx = std::clamp(int(x) + int(t) - rx, 0, int(w) - 1);
        s += kx[t] * in[size_t(y) * w + size_t(xx)];
      }
      tmp[size_t(y) * w + x] = s;
    }
  }
  for (uint32_t y = 0; y < h; ++y) {
    for (uint32_t x = 0; x < w; ++x) {
      double s = 0;
      for (size_t t = 0; t < ky.size(); ++t) {
        const int yy = std::clamp(int(y) + int(t) - ry, 0, int(h) - 1);
        s += ky[t] * tmp[size_t(yy) * w + x];
      }
      out[size_t(y) * w + x] = s;
    }
  }
  return out;
}

// exp(-π² x² / b) sampled at x = i / PPD degrees, |i| ≤ ceil(3σ·PPD), σ² = b / (2π²).
std::vector<double> csfGaussian(double b, double ppd) {
  const double sigmaDeg = std::sqrt(b / (2.0 * kPi * kPi));
  const int r = std::max(1, int(std::ceil(3.0 * sigmaDeg * ppd)));
  std::vector<double> k(2 * size_t(r) + 1);
  for (size_t t = 0; t < k.size(); ++t) {
    const double x = double(int(t) - r) / ppd;
    k[t] = std::exp(-kPi * kPi * x * x / b);
  }
  return k;
}

double sum(const std::vector<double>& v) {
  double s = 0;
  for (double x : v) s += x;
  return s;
}

// One channel's CSF (§4.1): a1·√(π/b1)·G1 + a2·√(π/b2)·G2 as a 2-D kernel normalized to sum
// 1. Each Gaussian is separable, so the sum is filtered as two separable passes.
struct Csf {
  double a1, b1, a2, b2;
};
std::vector<double> filterCsf(const std::vector<double>& in, uint32_t w, uint32_t h, const Csf& c,
                              double ppd) {
  const std::vector<double> g1 = csfGaussian(c.b1, ppd);
  const double w1 = c.a1 * std::sqrt(kPi / c.b1), s1 = sum(g1);
  std::vector<double> out = convolveSeparable(in, w, h, g1, g1);
  double norm = w1 * s1 * s1;
  if (c.a2 != 0.0) {
    const std::vector<double> g2 = csfGaussian(c.b2, ppd);
    const double w2 = c.a2 * std::sqrt(kPi / c.b2), s2 = sum(g2);
    const std::vector<double> o2 = convolveSeparable(in, w, h, g2, g2);
    for (size_t i = 0; i < out.size(); ++i) out[i] = w1 * out[i] + w2 * o2[i];
    norm += w2 * s2 * s2;
  } else {
    for (double& v : out) v *= w1;
  }
  for (double& v : out) v /= norm;
  return out;
}

struct Features {
  std::vector<double> edge, point;  // gradient magnitudes
};

// Edge and point detectors on the achromatic channel (§4.3): first and second derivatives of
// a Gaussian with σ = 0.5·w·PPD pixels. The derivative kernels have their positive weights
// summing to 1 and their negative weights to −1 (so a unit step gives magnitude ~1).
Features detectFeatures(const std::vector<double>& lum, uint32_t w, uint32_t h, double ppd) {
  const double sigma = 0.5 * kGw * ppd;
  const int r = std::max(1, int(std::ceil(3.0 * sigma)));
  std::vector<double> g(2 * size_t(r) + 1), d1(g.size()), d2(g.size());
  for (size_t t = 0; t < g.size(); ++t) {
    const double x = double(int(t) - r);
    const double gi = std::exp(-x * x / (2.0 * sigma * sigma));
    g[t] = gi;
    d1[t] = -x * gi;
    d2[t] = (x * x / (sigma * sigma) - 1.0) * gi;
  }
  const double sg = sum(g);
  for (double& v : g) v /= sg;
  auto normalizeSigned = [](std::vector<double>& k) {
    double pos = 0, neg = 0;
    for (double v : k) (v > 0 ? pos : neg) += v;
    for (double& v : k) v = v > 0 ? v / pos : (v < 0 ? v / -neg : 0.0);
  };
  normalizeSigned(d1);
  normalizeSigned(d2);
  const std::vector<double> ex = convolveSeparable(lum, w, h, d1, g);
  const std::vector<double> ey = convolveSeparable(lum, w, h, g, d1);
  const std::vector<double> px = convolveSeparable(lum, w, h, d2, g);
  const std::vector<double> py = convolveSeparable(lum, w, h, g, d2);
  Features f{std::vector<double>(lum.size()), std::vector<double>(lum.size())};
  for (size_t i = 0; i < lum.size(); ++i) {
    f.edge[i] = std::sqrt(ex[i] * ex[i] + ey[i] * ey[i]);
    f.point[i] = std::sqrt(px[i] * px[i] + py[i] * py[i]);
  }
  return f;
}

struct Prepared {
  std::vector<Vec3> huntLab;  // filtered colour, Hunt-adjusted CIELAB
  Features features;
};

Prepared prepare(std::span<const uint8_t> rgb, uint32_t w, uint32_t h, double ppd) {
  const size_t n = size_t(w) * h;
  std::array<std::vector<double>, 3> opp{std::vector<double>(n), std::vector<double>(n),
                                         std::vector<double>(n)};
  std::vector<double> lum(n);
  for (size_t i = 0; i < n; ++i) {
    const Vec3 lin{srgbToLinear(rgb[3 * i] / 255.0), srgbToLinear(rgb[3 * i + 1] / 255.0),
                   srgbToLinear(rgb[3 * i + 2] / 255.0)};
    const Vec3 c = xyzToYcxcz(linearToXyz(lin));
    for (int k = 0; k < 3; ++k) opp[size_t(k)][i] = c[size_t(k)];
    lum[i] = (c[0] + 16.0) / 116.0;  // relative luminance Y/Yn in [0, 1]
  }
  // CSF parameters of §4.1 (achromatic, red–green, blue–yellow).
  const Csf csf[3] = {
      {1.0, 0.0047, 0.0, 1e-5}, {1.0, 0.0053, 0.0, 1e-5}, {34.1, 0.04, 13.5, 0.025}};
  for (int k = 0; k < 3; ++k) opp[size_t(k)] = filterCsf(opp[size_t(k)], w, h, csf[k], ppd);
  Prepared p;
  p.huntLab.resize(n);
  for (size_t i = 0; i < n; ++i) {
    Vec3 lin = xyzToLinear(ycxczToXyz({opp[0][i], opp[1][i], opp[2][i]}));
    for (double& v : lin) v = std::clamp(v, 0.0, 1.0);
    p.huntLab[i] = hunt(xyzToLab(linearToXyz(lin)));
  }
  p.features = detectFeatures(lum, w, h, ppd);
  return p;
}

}  // namespace

std::vector<float> flipErrorMap(std::span<const uint8_t> reference, std::span<const uint8_t> test,
                                uint32_t width, uint32_t height, const FlipOptions& options) {
  const size_t n = size_t(width) * height;
  if (n == 0) throw std::invalid_argument("FLIP: empty image");
  if (reference.size() != 3 * n || test.size() != 3 * n) {
    throw std::invalid_argument("FLIP: images must both hold " + std::to_string(width) + "x" +
                                std::to_string(height) + " RGB8 pixels");
  }
  if (!(options.pixelsPerDegree > 0.0)) {
    throw std::invalid_argument("FLIP: pixels per degree must be positive");
  }
  const double ppd = options.pixelsPerDegree;
  const Prepared r = prepare(reference, width, height, ppd);
  const Prepared t = prepare(test, width, height, ppd);

  // The largest colour difference FLIP expects: pure green against pure blue (§4.2).
  const double cmax = std::pow(hyab(hunt(xyzToLab(linearToXyz({0.0, 1.0, 0.0}))),
                                    hunt(xyzToLab(linearToXyz({0.0, 0.0, 1.0})))),
                               kQc);
  std::vector<float> out(n);
  for (size_t i = 0; i < n; ++i) {
    const double d = std::pow(hyab(r.huntLab[i], t.huntLab[i]), kQc);
    // Compress: linear up to p_c·cmax (reaching p_t), then the remaining (1 − p_t) spread
    // over the rest of the range.
    const double ec = d < kPc * cmax ? (kPt / kPc) * d / cmax
                                     : kPt + (d - kPc * cmax) / (cmax - kPc * cmax) * (1.0 - kPt);
    const double df = std::max(std::abs(r.features.edge[i] - t.features.edge[i]),
                               std::abs(r.features.point[i] - t.features.point[i]));
    const double ef = std::pow(df / std::numbers::sqrt2, kQf);
    out[i] = float(std::clamp(std::pow(std::min(ec, 1.0), 1.0 - ef), 0.0, 1.0));
  }
  return out;
}

}  // namespace penumbra::reference
