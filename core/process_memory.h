// This process's memory, for the programs' reports (penumbra-sim --bench and its soak,
// penumbra-kiosk --frames, penumbra precompute): VmRSS and VmHWM (the peak) from
// /proc/self/status, and the bytes the C allocator holds for live blocks (glibc mallinfo2).
// RSS also moves with the allocator's free lists and arenas; the heap in use is what a leak
// would grow. -1 where the system does not say.
#pragma once

namespace penumbra::core {

struct ProcessMemory {
  long rssKb = -1, peakRssKb = -1, heapKb = -1;
};

ProcessMemory processMemory();

}  // namespace penumbra::core
