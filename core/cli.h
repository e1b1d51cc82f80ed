// The conventions every program of the project follows (README "Command-line conventions"):
//
//   exit 0  success
//   exit 1  runtime error: an input file, the data or the machine (core::Error, std::exception)
//   exit 2  usage error: unknown command or flag, a bad or missing value, flags that do not
//           go together (CLI11 parse errors, cli::UsageError)
//
// Every error goes to stderr as one line `<program>: error: <message>`; a usage error adds a
// second line naming the --help to read. `--version` prints `<program> <version>`, where the
// version is CMake's project version and, when the source is a git checkout at configure
// time, `git describe` of it.
#pragma once

#include <CLI/CLI.hpp>
#include <functional>
#include <sstream>
#include <stdexcept>
#include <string>
#include <type_traits>

namespace penumbra::cli {

inline constexpr int kExitOk = 0;
inline constexpr int kExitRuntimeError = 1;
inline constexpr int kExitUsage = 2;

// "0.1 (git v0.1-12-g0123abc-dirty)", or "0.1" outside a git checkout.
const char* version();

// Thrown by a command whose flags parsed but do not make sense together ("render needs
// --passes N or --fps F"): reported like a parse error, with exit 2.
class UsageError : public std::invalid_argument {
 public:
  using std::invalid_argument::invalid_argument;
};

// `<program>: error: <message>` on stderr; the usage form adds "Run '<command> --help' for
// usage." (for programs whose flags another library parses: bench/benchmark_main).
void printError(const std::string& program, const std::string& message);
void printUsageError(const std::string& program, const std::string& command,
                     const std::string& message);

// Names `app` after `program`, adds --version, parses argv and calls `body` (which returns
// the exit code on success). Maps every failure to the conventions above; `body` may throw.
int run(const std::string& program, CLI::App& app, int argc, char** argv,
        const std::function<int()>& body);

// CLI::Range that says what it expects. A value of the wrong shape — a list where one
// number is expected ("--passes 1,10,50" on render), a fraction for a count — gets
// "--passes: expects a single whole number from 1 to 257, got '1,10,50'" rather than
// CLI11's "Value 1,10,50 not in range 1 to 257". `NumberRange::list` is the check of one
// element of a comma-separated option (the message says a list is accepted).
class NumberRange : public CLI::Validator {
 public:
  template <typename T>
  NumberRange(T min, T max) : NumberRange(min, max, false) {}

  template <typename T>
  static NumberRange list(T min, T max) {
    return NumberRange(min, max, true);
  }

 private:
  template <typename T>
  NumberRange(T min, T max, bool isList);
};

// A comma-separated option of numbers, each checked by NumberRange::list(min, max).
template <typename V, typename T>
CLI::Option* addNumberList(CLI::App* app, const std::string& name, std::vector<V>& into,
                           const std::string& help, T min, T max) {
  return app->add_option(name, into, help)->delimiter(',')->check(NumberRange::list(min, max));
}

// The message of NumberRange for `value` outside [min, max] or not a number (testable
// without CLI11's option machinery).
std::string rangeProblem(const std::string& value, const std::string& min, const std::string& max,
                         bool wholeNumbers, bool isList);

template <typename T>
NumberRange::NumberRange(T min, T max, bool isList) {
  std::ostringstream minOut, maxOut;
  minOut << min;
  maxOut << max;
  const std::string minText = minOut.str(), maxText = maxOut.str();
  description(std::string(CLI::detail::type_name<T>()) + (isList ? " list, each in [" : " in [") +
              minText + " - " + maxText + "]");
  func_ = [min, max, minText, maxText, isList](std::string& value) -> std::string {
    T parsed{};
    if (CLI::detail::lexical_cast(value, parsed) && !(parsed < min) && !(max < parsed)) return {};
    return rangeProblem(value, minText, maxText, std::is_integral_v<T>, isList);
  };
}

}  // namespace penumbra::cli
