// Base-colour textures of product models (OBJ `map_Kd`, glTF `baseColorTexture`), decoded to
// linear RGB and sampled once per vertex when a model is loaded: a product's colour is a
// per-vertex reflectance (scene/mesh_io.h), so a texture finer than the mesh loses its detail
// between vertices (a 4-vertex quad shows a 1024² photograph as 4 colours, interpolated). Per
// pixel texturing would need uvs and texels in the bundle and a texture fetch in the
// rasterizer; per vertex is what issue 15 item 6 asks ("per vertex or per pixel, not one
// average") and what the per-frame shading already interpolates.
//
// Decoders, the same in every build that has them: binary and ASCII PPM (P6, P3; own code),
// PNG through libpng (PENUMBRA_WITH_PNG, on in every preset, the static aarch64 one too),
// JPEG and the other formats through tinygltf's stb_image (PENUMBRA_WITH_GLTF: off in the
// board build). A file no decoder of the build reads is not an error of the file: the loader
// warns, naming it, and the material keeps its constant colour (decodeTexture's nullopt).
// A file that is corrupt for its format is an error naming it.
//
// Determinism: sRGB decoding uses a table built from IEEE +, -, *, / only (Newton steps for
// the 2.4 power, no libm), bilinear filtering a fixed order of operations, so the same
// texture gives the same vertex colours on every machine.
#pragma once

#include <cstdint>
#include <filesystem>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include <glm/glm.hpp>

#include "core/error.h"

namespace penumbra::scene {

class TextureError : public core::Error {
 public:
  using core::Error::Error;
};

// A texture side beyond this is refused from the file's header before decoding: a PNG of
// 65535 x 65535 pixels is a few kilobytes that decode to 16 GB.
constexpr uint32_t kMaxTextureSide = 8192;

// Linear RGB texels in [0, 1], row 0 at the top of the image.
struct Texture {
  uint32_t width = 0, height = 0;
  std::vector<glm::dvec3> texels;
};

// What a coordinate outside [0, 1] reads (glTF sampler wrapS/wrapT; OBJ `-clamp on` is
// kClampToEdge, the default tiles).
enum class TextureWrap { kRepeat, kClampToEdge, kMirroredRepeat };

// The sRGB transfer function decoded (IEC 61966-2-1: c / 12.92 below 0.04045, else
// ((c + 0.055) / 1.055)^2.4) for the 8-bit code `code`.
double srgbToLinear(uint8_t code);

// Texels from interleaved sRGB-encoded samples, `components` (1 to 4; 1 and 2 are grey) per
// pixel of `bits` (8, or 16 in native byte order) each; alpha is dropped.
Texture textureFromSamples(uint32_t width, uint32_t height, int components, int bits,
                           const unsigned char* data);

// Width and height from a PNG's IHDR or a JPEG's start-of-frame marker; nullopt for any
// other format or a header that ends early.
std::optional<std::pair<uint32_t, uint32_t>> pngOrJpegSize(const unsigned char* bytes, size_t n);

// Decodes an image file's bytes (the texel values are sRGB-encoded, as both OBJ and glTF base
// colours are). `name` is used in messages. nullopt when no decoder of this build reads the
// format (the caller warns); throws TextureError "name: problem" for a corrupt file, a size
// beyond kMaxTextureSide or an unknown format.
std::optional<Texture> decodeTexture(std::string_view bytes, const std::string& name);

// Bilinear sample at (u, v) (glTF convention: (0, 0) is the image's top-left corner, u to the
// right, v down; OBJ's v points up and is passed as 1 - v), texel centres at
// ((i + 0.5) / width, (j + 0.5) / height), blended in linear RGB in the order
// ((t00 (1-fx) + t10 fx) (1-fy) + (t01 (1-fx) + t11 fx) fy). u and v must be finite.
glm::dvec3 sampleBilinear(const Texture& texture, double u, double v, TextureWrap wrapU,
                          TextureWrap wrapV);

}  // namespace penumbra::scene
