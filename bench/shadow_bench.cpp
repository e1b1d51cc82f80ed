// Per-frame shaft traversal and source-cluster selection (Gibson 2003 §6.1, §8) as the
// kiosk runs them, and the hierarchy's build, on the hand-built room of the unit tests
// (1,024 floor receivers x 60 ceiling sources). Target: <= 0.25 ms per frame on the board.
// And T() (shadow/tone_curve.h), which the intensity transfers call per vertex and source:
// its definition (binary search) against the bucket table the frame uses.
//   build/ci/bin/penumbra_shadow_bench
#include <benchmark/benchmark.h>

#include <vector>

#include "bench/benchmark_main.h"
#include "shadow/shaft_hierarchy.h"
#include "shadow/source_clusters.h"
#include "shadow/tone_curve.h"
#include "tests/shaft_test_room.h"

namespace penumbra::shadow {
namespace {

struct Room {
  scene::PatchMesh mesh;
  SourceReceiverSets sets;
  RadianceTransfers transfers;
  Room() { testing::buildTestRoom(32, 10, 6, false, mesh, sets, transfers); }
};

// A 0.5 m object sliding across the floor, one position per frame.
scene::Aabb boxAt(int64_t k) {
  const double x = 0.5 + 3.0 * double(k % 200) / 200.0;
  return scene::Aabb{{x, 0.0, 1.5}, {x + 0.5, 0.5, 2.0}};
}

// 4,096 radiances spread over the curve's whole range (a running radiance of Fig. 4 falls
// through many codes), T() of each per iteration: Arg 0 the binary search, 1 the table.
void BM_ToneCurve(benchmark::State& state) {
  const ToneCurve tone = ToneCurve::gamma(1.2, 2.2);
  std::vector<double> radiance(4096);
  for (size_t i = 0; i < radiance.size(); ++i) {
    radiance[i] = 1.0 / 1.2 * double((i * 2654435761u) % 4096) / 4096.0;
  }
  const bool table = state.range(0) == 1;
  for (auto _ : state) {
    unsigned sum = 0;
    for (double l : radiance) sum += table ? tone(l) : tone.bySearch(l);
    benchmark::DoNotOptimize(sum);
  }
  state.SetItemsProcessed(state.iterations() * int64_t(radiance.size()));
}
BENCHMARK(BM_ToneCurve)->Arg(0)->Arg(1)->Unit(benchmark::kMicrosecond);

void BM_ShaftHierarchyBuild(benchmark::State& state) {
  const Room room;
  const double prune = double(state.range(0)) / 100.0;
  size_t shafts = 0, bytes = 0;
  for (auto _ : state) {
    const ShaftHierarchy h(room.mesh, room.sets, room.transfers, {8, prune});
    shafts = h.shaftCount();
    bytes = h.memoryBytes();
  }
  state.counters["shafts"] = double(shafts);
  state.counters["KiB"] = double(bytes) / 1024.0;
}
BENCHMARK(BM_ShaftHierarchyBuild)->Arg(0)->Arg(2)->Unit(benchmark::kMillisecond);

// One frame: traverse for the object's box, then select 16 clusters (state.range(0) = 2:
// the 2% pruning the bundle ships, 0: none, the geometric floor of the source list).
void BM_TraverseAndSelect(benchmark::State& state) {
  const Room room;
  const ShaftHierarchy h(room.mesh, room.sets, room.transfers, {8, double(state.range(0)) / 100.0});
  TraversalResult traversal;
  ClusterSelection sel;
  h.traverse(boxAt(0), 0, traversal);
  selectSourceClusters(h, traversal.sources, 0, 16, sel);
  int64_t frame = 0;
  double visited = 0, sources = 0, clusters = 0;
  for (auto _ : state) {
    ++frame;
    h.traverse(boxAt(frame), static_cast<uint32_t>(frame), traversal);
    selectSourceClusters(h, traversal.sources, static_cast<uint32_t>(frame), 16, sel);
    visited += double(traversal.shaftsVisited);
    sources += double(traversal.sources.size());
    clusters += double(sel.clusters.size());
  }
  state.counters["shafts_visited"] =
      benchmark::Counter(visited, benchmark::Counter::kAvgIterations);
  state.counters["sources"] = benchmark::Counter(sources, benchmark::Counter::kAvgIterations);
  state.counters["clusters"] = benchmark::Counter(clusters, benchmark::Counter::kAvgIterations);
}
BENCHMARK(BM_TraverseAndSelect)->Arg(2)->Arg(0)->Unit(benchmark::kMicrosecond);

}  // namespace
}  // namespace penumbra::shadow

int main(int argc, char** argv) {
  return penumbra::bench::benchmarkMain("penumbra_shadow_bench", argc, argv);
}
