// A versioned, checksummed container of named binary arrays: the on-disk form of a scene
// bundle (everything `penumbra precompute` computes once per showroom).
//
// Layout (little-endian): magic "PENUMBRA-BUNDLE\0" (16 bytes), format version (u32),
// section count (u32), SHA-256 of everything after the header (32 bytes); then per
// section: name length (u32), name bytes, element size (u32), element count (u64), data.
// Reading checks the magic, the version, the checksum, and every section's element size
// and count against what the caller asks for, so a truncated, corrupted or mismatched
// file is refused with a message naming the file and the section — never half-loaded.
#pragma once

#include <cstdint>
#include <cstring>
#include <filesystem>
#include <map>
#include <span>
#include <stdexcept>
#include <string>
#include <type_traits>
#include <vector>

#include "core/error.h"

namespace penumbra::scene {

// A bundle larger than this is refused before it is read (docs/input-limits.md): the
// bundled showroom is 2.4 MB, a fine showroom some tens of MB; the board must hold the
// bundle together with its frame buffers, and a path to a device or a huge file must not
// take the kiosk's memory.
inline constexpr uintmax_t kMaxBundleBytes = uintmax_t{512} << 20;

class BundleError : public core::Error {
 public:
  using core::Error::Error;
};

class BundleWriter {
 public:
  explicit BundleWriter(uint32_t version) : version_(version) {}
  template <class T>
  void add(const std::string& name, std::span<const T> values) {
    static_assert(std::is_trivially_copyable_v<T>);
    addBytes(name, sizeof(T), values.size(), values.data());
  }
  template <class T>
  void addValue(const std::string& name, const T& value) {
    add(name, std::span<const T>(&value, 1));
  }
  // Writes atomically (a temporary file renamed over `path`); throws BundleError.
  void write(const std::filesystem::path& path) const;

 private:
  void addBytes(const std::string& name, size_t elementSize, size_t count, const void* data);
  uint32_t version_;
  std::vector<uint8_t> body_;
  uint32_t sections_ = 0;
};

class BundleReader {
 public:
  // Reads and verifies `path`; throws BundleError naming the file.
  BundleReader(const std::filesystem::path& path, uint32_t expectedVersion)
      : BundleReader(path, expectedVersion, expectedVersion) {}
  // The same for any format version in [oldestVersion, newestVersion] (a reader that still
  // knows older layouts); version() says which one the file has.
  BundleReader(const std::filesystem::path& path, uint32_t oldestVersion, uint32_t newestVersion);

  uint32_t version() const { return version_; }

  bool has(const std::string& name) const { return sections_.count(name) != 0; }
  template <class T>
  std::vector<T> get(const std::string& name) const {
    static_assert(std::is_trivially_copyable_v<T>);
    const Section& s = section(name, sizeof(T));
    std::vector<T> out(s.count);
    if (s.count > 0) std::memcpy(out.data(), data_.data() + s.offset, s.count * sizeof(T));
    return out;
  }
  template <class T>
  T getValue(const std::string& name) const {
    const std::vector<T> v = get<T>(name);
    if (v.size() != 1) fail(name, "holds " + std::to_string(v.size()) + " values, expected 1");
    return v[0];
  }
  [[noreturn]] void fail(const std::string& name, const std::string& what) const;

 private:
  struct Section {
    size_t elementSize, count, offset;
  };
  const Section& section(const std::string& name, size_t elementSize) const;
  std::string path_;
  std::vector<uint8_t> data_;
  uint32_t version_ = 0;
  std::map<std::string, Section> sections_;
};

}  // namespace penumbra::scene
