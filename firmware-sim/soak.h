// A soak schedule (issue 18 §4): a kiosk session long enough to show what only time shows —
// memory that grows, frame time that drifts, state that no longer replays. On top of a base
// session (its bundle, kiosk, board and camera rates), a visitor switches products and
// moves, turns and re-quality-toggles them every few seconds; the camera drops, delays,
// repeats, mis-sizes, mis-formats frames and disconnects; the board's load steps between
// 0.5× and 100× and single frames overrun. Every event is a pure function of its index
// (core::splitmix64 of a fixed key), so `penumbra-sim --soak N` replays bit-exactly and a
// window of it can be compared with a re-run (docs/kiosk.md, "Soak").
#pragma once

#include <cstdint>

#include "firmware-sim/session.h"

namespace penumbra::firmware_sim {

// `base` with `frames` frames and the soak's scripted presses, camera faults, load steps and
// overruns (replacing the base's). The base's start-up faults and product files are kept.
// Event density, per minute of virtual time at 30 fps: 20 button presses, 2 camera faults
// (one disconnect every ~5 min), 2 load steps, 3 overruns.
Session soakSession(Session base, uint32_t frames);

}  // namespace penumbra::firmware_sim
