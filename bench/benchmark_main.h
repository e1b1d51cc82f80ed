// The main() of the Google Benchmark programs (penumbra_bench, penumbra_shadow_bench,
// penumbra_shading_bench) under the project's command-line conventions (core/cli.h):
// `--version`, `<program>: error: ...` with exit 2 for an argument Google Benchmark does not
// take, exit 1 when a benchmark throws. Its own flags (--benchmark_filter=..., --help) pass
// through unchanged.
#pragma once

namespace penumbra::bench {

// Runs the registered benchmarks; returns the exit code.
int benchmarkMain(const char* program, int argc, char** argv);

}  // namespace penumbra::bench
