#include "scene/bundle_io.h"

#include <array>
#include <bit>
#include <fstream>

#include "core/regular_file.h"
#include "scene/sha256.h"

namespace penumbra::scene {
namespace {

static_assert(std::endian::native == std::endian::little, "bundles are little-endian");
constexpr char kMagic[16] = "PENUMBRA-BUNDLE";
constexpr size_t kHeaderSize = 16 + 4 + 4 + 32;
// Section names are short identifiers ("transfers.entry_vertex"); anything longer is damage.
constexpr uint32_t kMaxSectionName = 255;

template <class T>
void put(std::vector<uint8_t>& out, T value) {
  const auto* p = reinterpret_cast<const uint8_t*>(&value);
  out.insert(out.end(), p, p + sizeof(T));
}

}  // namespace

void BundleWriter::addBytes(const std::string& name, size_t elementSize, size_t count,
                            const void* data) {
  put(body_, static_cast<uint32_t>(name.size()));
  body_.insert(body_.end(), name.begin(), name.end());
  put(body_, static_cast<uint32_t>(elementSize));
  put(body_, static_cast<uint64_t>(count));
  const auto* p = static_cast<const uint8_t*>(data);
  body_.insert(body_.end(), p, p + elementSize * count);
  ++sections_;
}

void BundleWriter::write(const std::filesystem::path& path) const {
  std::vector<uint8_t> header(kMagic, kMagic + 16);
  put(header, version_);
  put(header, sections_);
  Sha256 hash;
  hash.update(body_);
  const auto digest = hash.finish();
  header.insert(header.end(), digest.begin(), digest.end());
  const std::filesystem::path temporary = path.string() + ".partial";
  {
    std::ofstream out(temporary, std::ios::binary | std::ios::trunc);
    out.write(reinterpret_cast<const char*>(header.data()), std::streamsize(header.size()));
    out.write(reinterpret_cast<const char*>(body_.data()), std::streamsize(body_.size()));
    if (!out) throw BundleError(path.string() + ": cannot write bundle");
  }
  std::error_code error;
  std::filesystem::rename(temporary, path, error);
  if (error) throw BundleError(path.string() + ": cannot write bundle: " + error.message());
}

BundleReader::BundleReader(const std::filesystem::path& path, uint32_t oldestVersion,
                           uint32_t newestVersion)
    : path_(path.string()),
      data_(core::readRegularFile(path, kMaxBundleBytes, "a scene bundle",
                                  core::throwAs<BundleError>)) {
  if (data_.size() < kHeaderSize || std::memcmp(data_.data(), kMagic, 16) != 0) {
    throw BundleError(path_ + ": not a Penumbra scene bundle (bad magic)");
  }
  uint32_t version, count;
  std::memcpy(&version, data_.data() + 16, 4);
  std::memcpy(&count, data_.data() + 20, 4);
  if (version < oldestVersion || version > newestVersion) {
    throw BundleError(
        path_ + ": bundle format version " + std::to_string(version) +
        ", this program reads version " + std::to_string(oldestVersion) +
        (newestVersion == oldestVersion ? std::string() : " to " + std::to_string(newestVersion)) +
        " (run `penumbra precompute` again)");
  }
  version_ = version;
  Sha256 hash;
  hash.update(std::span<const uint8_t>(data_).subspan(kHeaderSize));
  const auto digest = hash.finish();
  if (std::memcmp(digest.data(), data_.data() + 24, 32) != 0) {
    throw BundleError(path_ + ": checksum mismatch (the file is truncated or corrupted)");
  }
  size_t at = kHeaderSize;
  auto need = [&](size_t bytes, const std::string& what) {
    if (data_.size() - at < bytes) throw BundleError(path_ + ": truncated in " + what);
  };
  for (uint32_t s = 0; s < count; ++s) {
    need(4, "section header");
    uint32_t nameLength;
    std::memcpy(&nameLength, data_.data() + at, 4);
    at += 4;
    // Widened before the sum: a crafted length near 2^32 must not wrap past the check.
    if (nameLength > kMaxSectionName) {
      throw BundleError(path_ + ": section " + std::to_string(s) + ": name of " +
                        std::to_string(nameLength) + " bytes (at most " +
                        std::to_string(kMaxSectionName) + ")");
    }
    need(size_t{nameLength} + 12, "section header");
    std::string name(reinterpret_cast<const char*>(data_.data() + at), nameLength);
    at += nameLength;
    uint32_t elementSize;
    uint64_t elements;
    std::memcpy(&elementSize, data_.data() + at, 4);
    std::memcpy(&elements, data_.data() + at + 4, 8);
    at += 12;
    if (elementSize == 0 || elements > (data_.size() - at) / elementSize) {
      throw BundleError(path_ + ": section '" + name + "' runs past the end of the file");
    }
    sections_[name] = {elementSize, size_t(elements), at};
    at += elementSize * elements;
  }
  if (at != data_.size()) throw BundleError(path_ + ": trailing bytes after the last section");
}

const BundleReader::Section& BundleReader::section(const std::string& name,
                                                   size_t elementSize) const {
  const auto it = sections_.find(name);
  if (it == sections_.end()) fail(name, "missing");
  if (it->second.elementSize != elementSize) {
    fail(name, "element size " + std::to_string(it->second.elementSize) + ", expected " +
                   std::to_string(elementSize));
  }
  return it->second;
}

void BundleReader::fail(const std::string& name, const std::string& what) const {
  throw BundleError(path_ + ": section '" + name + "': " + what);
}

}  // namespace penumbra::scene
