#include "core/process_memory.h"

#include <malloc.h>

#include <cstdlib>
#include <fstream>
#include <string>

namespace penumbra::core {

ProcessMemory processMemory() {
  ProcessMemory m;
#if defined(__GLIBC__) && (__GLIBC__ > 2 || (__GLIBC__ == 2 && __GLIBC_MINOR__ >= 33))
  const struct mallinfo2 info = mallinfo2();
  m.heapKb = static_cast<long>((info.uordblks + info.hblkhd) / 1024);
#endif
  std::ifstream status("/proc/self/status");
  std::string line;
  while (std::getline(status, line)) {
    // "VmRSS:\t  109312 kB"
    if (line.rfind("VmRSS:", 0) == 0) m.rssKb = std::strtol(line.c_str() + 6, nullptr, 10);
    if (line.rfind("VmHWM:", 0) == 0) m.peakRssKb = std::strtol(line.c_str() + 6, nullptr, 10);
  }
  return m;
}

}  // namespace penumbra::core
