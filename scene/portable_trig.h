// Sine and cosine with the same bits on every machine, for the per-frame path (design §3:
// no libm there — glibc picks FMA or non-FMA variants of sin/cos per CPU, so its last bits
// may differ between an x86 build and an aarch64 one).
#pragma once

namespace penumbra::scene {

// sin and cos of an angle in degrees, from a fixed sequence of IEEE +, -, * (no FMA):
// exact for multiples of 90 degrees, within 2 ulp elsewhere. NaN or infinite input gives
// NaN.
void sinCosDegrees(double degrees, double& s, double& c);

}  // namespace penumbra::scene
