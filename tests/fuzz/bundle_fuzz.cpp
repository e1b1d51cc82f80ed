// Scene bundles (shadow/scene_bundle.h over scene/bundle_io.h), as `penumbra render` and the
// kiosk load them. Structure-aware in the simplest way that works: the harness writes the
// magic and the format version and recomputes the SHA-256 over the body before loading, so
// a mutation reaches the section walk and the per-section checks instead of stopping at the
// checksum (issue 18: a crafted bundle overflowed the heap behind a valid checksum). A bundle
// that loads and is small is then composed into one frame, as the kiosk's first frame: what
// loads must also draw (issue 18: a bundle that loaded crashed the renderer).
#include <vector>

#include "scene/bundle_io.h"
#include "scene/sha256.h"
#include "shadow/frame_compositor.h"
#include "shadow/scene_bundle.h"
#include "tests/fuzz/fuzz_support.h"

namespace {

using namespace penumbra;

// scene/bundle_io.h: magic (16 bytes), version (u32), section count (u32), SHA-256 (32).
constexpr size_t kMagicSize = 16, kChecksumAt = 24, kBodyAt = 56;
// Composing costs the image plus the shadow maps: only bundles this small are drawn.
constexpr uint64_t kMaxComposedPixels = 160 * 120;

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  std::vector<uint8_t> file(data, data + size);
  if (file.size() < kBodyAt) file.resize(kBodyAt, 0);
  std::memcpy(file.data(), "PENUMBRA-BUNDLE", kMagicSize);  // with its NUL: 16 bytes
  const uint32_t version = shadow::kBundleVersion;
  std::memcpy(file.data() + kMagicSize, &version, sizeof version);
  scene::Sha256 hash;
  hash.update(std::span<const uint8_t>(file).subspan(kBodyAt));
  const auto digest = hash.finish();
  std::memcpy(file.data() + kChecksumAt, digest.data(), digest.size());
  const auto path = fuzz::writeScratch("scene.bundle", file);
  fuzz::expectOnlyProjectErrors([&] {
    const shadow::SceneBundle bundle = shadow::loadBundle(path);
    if (uint64_t{bundle.view.width} * bundle.view.height > kMaxComposedPixels) return;
    shadow::FrameCompositor compositor(bundle, shadow::CompositorOptions{});
    raster::FrameContent frame;
    shadow::CompositeStats stats;
    compositor.compose(bundle.startPose, /*passes=*/4, /*frame=*/0, frame, stats);
  });
  return 0;
}
