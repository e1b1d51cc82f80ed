// Chart (d) data: 8-bit drift against the number of faint passes (bench/faint_pass_drift.h).
//
//   build/dev/bin/penumbra-drift --csv drift.csv [--max-passes 200] [--share 0.5]
#include "bench/faint_pass_drift.h"

#include <CLI/CLI.hpp>
#include <cstdio>
#include <fstream>
#include <stdexcept>

#include "core/cli.h"

int main(int argc, char** argv) {
  using namespace penumbra;
  CLI::App app{"8-bit drift of N faint shadow passes against the HDR answer (Gibson 2003 §10)"};
  std::string csv;
  int maxPasses = 200, vertices = 64;
  double share = 0.5, gamma = 2.2;
  app.add_option("--csv", csv, "CSV output")->required();
  app.add_option("--max-passes", maxPasses, "N = 1..this")
      ->check(cli::NumberRange(1, 100000))
      ->capture_default_str();
  app.add_option("--share", share, "share of the vertex radiance the N sources carry together")
      ->check(cli::NumberRange(0.0, 1.0))
      ->capture_default_str();
  app.add_option("--vertices", vertices, "radiance levels per N")
      ->check(cli::NumberRange(1, 100000))
      ->capture_default_str();
  app.add_option("--gamma", gamma, "display gamma of the tone curve T()")
      ->check(cli::NumberRange(1.0, 4.0))
      ->capture_default_str();
  return cli::run("penumbra-drift", app, argc, argv, [&] {
    std::ofstream out(csv);
    if (!out) throw std::runtime_error(csv + ": cannot write");
    const shadow::ToneCurve tone = shadow::ToneCurve::gamma(1.0, gamma);
    out << "passes,mask,policy,mean_abs,max_abs,mean_signed\n";
    for (uint8_t mask : {uint8_t{255}, uint8_t{128}}) {
      for (bench::DriftPolicy p :
           {bench::DriftPolicy::kIndependent, bench::DriftPolicy::kFig4,
            bench::DriftPolicy::kGraded, bench::DriftPolicy::kGradedFixed8_8}) {
        for (int n = 1; n <= maxPasses; ++n) {
          const bench::DriftResult r =
              bench::measureFaintPassDrift(tone, n, mask, p, share, vertices);
          out << n << ',' << int(mask) << ',' << bench::driftPolicyName(p) << ',' << r.meanAbs
              << ',' << r.maxAbs << ',' << r.meanSigned << '\n';
          if (n == maxPasses) {
            std::printf("passes %d mask %3d %-19s mean_abs %.3f max_abs %d mean_signed %+.3f\n", n,
                        int(mask), bench::driftPolicyName(p), r.meanAbs, r.maxAbs, r.meanSigned);
          }
        }
      }
    }
    if (!out) throw std::runtime_error(csv + ": write failed");
    return 0;
  });
}
