// `penumbra tune` (issue 17): the cheapest render settings (shadow/render_settings.h) whose
// frames meet an error target at every pose of a set, against a reference at each pose.
//
// The search. The references are made once per pose (the ray tracer dominates the run) and
// every candidate is measured against the same ones. For each combination of shadow-map size,
// fine-proxy passes and area penumbrae, the pass ceilings are tried in increasing order and
// the first that meets the target at every pose ends that combination: more passes only cost
// more, and the error does not rise with passes within the reference's noise (issue 15's
// targets, docs/accuracy.md). A candidate stops at the first pose that misses. Refinement also
// stops where more passes would not be seen (Gibson & Chalmers 2003 §8.2.2, after Gibson and
// Hubbold's perception-driven radiosity): when two successive ceilings miss at the same pose
// and 99 % of the shadow region's pixels differ between their frames there by less LDR-FLIP
// than the median pixel of that region changed by one level (the display's own step, the
// least difference it can show), the combination is left. The choice is
// the cheapest candidate that meets the target (within the frame budget when one is given);
// ties go to the candidate measured first. Nothing in the choice is timed: a frame's cost is
// the simulated board's (shadow::CostModel::raspberryPi4) for the work the frame did, at the
// dearest pose, so the same inputs choose the same settings on every machine.
//
// Cost: one reference per pose, then per candidate at most one fresh frame and one still frame
// per pose (a few tens of milliseconds each at 640x480) and an image comparison.
#pragma once

#include <cstdint>
#include <filesystem>
#include <functional>
#include <optional>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "reference/accuracy.h"
#include "shadow/frame_cost_model.h"
#include "shadow/render_settings.h"
#include "shadow/scene_bundle.h"

namespace penumbra::reference {

// One pose of a pose set, by name.
struct NamedPose {
  std::string name;
  shadow::ProductPose pose;
};

// Reads a pose set: {"format": "penumbra-poses", "version": 1, "poses": [{"name": "corner",
// "product": 0, "at": [X, LIFT, Z, YAW_DEGREES]}, ...]} (at least one pose; names unique;
// lifts in [0, 10] m, coordinates within ±1000 m). Throws core::Error naming the file and the
// field.
std::vector<NamedPose> loadPoseSet(const std::filesystem::path& path);

// What every pose must meet, in 8-bit levels within the shadow region.
struct ErrorTarget {
  double meanAbs = 1.0;
  double p99 = 6.0;
  double flip = 0;  // mean LDR-FLIP in the shadow region; 0: not checked
  // p99 beyond the reference's bounds (reference/differential.h: where the photograph's 8
  // bits leave the reference open) instead of against its midpoint. Needs a reference with
  // bounds (the ray tracer's); the mean stays against the midpoint.
  bool p99BeyondBounds = false;
  // Mean abs over the product's own pixels (8-bit levels, per channel sample): how it is
  // shaded (Gibson & Chalmers 2003 §5, the irradiance volume) rather than its shadow, against
  // a reference with TuneOptions::productBounces of indirect light; 0: not checked. Needs the
  // ray tracer's reference (the stand-in's product is Penumbra's own).
  double productMeanAbs = 0;
};

struct TuneOptions {
  ErrorTarget target;
  std::vector<NamedPose> poses;    // tuned on
  std::vector<NamedPose> heldOut;  // only measured with the choice (and the defaults)
  // The reference at each pose and how frames are drawn and compared (its reference fields,
  // rays, render options and FLIP viewing condition; the pipeline fields are the candidates').
  AccuracyOptions measure;
  // The product's own reference (only with target.productMeanAbs): the ray tracer's with this
  // many indirect bounces. The shadow's reference has measure.rays.bounces (0 by default:
  // the passes take away the sources' direct light, and the photograph holds the rest), but
  // the irradiance volume shades the product with the room's whole light, and against
  // direct light only the bunny in the open is 67.5 levels off over its own pixels, with 2
  // bounces 15.1 (docs/tuning.md).
  int productBounces = 2;
  // The candidates: every map size x fine-proxy passes x area penumbrae, each with the pass
  // ceilings in increasing order. Fine-proxy passes are tried only when a posed product has a
  // fine proxy (otherwise just the first value).
  std::vector<uint32_t> passCeilings{4, 8, 12, 16, 24, 32, 40, 50, 64};
  std::vector<uint32_t> mapSizes{64, 128, 256, 512};
  std::vector<uint32_t> fineProxyPasses{0, 8, 16, 32};
  std::vector<bool> areaPenumbrae{true, false};
  // Coarse to fine: the shaft hierarchy's settings (RenderSettings::pruneFraction,
  // receiversPerLeaf), each pair tried with the rest of the grid's choice held (with the
  // bundle's own settings when nothing met). Empty: that setting kept as the candidate has
  // it. `penumbra tune` tries 0.005, 0.01, 0.02, 0.05 and 4, 8, 16.
  std::vector<double> pruneFractions;
  std::vector<uint32_t> receiversPerLeaf;
  // Then a shadow map per source cluster (RenderSettings::texelsPerShadowPixel,
  // shadow/cluster_map_size.h): each value tried around the choice so far, under its map size
  // and under every larger one of mapSizes (each pass's own map only shrinks from that cap, so a
  // larger cap lets the clusters whose shadows look large get finer maps than the uniform
  // choice). Empty: not searched. `penumbra tune` tries 2, 4 and 8.
  std::vector<double> texelsPerShadowPixel;
  // Stop raising a combination's passes when the frames no longer change visibly (above).
  bool perceptualStop = true;
  // The frame budget on the board, ms (from `--fps`); 0: none.
  double maxBoardMs = 0;
  shadow::CostModel::Params board = shadow::CostModel::raspberryPi4();
};

// One pose's error, as `penumbra accuracy` measures it.
struct PoseError {
  std::string pose;
  double meanAbs = 0, flip = 0;
  uint32_t p99 = 0;
  std::optional<uint32_t> p99BeyondBounds;  // when the reference has bounds
  uint64_t pixels = 0;                      // in the shadow region
  double productMeanAbs = 0;                // over the product's pixels (ErrorTarget)
  uint64_t productPixels = 0;
  double boardMs = 0;  // the frame's cost on the board, fresh at this pose
};

struct TunedCandidate {
  shadow::RenderSettings settings;
  std::vector<PoseError> poses;  // in the set's order; stops at the first that misses
  bool meets = false;            // every pose measured and within the target
  double boardMs = 0;            // the dearest pose's
  double worstMeanAbs = 0;       // over the poses measured
  // When it missed at the same pose as the previous ceiling: the 99th-percentile FLIP
  // between the two frames in that pose's shadow region, and the one-level threshold there
  // (the median FLIP of a one-level change). -1: not compared.
  double flipToPrevious = -1, flipOneLevel = -1;
  bool stoppedPerceptually = false;  // flipToPrevious < flipOneLevel: no larger ceiling tried
};

struct TuneReport {
  std::vector<TunedCandidate> candidates;  // in the order measured
  std::optional<size_t> chosen;            // index into candidates
  TunedCandidate defaults;  // the bundle's own settings, every pose (meets: all within)
  TunedCandidate heldOutChosen, heldOutDefaults;  // the held-out poses, when any
  std::vector<nlohmann::json> references;         // per pose (set, then held out): its kind
};

// Progress: `done` steps of at most `total` of one phase (the references, then the
// candidates), and what is being measured.
using TuneProgress = std::function<void(size_t done, size_t total, const std::string& what)>;

// Each pose's reference, the set's then the held-out ones', made once: every candidate is
// measured against them. They depend on the room, its photograph, the tone curve and the
// products, not on the source set, so scene models that differ only there (other power
// shares) share them. Throws what making a reference throws, and std::invalid_argument for a
// product the bundle lacks.
struct TuneReferences {
  std::vector<PoseReference> poses, heldOut;
  // With a product target: per pose, the reference with productBounces (its product pixels
  // are what is measured); empty otherwise.
  std::vector<core::Image8> productPoses, productHeldOut;
};
TuneReferences makeTuneReferences(const shadow::SceneBundle& bundle, const TuneOptions& options,
                                  const TuneProgress& progress = {});

// Throws std::invalid_argument for an empty pose set, an empty candidate list, a map size or
// pass ceiling the settings refuse (validateRenderSettings), references that are not one per
// pose, or a p99 beyond bounds asked of a reference without them; the first form also what
// making a reference throws.
TuneReport tuneSettings(const shadow::SceneBundle& bundle, const TuneOptions& options,
                        const TuneProgress& progress = {});
TuneReport tuneSettings(const shadow::SceneBundle& bundle, const TuneOptions& options,
                        const TuneReferences& references, const TuneProgress& progress = {});

// The report as JSON: the target, every candidate (settings, per-pose errors and cost), the
// choice, the defaults and the held-out poses.
nlohmann::json toJson(const TuneOptions& options, const TuneReport& report);

// A Pareto chart of cost (board ms, x) against the worst pose's mean error (y) of every
// candidate measured at every pose: candidates that meet the target in green, others grey,
// the choice ringed, the defaults as a square, the target as a dashed line. PNG, written
// whole or not at all (core::writeFileReplacing).
void writeParetoChart(const std::filesystem::path& path, const TuneOptions& options,
                      const TuneReport& report);

}  // namespace penumbra::reference
