#include "kiosk/status.h"

#include <gtest/gtest.h>

#if defined(__GLIBC__)
#include <malloc.h>
#endif

#include <cstdint>
#include <stdexcept>
#include <string>
#include <vector>

namespace penumbra::kiosk {
namespace {

// Distinct messages.
std::string word(uint32_t i) {
  std::string w;
  do {
    w.push_back(static_cast<char>('a' + i % 26));
    i /= 26;
  } while (i != 0);
  return "event " + w;
}

TEST(KioskLog, KeepsAFixedNumberOfLinesOldestFirst) {
  KioskLog::Options o;
  o.capacity = 100;
  KioskLog log(nullptr, o);
  for (uint32_t i = 0; i < 250; ++i) log.write(i, LogLevel::kInfo, word(i));
  EXPECT_EQ(log.size(), 100u);
  EXPECT_EQ(log.dropped(), 150u);
  const std::vector<LogLine> lines = log.lines();
  ASSERT_EQ(lines.size(), 100u);
  for (uint32_t k = 0; k < 100; ++k) {
    EXPECT_EQ(lines[k].text, word(150 + k));
    EXPECT_EQ(lines[k].timeNs, 150 + k);
  }
  EXPECT_FALSE(log.contains(word(149)));
  EXPECT_TRUE(log.contains(word(150)));
  EXPECT_FALSE(log.contains(word(200), 199));  // written at 200
}

TEST(KioskLog, LevelFilterDropsLowerLevels) {
  KioskLog::Options o;
  o.minLevel = LogLevel::kWarning;
  KioskLog log(nullptr, o);
  log.write(1, LogLevel::kInfo, "camera: live again");
  log.write(2, LogLevel::kWarning, "camera: frozen");
  log.write(3, LogLevel::kError, "camera: disconnected");
  const std::vector<LogLine> lines = log.lines();
  ASSERT_EQ(lines.size(), 2u);
  EXPECT_EQ(lines[0].text, "camera: frozen");
  EXPECT_EQ(lines[1].level, LogLevel::kError);
}

TEST(KioskLog, ACameraSendingWrongFramesCostsOneLinePerWindow) {
  // 30 fps for 60 s, every frame refused (its sequence number changes every time, so the
  // kiosk names the repeat key).
  KioskLog log;  // default: 10 s window
  const int64_t period = 33'333'333;
  for (int64_t f = 0; f < 1800; ++f) {
    log.write(f * period, LogLevel::kWarning,
              "camera: frame " + std::to_string(f + 1) +
                  " refused: frame size 320x240, expected 640x480; keeping the last good frame",
              "camera: frame refused");
  }
  log.write(1800 * period, LogLevel::kInfo, "camera: live again after 60.0 s");
  const std::vector<LogLine> lines = log.lines();
  // The first line, one summary per 10 s window (6), the flush of the rest, the new line.
  EXPECT_GE(lines.size(), 7u);
  EXPECT_LE(lines.size(), 9u);
  EXPECT_EQ(lines.front().text.rfind("camera: frame 1 refused", 0), 0u);
  uint64_t counted = 1;
  for (size_t i = 1; i + 1 < lines.size(); ++i) {
    const std::string& t = lines[i].text;
    ASSERT_EQ(t.rfind("last message repeated ", 0), 0u) << t;
    counted += std::stoull(t.substr(22));
    EXPECT_NE(t.find("(latest: camera: frame "), std::string::npos) << t;
    EXPECT_EQ(lines[i].level, LogLevel::kWarning);
  }
  EXPECT_EQ(counted, 1800u) << "every refused frame is counted";
  EXPECT_NE(lines[lines.size() - 2].text.find("frame 1800 refused"), std::string::npos);
  EXPECT_EQ(lines.back().text, "camera: live again after 60.0 s");
}

TEST(KioskLog, ADifferentLineEndsARepeatRun) {
  KioskLog log;
  log.write(1, LogLevel::kWarning, "camera: frame 7 delivered again", "dup");
  log.write(2, LogLevel::kWarning, "camera: frame 8 delivered again", "dup");
  log.write(3, LogLevel::kWarning, "camera: frame 9 delivered again", "dup");
  log.write(4, LogLevel::kError, "camera: frame 9 delivered again", "dup");  // other level: new
  log.write(5, LogLevel::kInfo, "product: chair");
  // Without a key only identical texts repeat: lines differing in a number are all kept
  // (an exposure bracket's shots each say which exposure was applied).
  log.write(6, LogLevel::kInfo, "bracket: exposure 2000 us");
  log.write(7, LogLevel::kInfo, "bracket: exposure 4000 us");
  log.write(8, LogLevel::kInfo, "bracket: exposure 4000 us");
  log.write(9, LogLevel::kInfo, "bracket: exposure 4000 us");
  const std::vector<LogLine> lines = log.lines();
  ASSERT_EQ(lines.size(), 6u);
  EXPECT_EQ(lines[4].text, "bracket: exposure 2000 us");
  EXPECT_EQ(lines[5].text, "bracket: exposure 4000 us");
  EXPECT_TRUE(log.contains("exposure 4000")) << "a pending count hides nothing already kept";
  EXPECT_EQ(lines[1].text,
            "last message repeated 2 times (latest: camera: frame 9 delivered again)");
  EXPECT_EQ(lines[1].timeNs, 3);
  EXPECT_EQ(lines[2].level, LogLevel::kError);
  EXPECT_EQ(lines[3].text, "product: chair");
}

TEST(KioskLog, LongLinesAreCut) {
  KioskLog log;
  log.write(0, LogLevel::kError, std::string(100'000, 'x'));
  ASSERT_EQ(log.size(), 1u);
  EXPECT_EQ(log.lines()[0].text.size(), KioskLog::kMaxLineBytes);
  EXPECT_EQ(log.lines()[0].text.substr(KioskLog::kMaxLineBytes - 3), "...");
}

// The heap in use as glibc counts it, or -1 where that is not the allocator (another libc,
// or a sanitizer's allocator, which glibc's counters do not see).
long heapInUse() {
#if defined(__has_feature)
#if __has_feature(address_sanitizer) || __has_feature(thread_sanitizer)
  return -1;
#endif
#endif
#if defined(__GLIBC__) && !defined(__SANITIZE_ADDRESS__) && !defined(__SANITIZE_THREAD__)
  return static_cast<long>(mallinfo2().uordblks);
#else
  return -1;
#endif
}

// A kiosk runs for months: once built, the log must not take more memory line by line, even
// before its ring has filled once (the soak's heap check; a moved-in line used to bring its
// own buffer, so the heap grew with every line until the ring was full).
TEST(KioskLog, WritingLinesAllocatesNothing) {
  KioskLog::Options o;
  o.capacity = 64;
  KioskLog log(nullptr, o);
  std::vector<std::string> texts;
  for (uint32_t i = 0; i < 3 * o.capacity; ++i)
    texts.push_back(word(i) + std::string(40 + (i * 37) % 400, '.'));
  log.write(0, LogLevel::kInfo, std::string(KioskLog::kMaxLineBytes, 'w'));  // the repeat state's
  const long before = heapInUse();
  if (before < 0) GTEST_SKIP() << "glibc's heap counters do not see this build's allocator";
  for (uint32_t i = 0; i < texts.size(); ++i) {
    log.write(i + 1, LogLevel::kWarning, texts[i]);
    // Runs of repeats, counted and written out as one line.
    if (i % 16 == 0)
      for (uint32_t r = 0; r < 3; ++r) log.write(i + 1, LogLevel::kWarning, texts[r], "bad frame");
  }
  EXPECT_EQ(heapInUse() - before, 0);
  EXPECT_EQ(log.size(), o.capacity);
  EXPECT_EQ(log.lines().back().text, texts.back());
  EXPECT_GT(log.dropped(), 0u);
}

TEST(KioskLog, BadOptionsAreRefused) {
  KioskLog::Options o;
  o.capacity = 0;
  EXPECT_THROW(KioskLog(nullptr, o), std::invalid_argument);
  o = {};
  o.repeatWindowNs = -1;
  EXPECT_THROW(KioskLog(nullptr, o), std::invalid_argument);
}

}  // namespace
}  // namespace penumbra::kiosk
