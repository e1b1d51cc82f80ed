#include "platform/v4l2_devices.h"

#include <algorithm>
#include <fstream>
#include <system_error>

namespace penumbra::platform {

std::vector<V4l2Device> listV4l2Devices(const std::filesystem::path& sysfs) {
  std::vector<std::pair<unsigned long, V4l2Device>> found;
  std::error_code ec;
  for (const auto& e : std::filesystem::directory_iterator(sysfs, ec)) {
    const std::string entry = e.path().filename().string();
    if (entry.rfind("video", 0) != 0 || entry.size() == 5 ||
        entry.find_first_not_of("0123456789", 5) != std::string::npos || entry.size() > 12) {
      continue;
    }
    V4l2Device d;
    d.node = std::filesystem::path("/dev") / entry;
    std::ifstream in(e.path() / "name");
    std::getline(in, d.name);
    if (d.name.empty()) d.name = "(no name)";
    found.emplace_back(std::stoul(entry.substr(5)), d);
  }
  std::sort(found.begin(), found.end(),
            [](const auto& a, const auto& b) { return a.first < b.first; });
  std::vector<V4l2Device> devices;
  devices.reserve(found.size());
  for (auto& [n, d] : found) devices.push_back(std::move(d));
  return devices;
}

}  // namespace penumbra::platform
