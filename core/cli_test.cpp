#include "core/cli.h"

#include <gtest/gtest.h>

#include <cstdio>
#include <string>
#include <vector>

namespace penumbra::cli {
namespace {

// Runs `app` on `args` (program name first) with stderr captured; returns the exit code.
struct Outcome {
  int code;
  std::string err;
};

Outcome runWith(CLI::App& app, std::vector<std::string> args, const std::function<int()>& body) {
  std::vector<char*> argv;
  for (std::string& a : args) argv.push_back(a.data());
  testing::internal::CaptureStderr();
  const int code = run("prog", app, static_cast<int>(argv.size()), argv.data(), body);
  return {code, testing::internal::GetCapturedStderr()};
}

TEST(Cli, SuccessReturnsTheBodysCode) {
  CLI::App app;
  EXPECT_EQ(runWith(app, {"prog"}, [] { return 0; }).code, kExitOk);
}

TEST(Cli, RuntimeErrorIsExitOneWithThePrefix) {
  CLI::App app;
  const Outcome o =
      runWith(app, {"prog"}, []() -> int { throw std::runtime_error("a.json: x: bad"); });
  EXPECT_EQ(o.code, kExitRuntimeError);
  EXPECT_EQ(o.err, "prog: error: a.json: x: bad\n");
}

TEST(Cli, ParseErrorIsExitTwoWithThePrefixAndAHint) {
  CLI::App app;
  int n = 0;
  app.add_option("--n", n)->check(NumberRange(1, 257));
  bool ran = false;
  const Outcome o = runWith(app, {"prog", "--n", "1,10,50"}, [&] {
    ran = true;
    return 0;
  });
  EXPECT_FALSE(ran);
  EXPECT_EQ(o.code, kExitUsage);
  EXPECT_EQ(o.err,
            "prog: error: --n: expects a single whole number from 1 to 257 (not a list), got "
            "'1,10,50'\nRun 'prog --help' for usage.\n");
}

TEST(Cli, UsageErrorFromTheBodyIsExitTwo) {
  CLI::App app;
  const Outcome o = runWith(app, {"prog"}, []() -> int { throw UsageError("needs --a or --b"); });
  EXPECT_EQ(o.code, kExitUsage);
  EXPECT_NE(o.err.find("prog: error: needs --a or --b\n"), std::string::npos);
}

TEST(Cli, UnknownCommandIsNamed) {
  CLI::App app;
  app.require_subcommand(1);
  app.add_subcommand("render", "");
  app.add_subcommand("replay", "");
  const Outcome o = runWith(app, {"prog", "tune"}, [] { return 0; });
  EXPECT_EQ(o.code, kExitUsage);
  EXPECT_EQ(o.err.substr(0, o.err.find('\n')),
            "prog: error: unknown command 'tune' (commands: render, replay)");
}

TEST(Cli, TheHintNamesTheCommandWhoseFlagsFailed) {
  CLI::App app;
  app.require_subcommand(1);
  int n = 0;
  app.add_subcommand("render", "")->add_option("--n", n)->check(NumberRange(1, 9));
  const Outcome o = runWith(app, {"prog", "render", "--n", "10"}, [] { return 0; });
  EXPECT_EQ(o.code, kExitUsage);
  EXPECT_NE(o.err.find("Run 'prog render --help' for usage."), std::string::npos);
}

TEST(Cli, VersionNamesTheProgram) {
  CLI::App app;
  testing::internal::CaptureStdout();
  const Outcome o = runWith(app, {"prog", "--version"}, [] { return 1; });
  const std::string out = testing::internal::GetCapturedStdout();
  EXPECT_EQ(o.code, kExitOk);
  EXPECT_EQ(out, std::string("prog ") + version() + "\n");
}

TEST(Cli, RangeProblemSaysWhatIsExpected) {
  EXPECT_EQ(rangeProblem("2.5", "1", "9", true, false),
            "expects a whole number from 1 to 9, got '2.5'");
  EXPECT_EQ(rangeProblem("x", "0.5", "1", false, false), "expects a number from 0.5 to 1, got 'x'");
  EXPECT_EQ(rangeProblem("300", "1", "257", true, true),
            "expects a comma-separated list of whole numbers from 1 to 257, got '300'");
}

TEST(Cli, NumberRangeAcceptsTheBoundsAndRefusesOutside) {
  NumberRange r(1, 257);
  for (std::string ok : {"1", "257", "100"}) EXPECT_EQ(r(ok), "") << ok;
  for (std::string bad : {"0", "258", "1.5", "1,2", ""}) EXPECT_NE(r(bad), "") << bad;
  NumberRange d(0.01, 1.0);
  EXPECT_EQ(d(std::string("0.01")), "");
  EXPECT_NE(d(std::string("1.01")), "");
}

}  // namespace
}  // namespace penumbra::cli
