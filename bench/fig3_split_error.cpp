// Gibson 2003 Fig. 3, measured on the showroom: the 8-bit error of subtracting intensity
// transfers S_ij for a random set of P actually occluded sources, against the HDR answer
// T(L_i - sum over occluded L_ij), as P grows — for Fig. 4's fixed 50/50 split, and for
// intensityTransfersForOcclusion() with q fixed and q set to the occluded share (what the
// kiosk gets from the previous frame; frames are coherent).
//
//   build/release/bin/penumbra-fig3 data/showroom/showroom.json --csv fig3.csv
//   /usr/bin/python3 bench/plot_fig3.py fig3.csv fig3.png
#include <CLI/CLI.hpp>
#include <algorithm>
#include <cstdio>
#include <fstream>
#include <numeric>
#include <random>

#include "core/cli.h"
#include "lighting/precompute.h"
#include "scene/scene_file.h"
#include "shadow/intensity_transfer.h"

namespace {

using namespace penumbra;

struct Policy {
  const char* name;
  std::function<void(const glm::dvec3&, std::span<const glm::dvec3>, std::span<const uint8_t>,
                     double, std::span<core::Rgb8>)>
      compute;
};

}  // namespace

int main(int argc, char** argv) {
  CLI::App app{"Fig. 3 of Gibson 2003, measured: intensity-transfer error against occlusion"};
  std::string scenePath, csvPath;
  int trials = 200, minSources = 20;
  app.add_option("SCENE", scenePath, "scene file (data/showroom/showroom.json)")->required();
  app.add_option("--csv", csvPath, "CSV output")->required();
  app.add_option("--trials", trials, "random occluded sets per occlusion level")
      ->capture_default_str();
  app.add_option("--min-sources", minSources, "vertices with at least this many sources")
      ->capture_default_str();
  return penumbra::cli::run("penumbra-fig3", app, argc, argv, [&] {
    const scene::SceneDescription scene = scene::loadSceneFile(scenePath);
    std::vector<lighting::StageTiming> timings;
    const shadow::SceneBundle b = lighting::precomputeBundle(scene, {}, timings);
    const shadow::RadianceTransfers& t = b.transfers;

    // Per receiver vertex: its sources' transfers in the frame order of §7.1.1 (decreasing
    // average transfer) and their patch ids.
    std::vector<size_t> order(b.sets.sources.size());
    std::iota(order.begin(), order.end(), 0);
    std::stable_sort(order.begin(), order.end(),
                     [&](size_t a, size_t c) { return t.sourceAverage[a] > t.sourceAverage[c]; });
    std::vector<std::vector<std::pair<size_t, glm::dvec3>>> perVertex(t.receiverVertices.size());
    for (size_t s : order) {
      for (uint32_t e = t.sourceStart[s]; e < t.sourceStart[s + 1]; ++e) {
        perVertex[t.entryVertex[e]].push_back({s, glm::dvec3(t.entryTransfer[e])});
      }
    }
    const std::vector<Policy> policies = {
        {"fig4_50_50",
         [&](const glm::dvec3& l, std::span<const glm::dvec3> x, std::span<const uint8_t> sets,
             double,
             std::span<core::Rgb8> out) { shadow::intensityTransfers(l, x, sets, b.tone, out); }},
        {"graded_q_0.5",
         [&](const glm::dvec3& l, std::span<const glm::dvec3> x, std::span<const uint8_t>, double,
             std::span<core::Rgb8> out) {
           shadow::intensityTransfersForOcclusion(l, x, 0.5, b.tone, out);
         }},
        {"graded_q_measured",
         [&](const glm::dvec3& l, std::span<const glm::dvec3> x, std::span<const uint8_t>,
             double share, std::span<core::Rgb8> out) {
           shadow::intensityTransfersForOcclusion(l, x, share, b.tone, out);
         }},
    };

    std::ofstream csv(csvPath);
    csv << "occluded_share";
    for (const Policy& p : policies) csv << ',' << p.name << "_mean_abs," << p.name << "_p99_abs";
    csv << '\n';
    std::printf("%8s", "occluded");
    for (const Policy& p : policies) std::printf(" %22s", p.name);
    std::printf("\n");
    std::mt19937_64 rng(2003);
    size_t vertices = 0;
    for (const auto& v : perVertex) vertices += v.size() >= size_t(minSources);
    for (int step = 0; step <= 20; ++step) {
      const double share = step / 20.0;
      std::vector<std::vector<double>> errors(policies.size());
      for (size_t i = 0; i < perVertex.size(); ++i) {
        const auto& sources = perVertex[i];
        if (sources.size() < size_t(minSources)) continue;
        const size_t n = sources.size();
        std::vector<glm::dvec3> x(n);
        std::vector<uint8_t> sets(n);
        for (size_t j = 0; j < n; ++j) {
          x[j] = sources[j].second;
          sets[j] = uint8_t(shadow::sourceSet(1, b.sets.sources[sources[j].first]));
        }
        const glm::dvec3 total(t.vertexRadiance[i]);
        const core::Rgb8 c0 = b.tone.map(total);
        std::vector<std::vector<core::Rgb8>> s(policies.size(), std::vector<core::Rgb8>(n));
        for (size_t k = 0; k < policies.size(); ++k)
          policies[k].compute(total, x, sets, share, s[k]);
        std::vector<size_t> pick(n);
        std::iota(pick.begin(), pick.end(), 0);
        const size_t occluded = size_t(share * double(n) + 0.5);
        for (int trial = 0; trial < trials; ++trial) {
          std::shuffle(pick.begin(), pick.end(), rng);
          glm::dvec3 rest = total;
          for (size_t m = 0; m < occluded; ++m) rest -= glm::max(x[pick[m]], glm::dvec3(0.0));
          const core::Rgb8 truth = b.tone.map(rest);
          for (size_t k = 0; k < policies.size(); ++k) {
            int r = c0.r, g = c0.g, bl = c0.b;
            for (size_t m = 0; m < occluded; ++m) {
              r -= s[k][pick[m]].r;
              g -= s[k][pick[m]].g;
              bl -= s[k][pick[m]].b;
            }
            // The frame buffer saturates at 0 (spec §8: one clamp of the sum).
            const double e =
                (std::abs(std::max(r, 0) - truth.r) + std::abs(std::max(g, 0) - truth.g) +
                 std::abs(std::max(bl, 0) - truth.b)) /
                3.0;
            errors[k].push_back(e);
          }
        }
      }
      csv << share;
      std::printf("%8.2f", share);
      for (auto& e : errors) {
        std::sort(e.begin(), e.end());
        const double mean = std::accumulate(e.begin(), e.end(), 0.0) / double(e.size());
        const double p99 = e[std::min(e.size() - 1, size_t(0.99 * double(e.size())))];
        csv << ',' << mean << ',' << p99;
        std::printf(" %12.3f (p99 %5.1f)", mean, p99);
      }
      csv << '\n';
      std::printf("\n");
    }
    std::printf("vertices %zu (>= %d sources each), trials %d per level\n", vertices, minSources,
                trials);
    return 0;
  });
}
