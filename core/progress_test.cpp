#include "core/progress.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cstdio>
#include <string>

namespace penumbra::core {
namespace {

// Everything `write` printed through a Progress on a temporary file.
template <typename Write>
std::string printed(bool terminal, Write write) {
  std::FILE* f = std::tmpfile();
  {
    Progress p("job", terminal, f);
    write(p);
  }
  std::rewind(f);
  std::string text;
  for (int c; (c = std::fgetc(f)) != EOF;) text += static_cast<char>(c);
  std::fclose(f);
  return text;
}

TEST(Progress, OffATerminalStagesArePlainLines) {
  const std::string text = printed(false, [](Progress& p) {
    p.stage("load", 0, 3);
    p.stage("merge", 1, 3);
    p.stage("save", 2, 3);
    p.finish();
  });
  EXPECT_EQ(text, "job  1/3 load\njob  2/3 merge\njob  3/3 save\n");
}

TEST(Progress, OffATerminalFractionsPrintEveryTenPercent) {
  const std::string text = printed(false, [](Progress& p) {
    for (uint32_t i = 0; i <= 1000; ++i) p.fraction(i, 1000);
  });
  EXPECT_EQ(text.find('\r'), std::string::npos);
  EXPECT_EQ(text,
            "job 0%\njob 10%\njob 20%\njob 30%\njob 40%\njob 50%\njob 60%\njob 70%\njob 80%\n"
            "job 90%\njob 100%\n");
}

TEST(Progress, OnATerminalOneLineIsRedrawnAndEnded) {
  const std::string text = printed(true, [](Progress& p) {
    p.stage("load", 0, 2);
    p.stage("save", 1, 2);
    p.finish();
    p.finish();  // a second finish adds nothing
  });
  EXPECT_EQ(text.front(), '\r');
  EXPECT_EQ(std::count(text.begin(), text.end(), '\r'), 2);
  EXPECT_EQ(std::count(text.begin(), text.end(), '\n'), 1);
  EXPECT_EQ(text.back(), '\n');
  EXPECT_NE(text.find("[############------------]  2/2 save"), std::string::npos);
}

}  // namespace
}  // namespace penumbra::core
