// The environment camera's fisheye lens file (envmap/fisheye_lens_file.h), as the kiosk reads
// it at start when kiosk.json's "environment" names one and `penumbra-kiosk --check` prints it.
// Values are mutated through the JSON structure (json_mutator.cpp). An accepted file must hold
// what the reader promises (a positive focal length, the centre inside the image), its reach
// must be a number in [0, π], and it must write and read back to the same values.
#include <cmath>
#include <cstdlib>
#include <numbers>
#include <string>

#include "envmap/fisheye_lens_file.h"
#include "tests/fuzz/fuzz_support.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  using namespace penumbra;
  const auto path = fuzz::writeScratch("lens.json", {data, size});
  fuzz::expectOnlyProjectErrors([&] {
    const envmap::FisheyeLensFile f = envmap::readFisheyeLensFile(path, core::throwAs<core::Error>);
    const envmap::FisheyeLens& l = f.lens;
    if (!(l.fx > 0 && l.fy > 0 && l.cx > 0 && l.cx < l.width && l.cy > 0 && l.cy < l.height))
      std::abort();
    const double reach = envmap::nearestEdgeReach(l);
    if (!(reach >= 0 && reach <= std::numbers::pi)) std::abort();
    const std::string text = envmap::fisheyeLensJson(f);
    const auto again = fuzz::writeScratch(
        "again.json", {reinterpret_cast<const uint8_t*>(text.data()), text.size()});
    const envmap::FisheyeLensFile g =
        envmap::readFisheyeLensFile(again, core::throwAs<core::Error>);
    if (g.lens.fx != l.fx || g.lens.fy != l.fy || g.lens.cx != l.cx || g.lens.cy != l.cy ||
        g.lens.k != l.k || g.rmsPx != f.rmsPx || g.views != f.views || g.board != f.board ||
        g.square != f.square)
      std::abort();
  });
  return 0;
}
