#include "platform/service_notifier.h"

#include <sys/socket.h>
#include <sys/un.h>
#include <unistd.h>

#include <cerrno>
#include <cstddef>
#include <cstdlib>
#include <cstring>

namespace penumbra::platform {

ServiceNotifier::ServiceNotifier() {
  const char* socketPath = std::getenv("NOTIFY_SOCKET");
  if (socketPath == nullptr || socketPath[0] == '\0') return;
  address_ = socketPath;
  if (address_[0] == '@') address_[0] = '\0';  // an abstract socket
  if (address_.size() >= sizeof(sockaddr_un::sun_path)) {
    lastError_ = "NOTIFY_SOCKET is longer than a socket path";
    return;
  }
  const char* usec = std::getenv("WATCHDOG_USEC");
  const char* pid = std::getenv("WATCHDOG_PID");
  if (usec != nullptr && (pid == nullptr || std::strtoll(pid, nullptr, 10) == getpid())) {
    const long long us = std::strtoll(usec, nullptr, 10);
    if (us > 0) watchdogNs_ = us * 1000;
  }
  fd_ = socket(AF_UNIX, SOCK_DGRAM | SOCK_CLOEXEC, 0);
  if (fd_ < 0) lastError_ = std::strerror(errno);
}

ServiceNotifier::~ServiceNotifier() {
  if (fd_ >= 0) close(fd_);
}

void ServiceNotifier::send(std::string_view message) {
  if (fd_ < 0) return;
  sockaddr_un to{};
  to.sun_family = AF_UNIX;
  std::memcpy(to.sun_path, address_.data(), address_.size());
  const auto length = static_cast<socklen_t>(offsetof(sockaddr_un, sun_path) + address_.size());
  if (sendto(fd_, message.data(), message.size(), MSG_NOSIGNAL, reinterpret_cast<sockaddr*>(&to),
             length) < 0) {
    lastError_ = std::strerror(errno);
  }
}

void ServiceNotifier::ready(std::string_view status) {
  send("READY=1\nSTATUS=" + std::string(status));
}

void ServiceNotifier::status(std::string_view status) {
  send("STATUS=" + std::string(status));
}

void ServiceNotifier::alive(int64_t nowNs) {
  if (watchdogNs_ == 0 || (lastAliveNs_ != INT64_MIN && nowNs - lastAliveNs_ < watchdogNs_ / 2)) {
    return;
  }
  lastAliveNs_ = nowNs;
  send("WATCHDOG=1");
}

void ServiceNotifier::stopping() {
  send("STOPPING=1");
}

}  // namespace penumbra::platform
