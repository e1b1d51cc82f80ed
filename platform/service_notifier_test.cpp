// The sd_notify protocol against a real AF_UNIX datagram socket standing where systemd's
// would (this machine's systemd is not PID 1): the messages, their path and abstract
// addresses, the watchdog's rate, and silence without NOTIFY_SOCKET.
#include "platform/service_notifier.h"

#include <gtest/gtest.h>
#include <sys/socket.h>
#include <sys/un.h>
#include <unistd.h>

#include <cstddef>
#include <cstdlib>
#include <cstring>
#include <string>
#include <vector>

#include "tests/scratch_dir.h"

namespace penumbra::platform {
namespace {

// A bound datagram socket, as systemd's notify socket is.
class NotifySocket {
 public:
  explicit NotifySocket(const std::string& address) {
    fd_ = socket(AF_UNIX, SOCK_DGRAM | SOCK_CLOEXEC | SOCK_NONBLOCK, 0);
    sockaddr_un a{};
    a.sun_family = AF_UNIX;
    std::string bytes = address;
    if (bytes[0] == '@') bytes[0] = '\0';
    std::memcpy(a.sun_path, bytes.data(), bytes.size());
    const auto length = static_cast<socklen_t>(offsetof(sockaddr_un, sun_path) + bytes.size());
    EXPECT_EQ(bind(fd_, reinterpret_cast<sockaddr*>(&a), length), 0) << std::strerror(errno);
  }
  ~NotifySocket() { close(fd_); }
  std::vector<std::string> received() {
    std::vector<std::string> messages;
    char buffer[4096];
    for (ssize_t n; (n = recv(fd_, buffer, sizeof buffer, 0)) >= 0;) {
      messages.emplace_back(buffer, size_t(n));
    }
    return messages;
  }

 private:
  int fd_ = -1;
};

class Environment {
 public:
  Environment(const char* socket, const char* usec) {
    set("NOTIFY_SOCKET", socket);
    set("WATCHDOG_USEC", usec);
    unsetenv("WATCHDOG_PID");
  }
  ~Environment() {
    unsetenv("NOTIFY_SOCKET");
    unsetenv("WATCHDOG_USEC");
  }

 private:
  static void set(const char* key, const char* value) {
    if (value != nullptr) {
      setenv(key, value, 1);
    } else {
      unsetenv(key);
    }
  }
};

TEST(ServiceNotifier, SendsReadyStatusWatchdogAndStoppingToThePathSocket) {
  const std::string path = test::scratchPath("notify.sock").string();
  unlink(path.c_str());
  NotifySocket systemd(path);
  const Environment env(path.c_str(), "2000000");  // WatchdogSec=2
  ServiceNotifier n;
  ASSERT_TRUE(n.active());
  EXPECT_EQ(n.watchdogNs(), 2'000'000'000);
  n.ready("showing frames");
  // Every frame calls alive(); a ping goes at most once per half interval (1 s).
  for (int64_t t = 0; t <= 2'500'000'000; t += 33'000'000) n.alive(t);
  n.status("stopping: SIGTERM");
  n.stopping();
  EXPECT_EQ(n.lastError(), "");
  EXPECT_EQ(systemd.received(),
            (std::vector<std::string>{"READY=1\nSTATUS=showing frames", "WATCHDOG=1", "WATCHDOG=1",
                                      "WATCHDOG=1", "STATUS=stopping: SIGTERM", "STOPPING=1"}));
  unlink(path.c_str());
}

TEST(ServiceNotifier, AbstractSocketAndNoWatchdog) {
  const std::string name = "@penumbra-notify-test-" + std::to_string(getpid());
  NotifySocket systemd(name);
  const Environment env(name.c_str(), nullptr);
  ServiceNotifier n;
  ASSERT_TRUE(n.active());
  EXPECT_EQ(n.watchdogNs(), 0);
  n.ready("up");
  n.alive(0);  // no watchdog asked for: nothing sent
  EXPECT_EQ(systemd.received(), (std::vector<std::string>{"READY=1\nSTATUS=up"}));
}

TEST(ServiceNotifier, WithoutSystemdEverythingIsSilent) {
  const Environment env(nullptr, "2000000");
  ServiceNotifier n;
  EXPECT_FALSE(n.active());
  n.ready("up");
  n.alive(0);
  EXPECT_EQ(n.lastError(), "");
}

TEST(ServiceNotifier, AGoneSocketIsAnErrorNotACrash) {
  const std::string path = test::scratchPath("gone.sock").string();
  unlink(path.c_str());
  const Environment env(path.c_str(), nullptr);
  ServiceNotifier n;
  n.ready("up");
  EXPECT_NE(n.lastError(), "");
}

}  // namespace
}  // namespace penumbra::platform
