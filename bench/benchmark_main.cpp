#include "bench/benchmark_main.h"

#include <benchmark/benchmark.h>

#include <exception>
#include <iostream>
#include <string>
#include <string_view>

#include "core/cli.h"

namespace penumbra::bench {

int benchmarkMain(const char* program, int argc, char** argv) {
  for (int i = 1; i < argc; ++i) {
    if (std::string_view(argv[i]) == "--version") {
      std::cout << program << " " << cli::version() << "\n";
      return cli::kExitOk;
    }
  }
  try {
    // Takes the --benchmark_* flags out of argv (and prints --help, exit 0); what is left
    // beyond the program name is not a flag of this program.
    benchmark::Initialize(&argc, argv);
    if (argc > 1) {
      cli::printUsageError(program, program, std::string("unknown argument '") + argv[1] + "'");
      return cli::kExitUsage;
    }
    benchmark::RunSpecifiedBenchmarks();
    benchmark::Shutdown();
    return cli::kExitOk;
  } catch (const std::exception& e) {
    cli::printError(program, e.what());
    return cli::kExitRuntimeError;
  }
}

}  // namespace penumbra::bench
