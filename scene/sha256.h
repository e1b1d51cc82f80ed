// SHA-256 (FIPS 180-4), for golden-image hashes and bundle checksums.
#pragma once

#include <array>
#include <cstdint>
#include <span>
#include <string>

namespace penumbra::scene {

class Sha256 {
 public:
  Sha256();
  void update(std::span<const uint8_t> data);
  std::array<uint8_t, 32> finish();

 private:
  void compress(const uint8_t* block);
  std::array<uint32_t, 8> h_;
  std::array<uint8_t, 64> buffer_{};
  size_t buffered_ = 0;
  uint64_t totalBytes_ = 0;
};

// The digest of `data`.
std::array<uint8_t, 32> sha256(std::span<const uint8_t> data);
// A digest in lower-case hex.
std::string toHex(const std::array<uint8_t, 32>& digest);
// Lower-case hex digest of `data`: toHex(sha256(data)).
std::string sha256Hex(std::span<const uint8_t> data);

}  // namespace penumbra::scene
