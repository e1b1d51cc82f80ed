// Frame traces (raster/frame_trace.h): the JSON description and its sidecar buffer, as
// `penumbra render` reads them. Input: the JSON text, a NUL byte, the buffer's bytes (the
// seeds' "buffer" field names "buffer.bin", where the tail is written). A trace that loads
// and is small enough to draw quickly is rendered with the scalar reference and the best
// SIMD target: the bit-exact contract (docs/design.md §3) says the two images are equal.
#include <cstdlib>
#include <cstring>

#include "raster/frame_trace.h"
#include "raster/renderer.h"
#include "simd/targets.h"
#include "tests/fuzz/fuzz_support.h"

namespace {

using namespace penumbra;

// Rendering costs width x height plus a shadow map per pass: only traces this small are
// drawn, so the target keeps thousands of executions per second on loading.
bool smallEnoughToRender(const raster::FrameTrace& t) {
  if (uint64_t{t.view.width} * t.view.height > 128 * 128 || t.frame.passes.size() > 8) {
    return false;
  }
  for (const raster::ShadowPass& p : t.frame.passes) {
    if (p.shadowMapSize > 256) return false;
  }
  return true;
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  const fuzz::TextAndTail input = fuzz::splitAtNul(data, size);
  fuzz::writeScratch("buffer.bin", input.tail);
  const auto path = fuzz::writeScratch("trace.json", input.text);
  fuzz::expectOnlyProjectErrors([&] {
    const raster::FrameTrace trace = raster::loadTrace(path);
    if (!smallEnoughToRender(trace)) return;
    raster::RenderOptions options;
    options.isa = simd::Isa::kScalar;
    const std::vector<uint8_t> reference = raster::renderTrace(trace, options);
    options.isa = simd::bestIsa();
    if (raster::renderTrace(trace, options) != reference) {
      std::fprintf(stderr, "trace_fuzz: %s differs from the scalar reference\n",
                   simd::isaName(options.isa));
      std::abort();
    }
  });
  return 0;
}
