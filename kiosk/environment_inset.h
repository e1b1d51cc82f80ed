// What the environment camera sees, on the HUD (issue 16 item 7): the hemisphere map drawn as
// the disc an upward fisheye films, tone-mapped for the display by Reinhard et al. 2002's
// global operator with its world luminance, key and white smoothed over time
// (envmap/reinhard_tonemap.h: a cloud or a lamp does not make the inset flash), and the
// frame's lights as dots — what a technician checks when the product's light looks wrong.
//
// The disc is the map's own parametrisation (hemisphere_map.h: radius² = u, the azimuth the
// map's), seen from below as the camera looks up: image x is the camera's x, image y its y.
// Which map pixel each inset pixel shows is fixed at construction by exact comparisons
// against the columns' boundary directions (portable sine and cosine, no atan2), so the
// inset's bytes — part of the simulator's golden frames — are the same everywhere.
#pragma once

#include <cstdint>
#include <span>
#include <vector>

#include <glm/glm.hpp>

#include "core/image.h"
#include "envmap/directional_light.h"
#include "envmap/hemisphere_map.h"
#include "envmap/reinhard_tonemap.h"

namespace penumbra::kiosk {

class EnvironmentInset {
 public:
  // An inset of `size` × `size` pixels for maps of `cols` × `rows` (hemisphere_map.h).
  explicit EnvironmentInset(uint32_t size = 96, uint32_t cols = envmap::kEnvmapCols,
                            uint32_t rows = envmap::kEnvmapRows);

  // Draws `map` and the `lights` (world directions, mapped back to the camera's frame by the
  // transpose of `toWorld`) into the RGBA8 frame, its top-right corner at (x0 + size, y0).
  // Throws envmap::ToneMapError for a map of another size or with bad values.
  void draw(const envmap::HemisphereMap& map, std::span<const envmap::DirectionalLight> lights,
            const glm::dmat3& toWorld, std::span<uint8_t> rgba, uint32_t width, uint32_t height,
            int x0, int y0);

  uint32_t size() const { return size_; }

 private:
  uint32_t size_, cols_, rows_;
  std::vector<uint32_t> inset_;   // inset pixel of each disc pixel
  std::vector<uint32_t> source_;  // map pixel (row · cols + col) of each disc pixel
  core::ImageF disc_;             // the disc pixels' radiance, one row
  envmap::ReinhardToneMapper tone_;
};

}  // namespace penumbra::kiosk
