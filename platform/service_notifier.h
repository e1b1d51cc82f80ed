// systemd's service notification protocol (sd_notify(3)), spoken directly so the kiosk needs
// no libsystemd: each message is one datagram of `KEY=value` lines to the AF_UNIX socket named
// in $NOTIFY_SOCKET (a leading '@' names an abstract socket). The kiosk's unit is
// Type=notify with WatchdogSec= (packaging/penumbra-kiosk.service): READY=1 once the first
// frame is on the screen, WATCHDOG=1 from the frame loop, so a loop that hangs — a bad file
// that freezes a frame — is killed and restarted by systemd instead of showing one frame
// forever. Without $NOTIFY_SOCKET (not started by systemd) every call does nothing.
#pragma once

#include <cstdint>
#include <string>
#include <string_view>

namespace penumbra::platform {

class ServiceNotifier {
 public:
  // Reads NOTIFY_SOCKET, WATCHDOG_USEC and WATCHDOG_PID from the environment (the watchdog
  // applies when WATCHDOG_PID is unset or this process's id).
  ServiceNotifier();
  ~ServiceNotifier();
  ServiceNotifier(const ServiceNotifier&) = delete;
  ServiceNotifier& operator=(const ServiceNotifier&) = delete;

  bool active() const { return fd_ >= 0; }
  int64_t watchdogNs() const { return watchdogNs_; }  // 0: no watchdog asked for

  void ready(std::string_view status);
  void status(std::string_view status);
  // WATCHDOG=1, sent at most every half watchdog interval (systemd's advice) however often
  // it is called: the frame loop calls it every frame.
  void alive(int64_t nowNs);
  void stopping();

  // The last send's error (errno text), empty when every send went through.
  const std::string& lastError() const { return lastError_; }

 private:
  void send(std::string_view message);

  int fd_ = -1;
  std::string address_;  // sockaddr_un path bytes (abstract: leading NUL)
  int64_t watchdogNs_ = 0;
  int64_t lastAliveNs_ = INT64_MIN;
  std::string lastError_;
};

}  // namespace penumbra::platform
