#include "core/cli.h"

#include <cstdio>
#include <exception>
#include <new>
#include <vector>

#include "penumbra_version.h"

namespace penumbra::cli {

const char* version() {
  return kPenumbraVersion;
}

std::string rangeProblem(const std::string& value, const std::string& min, const std::string& max,
                         bool wholeNumbers, bool isList) {
  const std::string kind = wholeNumbers ? "whole number" : "number";
  const std::string range = " from " + min + " to " + max;
  const std::string got = ", got '" + value + "'";
  if (isList) return "expects a comma-separated list of " + kind + "s" + range + got;
  if (value.find_first_of(", ") != std::string::npos) {
    return "expects a single " + kind + range + " (not a list)" + got;
  }
  return "expects a " + kind + range + got;
}

void printError(const std::string& program, const std::string& message) {
  std::fprintf(stderr, "%s: error: %s\n", program.c_str(), message.c_str());
}

void printUsageError(const std::string& program, const std::string& command,
                     const std::string& message) {
  printError(program, message);
  std::fprintf(stderr, "Run '%s --help' for usage.\n", command.c_str());
}

namespace {

// "penumbra render" when the error is in `render`'s flags: the help that explains them.
std::string commandPath(const CLI::App& app) {
  std::string path = app.get_name();
  const CLI::App* current = &app;
  for (;;) {
    const std::vector<CLI::App*> parsed = current->get_subcommands();
    if (parsed.empty()) return path;
    current = parsed.back();
    path += " " + current->get_name();
  }
}

void printUsageError(const CLI::App& app, const std::string& message) {
  cli::printUsageError(app.get_name(), commandPath(app), message);
}

// The names of `app`'s commands, "a, b, c".
std::string commandNames(const CLI::App& app) {
  std::string names;
  for (const CLI::App* sub : app.get_subcommands([](const CLI::App*) { return true; })) {
    names += (names.empty() ? "" : ", ") + sub->get_name();
  }
  return names;
}

// A program made of commands (`penumbra render ...`) whose first argument names no command or
// is an unknown option: CLI11 would say "A subcommand is required" for either.
std::string unknownCommandOrOption(const CLI::App& app, int argc, char** argv) {
  if (app.get_require_subcommand_min() == 0 || argc < 2) return {};
  const std::string first = argv[1];
  if (first.empty()) return {};
  if (first[0] == '-') {
    // Before a command only the program's own options (--help, --version) are known.
    if (app.get_option_no_throw(first.substr(0, first.find('='))) != nullptr) return {};
    return "unknown option '" + first + "' (options go after the command: " + app.get_name() +
           " COMMAND --help)";
  }
  try {
    (void)app.get_subcommand(first);
    return {};
  } catch (const CLI::OptionNotFound&) {
    return "unknown command '" + first + "' (commands: " + commandNames(app) + ")";
  }
}

}  // namespace

int run(const std::string& program, CLI::App& app, int argc, char** argv,
        const std::function<int()>& body) {
  app.name(program);
  app.set_version_flag("--version", program + " " + version(), "print the version and exit");
  if (const std::string unknown = unknownCommandOrOption(app, argc, argv); !unknown.empty()) {
    printUsageError(app, unknown);
    return kExitUsage;
  }
  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    // --help and --version end the parse with exit code 0; CLI11 prints them.
    if (e.get_exit_code() == 0) return app.exit(e);
    if (dynamic_cast<const CLI::RequiredError*>(&e) != nullptr && app.get_subcommands().empty() &&
        app.get_require_subcommand_min() > 0) {
      printUsageError(app, "a command is required (one of: " + commandNames(app) + ")");
    } else {
      printUsageError(app, e.what());
    }
    return kExitUsage;
  }
  try {
    return body();
  } catch (const UsageError& e) {
    printUsageError(app, e.what());
    return kExitUsage;
  } catch (const std::bad_alloc&) {
    printError(program, "out of memory");
    return kExitRuntimeError;
  } catch (const std::exception& e) {
    printError(program, e.what());
    return kExitRuntimeError;
  }
}

}  // namespace penumbra::cli
