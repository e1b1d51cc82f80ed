#include "reference/settings_tuning.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <set>
#include <stdexcept>
#include <tuple>

#include <opencv2/core.hpp>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>

#include "core/json_reader.h"
#include "core/replace_file.h"
#include "shadow/frame_loop.h"

namespace penumbra::reference {

std::vector<NamedPose> loadPoseSet(const std::filesystem::path& path) {
  const core::JsonDocument doc(path, core::throwAs<core::Error>);
  const core::JsonValue root = doc.root();
  root.object({"format", "version", "poses"});
  core::requireFileFormat(root, "penumbra-poses", 1);
  std::vector<NamedPose> poses;
  std::set<std::string> names;
  for (const core::JsonValue& v : root["poses"].array(1, 1000)) {
    v.object({"name", "product", "at"});
    NamedPose p;
    p.name = v["name"].nonEmptyString();
    if (!names.insert(p.name).second) v["name"].fail("\"" + p.name + "\" names two poses");
    p.pose.product = static_cast<uint32_t>(v["product"].integer(0, 1'000'000));
    const core::JsonValue at = v["at"];
    const std::vector<double> xyzw = at.numbers(4);
    const auto within = [&](size_t i, double lo, double hi, const char* what) {
      if (!(xyzw[i] >= lo && xyzw[i] <= hi)) {
        at.fail(std::string(what) + " " + core::formatNumber(xyzw[i]) + " is not in [" +
                core::formatNumber(lo) + ", " + core::formatNumber(hi) + "]");
      }
      return static_cast<float>(xyzw[i]);
    };
    p.pose.x = within(0, -1000, 1000, "x");
    p.pose.lift = within(1, 0, 10, "lift");
    p.pose.z = within(2, -1000, 1000, "z");
    p.pose.yawDegrees = within(3, -3600, 3600, "yaw");
    poses.push_back(std::move(p));
  }
  return poses;
}

namespace {

// The board's cost of a frame of the product just moved there: the still frame's passes and
// shadowed pixels, every product vertex placed, transferred and shaded again (what a kiosk
// frame pays while a visitor moves the product), so the cost does not depend on which frame
// came before.
double boardMs(const shadow::CostModel& board, const shadow::FrameLoop& loop) {
  shadow::CostModel::Workload work;
  work.passes = loop.stats.passes;
  work.shadowedPixels = loop.renderer.lastStats().passPixels;
  work.shadowMapTexels = loop.renderer.lastStats().shadowMapTexels;
  work.productVertices = loop.stats.productVertices;
  work.shadedVertices = loop.stats.productVertices;
  work.transferredVertices = loop.stats.productVertices;
  work.shadowMapTriangles = loop.renderer.lastStats().shadowMapTriangles;
  return double(board.frameNs(0, work)) * 1e-6;
}

bool within(const PoseError& e, const ErrorTarget& t) {
  const uint32_t p99 = t.p99BeyondBounds ? e.p99BeyondBounds.value() : e.p99;
  const bool shadow = e.pixels == 0 || (e.meanAbs <= t.meanAbs && double(p99) <= t.p99 &&
                                        (t.flip <= 0 || e.flip <= t.flip));
  return shadow && (t.productMeanAbs <= 0 || e.productMeanAbs <= t.productMeanAbs);
}

class Measurer {
 public:
  Measurer(const shadow::SceneBundle& bundle, const TuneOptions& o)
      : bundle_(bundle), options_(o), board_(o.board) {
    compare_.flip.pixelsPerDegree = o.measure.pixelsPerDegree;
    // FLIP costs about 100x the other metrics: measured only when the target has it.
    compare_.computeFlip = o.target.flip > 0;
  }

  // Every pose of `poses` with `settings` (stopping at the first that misses when
  // `stopAtMiss`), against `references` in the same order, the product's pixels against
  // `productReferences` (empty: against `references`). `missed` (when given) gets the
  // frame at the first pose that missed, and `missedPose` its index.
  TunedCandidate measure(const shadow::RenderSettings& settings,
                         const std::vector<NamedPose>& poses,
                         const std::vector<PoseReference>& references,
                         const std::vector<core::Image8>& productReferences, bool stopAtMiss,
                         core::Image8* missed = nullptr, size_t* missedPose = nullptr) {
    TunedCandidate c;
    c.settings = settings;
    c.meets = true;
    shadow::FrameLoop loop(bundle_, shadow::compositorOptions(settings), options_.measure.render);
    for (size_t i = 0; i < poses.size(); ++i) {
      loop.still(poses[i].pose, settings.maxPasses);
      core::Image8 frame =
          fromRgba8(loop.rgba, bundle_.view.width, bundle_.view.height, "penumbra frame");
      const ImageComparison cmp =
          compareImages(references[i].image, frame, &references[i].region, compare_);
      PoseError e;
      e.pose = poses[i].name;
      e.meanAbs = cmp.masked->pixels ? cmp.masked->meanAbs : 0.0;
      e.p99 = cmp.masked->pixels ? cmp.masked->p99Abs : 0;
      e.flip = cmp.masked->pixels ? cmp.masked->flipMean : 0.0;
      e.pixels = cmp.masked->pixels;
      // Over the product's own pixels (the same silhouette whatever the candidate). An
      // interval of one value is the reference itself: the plain error, without the
      // whole-frame SSIM compareImages would add.
      const core::Image8& productReference =
          productReferences.empty() ? references[i].image : productReferences[i];
      const RegionErrors product =
          intervalErrors(productReference, productReference, frame, references[i].productRegion);
      e.productPixels = product.pixels;
      e.productMeanAbs = product.pixels ? product.meanAbs : 0.0;
      if (!references[i].lower.pixels.empty()) {
        e.p99BeyondBounds =
            intervalErrors(references[i].lower, references[i].upper, frame, references[i].region)
                .p99Abs;
      }
      e.boardMs = boardMs(board_, loop);
      c.boardMs = std::max(c.boardMs, e.boardMs);
      c.worstMeanAbs = std::max(c.worstMeanAbs, e.meanAbs);
      const bool ok = within(e, options_.target);
      c.poses.push_back(std::move(e));
      if (!ok) {
        if (c.meets && missed) {
          *missed = std::move(frame);
          *missedPose = i;
        }
        c.meets = false;
        if (stopAtMiss) break;
      }
    }
    return c;
  }

 private:
  const shadow::SceneBundle& bundle_;
  const TuneOptions& options_;
  shadow::CostModel board_;
  CompareOptions compare_;
};

// The q-quantile (nearest rank, q in [0, 1]) of the per-pixel LDR-FLIP between `a` and `b`
// over `region`'s pixels; 0 for an empty region.
double regionFlip(const core::Image8& a, const core::Image8& b, const core::Image8& region,
                  double pixelsPerDegree, double q) {
  CompareOptions o;
  o.flip.pixelsPerDegree = pixelsPerDegree;
  const ImageComparison c = compareImages(a, b, &region, o);
  std::vector<float> values;
  for (size_t i = 0; i < region.pixels.size(); ++i) {
    if (region.pixels[i]) values.push_back(c.flipMap[i]);
  }
  if (values.empty()) return 0.0;
  const size_t rank = std::min(values.size() - 1, size_t(std::ceil(q * double(values.size()))));
  std::nth_element(values.begin(), values.begin() + std::ptrdiff_t(rank), values.end());
  return values[rank];
}

// What the display can just show in `region`: the median per-pixel FLIP of `image` against
// itself with the region one level darker (each channel, clamped at 0).
double oneLevelFlip(const core::Image8& image, const core::Image8& region, double pixelsPerDegree) {
  core::Image8 darker = image;
  const size_t channels = image.channels;
  for (size_t i = 0; i < region.pixels.size(); ++i) {
    if (!region.pixels[i]) continue;
    for (size_t c = 0; c < channels; ++c) {
      uint8_t& v = darker.pixels[i * channels + c];
      v = v > 0 ? uint8_t(v - 1) : v;
    }
  }
  return regionFlip(image, darker, region, pixelsPerDegree, 0.5);
}

void checkPoses(const shadow::SceneBundle& bundle, const std::vector<NamedPose>& poses) {
  for (const NamedPose& p : poses) {
    if (p.pose.product >= bundle.products.size()) {
      throw std::invalid_argument("pose " + p.name + ": product " + std::to_string(p.pose.product) +
                                  ", the bundle has " + std::to_string(bundle.products.size()));
    }
  }
}

std::invalid_argument boundsNeeded(const std::string& kind) {
  return std::invalid_argument(
      "tune: p99 beyond the reference's bounds needs a reference with bounds (the ray "
      "tracer's), not " +
      kind);
}

}  // namespace

TuneReferences makeTuneReferences(const shadow::SceneBundle& bundle, const TuneOptions& o,
                                  const TuneProgress& progress) {
  checkPoses(bundle, o.poses);
  checkPoses(bundle, o.heldOut);
  // Refused before the stand-in's references are made, which would have no bounds.
  if (o.target.p99BeyondBounds && o.measure.penumbraReference) throw boundsNeeded("penumbra");
  const bool product = o.target.productMeanAbs > 0;
  if (product && o.measure.penumbraReference) {
    throw std::invalid_argument(
        "tune: a product target needs the ray tracer's reference: the stand-in's product is "
        "Penumbra's own shading");
  }
  TuneReferences r;
  const size_t total = (o.poses.size() + o.heldOut.size()) * (product ? 2 : 1);
  AccuracyOptions withBounces = o.measure;
  withBounces.rays.bounces = o.productBounces;
  size_t made = 0;
  for (const auto& [poses, into, productInto] :
       {std::tuple{&o.poses, &r.poses, &r.productPoses},
        std::tuple{&o.heldOut, &r.heldOut, &r.productHeldOut}}) {
    for (const NamedPose& p : *poses) {
      if (progress) progress(made++, total, "reference " + p.name);
      into->push_back(makePoseReference(bundle, o.measure, p.pose));
      if (!product) continue;
      if (progress) progress(made++, total, "product reference " + p.name);
      productInto->push_back(makePoseReference(bundle, withBounces, p.pose).image);
    }
  }
  if (progress) progress(total, total, "references made");
  return r;
}

TuneReport tuneSettings(const shadow::SceneBundle& bundle, const TuneOptions& o,
                        const TuneProgress& progress) {
  return tuneSettings(bundle, o, makeTuneReferences(bundle, o, progress), progress);
}

TuneReport tuneSettings(const shadow::SceneBundle& bundle, const TuneOptions& o,
                        const TuneReferences& made, const TuneProgress& progress) {
  if (o.poses.empty()) throw std::invalid_argument("tune: no poses to tune on");
  if (o.passCeilings.empty() || o.mapSizes.empty() || o.fineProxyPasses.empty() ||
      o.areaPenumbrae.empty()) {
    throw std::invalid_argument("tune: an empty list of candidates");
  }
  checkPoses(bundle, o.poses);
  checkPoses(bundle, o.heldOut);
  if (made.poses.size() != o.poses.size() || made.heldOut.size() != o.heldOut.size()) {
    throw std::invalid_argument("tune: the references are not one per pose");
  }
  if ((o.target.productMeanAbs > 0) && (made.productPoses.size() != o.poses.size() ||
                                        made.productHeldOut.size() != o.heldOut.size())) {
    throw std::invalid_argument("tune: a product target needs a product reference per pose");
  }
  const std::vector<PoseReference>& references = made.poses;
  const std::vector<PoseReference>& heldOutReferences = made.heldOut;
  std::vector<uint32_t> ceilings = o.passCeilings;
  std::sort(ceilings.begin(), ceilings.end());
  ceilings.erase(std::unique(ceilings.begin(), ceilings.end()), ceilings.end());
  // Fine-proxy passes change nothing where no posed product has a fine proxy.
  const bool anyFine = std::any_of(o.poses.begin(), o.poses.end(), [&](const NamedPose& p) {
    return !bundle.products[p.pose.product].fineProxy.indices.empty();
  });
  const std::vector<uint32_t> fines =
      anyFine ? o.fineProxyPasses : std::vector<uint32_t>{o.fineProxyPasses.front()};
  // The posed products with a fine proxy, each searched on its own after the grid when the
  // set poses more than one product (with one, the grid's uniform count is already its own).
  std::set<uint32_t> posedProducts;
  for (const NamedPose& p : o.poses) posedProducts.insert(p.pose.product);
  std::vector<uint32_t> finePosed;
  for (const uint32_t product : posedProducts) {
    if (posedProducts.size() > 1 && !bundle.products[product].fineProxy.indices.empty()) {
      finePosed.push_back(product);
    }
  }
  const size_t productSteps = finePosed.size() * o.fineProxyPasses.size();
  for (uint32_t map : o.mapSizes) {
    for (uint32_t n : ceilings) {
      for (uint32_t fine : fines) shadow::validateRenderSettings({n, map, fine, true, true});
    }
  }
  // Every pair of shaft settings to try with the rest of `base` held; a setting without
  // values to try keeps `base`'s own.
  const auto forEachShaftPair = [&](const shadow::RenderSettings& base, const auto& visit) {
    const auto orKept = [](auto values, auto kept) {
      return values.empty() ? decltype(values){kept} : values;
    };
    for (double prune : orKept(o.pruneFractions, base.pruneFraction)) {
      for (uint32_t leaf : orKept(o.receiversPerLeaf, base.receiversPerLeaf)) {
        shadow::RenderSettings s = base;
        s.pruneFraction = prune;
        s.receiversPerLeaf = leaf;
        visit(s);
      }
    }
  };
  forEachShaftPair(shadow::RenderSettings{},
                   [](const shadow::RenderSettings& s) { shadow::validateRenderSettings(s); });
  for (const double texels : o.texelsPerShadowPixel) {
    shadow::RenderSettings s;
    s.texelsPerShadowPixel = texels;
    shadow::validateRenderSettings(s);
  }
  const size_t clusterMapSteps = o.texelsPerShadowPixel.size() * o.mapSizes.size();

  const size_t combinations = o.mapSizes.size() * fines.size() * o.areaPenumbrae.size();
  const size_t shaftPairs = o.pruneFractions.empty() && o.receiversPerLeaf.empty()
                                ? 0
                                : std::max<size_t>(o.pruneFractions.size(), 1) *
                                      std::max<size_t>(o.receiversPerLeaf.size(), 1);
  const size_t total = combinations * ceilings.size() + shaftPairs + clusterMapSteps +
                       productSteps + 1 + (o.heldOut.empty() ? 0 : 2);
  size_t done = 0;
  const auto step = [&](const std::string& what) {
    if (progress) progress(done, total, what);
    ++done;
  };

  TuneReport report;
  for (const auto* set : {&references, &heldOutReferences}) {
    for (const PoseReference& r : *set) {
      report.references.push_back(r.info);
      if (o.target.p99BeyondBounds && r.lower.pixels.empty()) {
        throw boundsNeeded(r.info.value("kind", std::string("this one")));
      }
    }
  }

  // Each pose's one-level FLIP threshold, for perceptual stopping.
  std::vector<double> oneLevelLevels(references.size(), 0.0);
  if (o.perceptualStop) {
    for (size_t i = 0; i < references.size(); ++i) {
      oneLevelLevels[i] =
          oneLevelFlip(references[i].image, references[i].region, o.measure.pixelsPerDegree);
    }
  }

  Measurer measurer(bundle, o);
  for (const bool area : o.areaPenumbrae) {
    for (const uint32_t map : o.mapSizes) {
      for (const uint32_t fine : fines) {
        core::Image8 previous;  // the last ceiling's frame where it missed
        size_t previousPose = SIZE_MAX;
        for (size_t k = 0; k < ceilings.size(); ++k) {
          const shadow::RenderSettings s{ceilings[k], map, fine, area, true};
          step("map " + std::to_string(map) + ", fine " + std::to_string(fine) + ", area " +
               (area ? "on" : "off") + ", " + std::to_string(ceilings[k]) + " passes");
          core::Image8 missed;
          size_t missedPose = SIZE_MAX;
          report.candidates.push_back(measurer.measure(s, o.poses, references, made.productPoses,
                                                       true, &missed, &missedPose));
          TunedCandidate& c = report.candidates.back();
          bool stop = c.meets;
          if (!c.meets && o.perceptualStop && missedPose == previousPose) {
            const PoseReference& ref = references[missedPose];
            // The 99th percentile: a change confined to a penumbra moves few pixels, and
            // the mean over the whole shadow would call it invisible.
            c.flipToPrevious =
                regionFlip(previous, missed, ref.region, o.measure.pixelsPerDegree, 0.99);
            c.flipOneLevel = oneLevelLevels[missedPose];
            c.stoppedPerceptually = c.flipToPrevious < c.flipOneLevel;
            stop = c.stoppedPerceptually;
          }
          if (stop) {
            done += ceilings.size() - 1 - k;  // the larger ceilings, not measured
            break;
          }
          previous = std::move(missed);
          previousPose = missedPose;
        }
      }
    }
  }
  const auto choose = [&] {
    report.chosen.reset();
    for (size_t i = 0; i < report.candidates.size(); ++i) {
      const TunedCandidate& c = report.candidates[i];
      if (!c.meets || (o.maxBoardMs > 0 && c.boardMs > o.maxBoardMs)) continue;
      // Strictly cheaper only: among equals the first measured (fewer passes, smaller maps).
      if (!report.chosen || c.boardMs < report.candidates[*report.chosen].boardMs) {
        report.chosen = i;
      }
    }
  };
  choose();
  // Coarse to fine: the shaft settings around the grid's choice. They move which receivers a
  // pass draws (the board model's shadowed pixels) and, through the light pruned, the error;
  // measured on the showroom's corners they barely move the error (docs/tuning.md), so each
  // pair is tried once around the choice rather than multiplying the grid.
  if (shaftPairs > 0) {
    shadow::RenderSettings around =
        report.chosen ? report.candidates[*report.chosen].settings : bundle.settings;
    around.tuned = true;
    forEachShaftPair(around, [&](const shadow::RenderSettings& s) {
      step("shafts: prune " + core::formatNumber(s.pruneFraction) + ", " +
           std::to_string(s.receiversPerLeaf) + " receivers per leaf");
      // The choice itself is measured already.
      if (report.chosen && s == around) return;
      report.candidates.push_back(
          measurer.measure(s, o.poses, references, made.productPoses, true));
    });
    choose();
  }
  // Then a map per cluster, around the choice: each pass's map shrinks from the frame's to what
  // its shadow's footprint on screen needs, so it is tried under the choice's map and the larger
  // ones (mapSizes in the order given; smaller caps only shrink the maps further).
  if (clusterMapSteps > 0) {
    shadow::RenderSettings around =
        report.chosen ? report.candidates[*report.chosen].settings : bundle.settings;
    around.tuned = true;
    for (const double texels : o.texelsPerShadowPixel) {
      for (const uint32_t map : o.mapSizes) {
        if (map < around.shadowMapSize) {
          ++done;
          continue;
        }
        shadow::RenderSettings s = around;
        s.texelsPerShadowPixel = texels;
        s.shadowMapSize = map;
        step("map per cluster: " + core::formatNumber(texels) + " texels per pixel, at most " +
             std::to_string(map));
        if (report.chosen && s == report.candidates[*report.chosen].settings) continue;
        report.candidates.push_back(
            measurer.measure(s, o.poses, references, made.productPoses, true));
      }
    }
    choose();
  }
  // Then each posed product's fine-proxy passes on its own, the rest held: one product's
  // count changes only the frames it stands in, and products want opposite counts
  // (RenderSettings::productFineProxyPasses).
  if (productSteps > 0) {
    // The choice so far (the bundle's own settings when nothing met), one count per product.
    const auto aroundChoice = [&] {
      shadow::RenderSettings s =
          report.chosen ? report.candidates[*report.chosen].settings : bundle.settings;
      s.tuned = true;
      if (s.productFineProxyPasses.empty()) {
        s.productFineProxyPasses.assign(bundle.products.size(), s.fineProxyPasses);
      }
      return s;
    };
    shadow::RenderSettings around = aroundChoice();
    for (const uint32_t product : finePosed) {
      for (const uint32_t fine : o.fineProxyPasses) {
        shadow::RenderSettings s = around;
        s.productFineProxyPasses[product] = fine;
        step(bundle.products[product].name + ": fine proxy in " + std::to_string(fine) +
             " of 50 passes");
        if (report.chosen && shadow::fineProxyPassesOf(report.candidates[*report.chosen].settings,
                                                       product) == fine) {
          continue;  // the choice itself
        }
        report.candidates.push_back(
            measurer.measure(s, o.poses, references, made.productPoses, true));
      }
      choose();
      around = aroundChoice();
    }
  }

  step("the bundle's own settings");
  shadow::RenderSettings defaults = bundle.settings;
  report.defaults = measurer.measure(defaults, o.poses, references, made.productPoses, false);
  if (!o.heldOut.empty()) {
    step("held-out poses, the bundle's settings");
    report.heldOutDefaults =
        measurer.measure(defaults, o.heldOut, heldOutReferences, made.productHeldOut, false);
    if (report.chosen) {
      step("held-out poses, the choice");
      report.heldOutChosen = measurer.measure(report.candidates[*report.chosen].settings, o.heldOut,
                                              heldOutReferences, made.productHeldOut, false);
    }
  }
  if (progress) progress(total, total, "done");
  return report;
}

namespace {

nlohmann::json settingsJson(const shadow::RenderSettings& s) {
  return {{"max_passes", s.maxPasses},
          {"shadow_map_size", s.shadowMapSize},
          {"fine_proxy_passes", s.fineProxyPasses},
          {"product_fine_proxy_passes", s.productFineProxyPasses},
          {"area_penumbrae", s.areaPenumbrae},
          {"prune_fraction", s.pruneFraction},
          {"receivers_per_leaf", s.receiversPerLeaf},
          {"texels_per_shadow_pixel", s.texelsPerShadowPixel}};
}

nlohmann::json candidateJson(const TunedCandidate& c, bool flipMeasured) {
  nlohmann::json poses = nlohmann::json::array();
  for (const PoseError& e : c.poses) {
    poses.push_back({{"pose", e.pose},
                     {"mean_abs_shadow", e.meanAbs},
                     {"p99_abs_shadow", e.p99},
                     {"p99_beyond_bounds_shadow",
                      e.p99BeyondBounds ? nlohmann::json(*e.p99BeyondBounds) : nullptr},
                     {"flip_shadow", flipMeasured ? nlohmann::json(e.flip) : nullptr},
                     {"shadow_pixels", e.pixels},
                     {"mean_abs_product", e.productMeanAbs},
                     {"product_pixels", e.productPixels},
                     {"board_ms", e.boardMs}});
  }
  return {{"settings", settingsJson(c.settings)},
          {"meets", c.meets},
          {"flip_to_previous_ceiling",
           c.flipToPrevious >= 0 ? nlohmann::json(c.flipToPrevious) : nullptr},
          {"flip_one_level", c.flipOneLevel >= 0 ? nlohmann::json(c.flipOneLevel) : nullptr},
          {"stopped_perceptually", c.stoppedPerceptually},
          {"board_ms", c.boardMs},
          {"worst_mean_abs_shadow", c.worstMeanAbs},
          {"poses", poses}};
}

}  // namespace

nlohmann::json toJson(const TuneOptions& o, const TuneReport& r) {
  nlohmann::json candidates = nlohmann::json::array();
  for (const TunedCandidate& c : r.candidates)
    candidates.push_back(candidateJson(c, o.target.flip > 0));
  nlohmann::json j = {
      {"target",
       {{"mean_abs_shadow", o.target.meanAbs},
        {"p99_abs_shadow", o.target.p99},
        {"p99_beyond_bounds", o.target.p99BeyondBounds},
        {"flip_shadow", o.target.flip > 0 ? nlohmann::json(o.target.flip) : nullptr},
        {"mean_abs_product",
         o.target.productMeanAbs > 0 ? nlohmann::json(o.target.productMeanAbs) : nullptr}}},
      {"max_board_ms", o.maxBoardMs > 0 ? nlohmann::json(o.maxBoardMs) : nullptr},
      {"board", "Raspberry Pi 4 cost model (shadow::CostModel::raspberryPi4)"},
      {"references", r.references},
      {"candidates", candidates},
      {"chosen", r.chosen ? nlohmann::json(*r.chosen) : nullptr},
      {"defaults", candidateJson(r.defaults, o.target.flip > 0)}};
  if (r.chosen) {
    const TunedCandidate& c = r.candidates[*r.chosen];
    j["settings"] = settingsJson(c.settings);
    j["board_ms"] = c.boardMs;
    j["board_ms_saved"] = r.defaults.boardMs - c.boardMs;
  }
  if (!o.heldOut.empty()) {
    j["held_out"] = {
        {"defaults", candidateJson(r.heldOutDefaults, o.target.flip > 0)},
        {"chosen", r.chosen ? candidateJson(r.heldOutChosen, o.target.flip > 0) : nullptr}};
  }
  return j;
}

void writeParetoChart(const std::filesystem::path& path, const TuneOptions& o,
                      const TuneReport& r) {
  const int width = 900, height = 560, left = 80, right = 30, top = 50, bottom = 60;
  double maxMs = r.defaults.boardMs, maxErr = std::max(o.target.meanAbs, r.defaults.worstMeanAbs);
  for (const TunedCandidate& c : r.candidates) {
    maxMs = std::max(maxMs, c.boardMs);
    maxErr = std::max(maxErr, c.worstMeanAbs);
  }
  maxMs = maxMs > 0 ? maxMs * 1.08 : 1.0;
  maxErr = maxErr > 0 ? maxErr * 1.1 : 1.0;
  const auto px = [&](double ms, double err) {
    return cv::Point(left + int(std::lround(ms / maxMs * (width - left - right))),
                     height - bottom - int(std::lround(err / maxErr * (height - top - bottom))));
  };
  cv::Mat img(height, width, CV_8UC3, cv::Scalar(255, 255, 255));
  const cv::Scalar black(0, 0, 0), grey(170, 170, 170), green(40, 150, 40), red(30, 30, 200);
  // Text at `at`, moved left as far as it takes to end inside the image.
  const auto text = [&](const std::string& t, cv::Point at, double scale = 0.45) {
    int baseline = 0;
    const int w = cv::getTextSize(t, cv::FONT_HERSHEY_SIMPLEX, scale, 1, &baseline).width;
    at.x = std::max(2, std::min(at.x, width - 4 - w));
    cv::putText(img, t, at, cv::FONT_HERSHEY_SIMPLEX, scale, black, 1, cv::LINE_AA);
  };
  cv::line(img, px(0, 0), px(maxMs, 0), black);
  cv::line(img, px(0, 0), px(0, maxErr), black);
  for (int k = 0; k <= 5; ++k) {
    char label[32];
    std::snprintf(label, sizeof label, "%.0f", maxMs * k / 5);
    text(label, px(maxMs * k / 5, 0) + cv::Point(-10, 20));
    std::snprintf(label, sizeof label, "%.2f", maxErr * k / 5);
    text(label, px(0, maxErr * k / 5) + cv::Point(-55, 5));
  }
  text("frame on the Raspberry Pi 4 cost model (ms)", cv::Point(width / 2 - 170, height - 15), 0.5);
  text("worst pose: mean abs error in the shadow (levels)", cv::Point(10, 30), 0.5);
  // The target: a dashed line.
  for (double ms = 0; ms < maxMs; ms += maxMs / 60) {
    cv::line(img, px(ms, o.target.meanAbs), px(std::min(maxMs, ms + maxMs / 120), o.target.meanAbs),
             red);
  }
  text("target", px(0, o.target.meanAbs) + cv::Point(6, -6));
  text("green: meets the target at every pose; grey: misses it (mean, p99 or budget)",
       cv::Point(left, top - 8), 0.4);
  for (const TunedCandidate& c : r.candidates) {
    cv::circle(img, px(c.boardMs, c.worstMeanAbs), 4, c.meets ? green : grey, cv::FILLED,
               cv::LINE_AA);
  }
  const cv::Point d = px(r.defaults.boardMs, r.defaults.worstMeanAbs);
  cv::rectangle(img, d - cv::Point(6, 6), d + cv::Point(6, 6), black, 2);
  text("defaults", d + cv::Point(9, -8));
  if (r.chosen) {
    const TunedCandidate& c = r.candidates[*r.chosen];
    const cv::Point p = px(c.boardMs, c.worstMeanAbs);
    cv::circle(img, p, 10, red, 2, cv::LINE_AA);
    // The fine-proxy passes: one count, or one per product.
    std::string fine = std::to_string(c.settings.fineProxyPasses);
    if (!c.settings.productFineProxyPasses.empty()) {
      fine.clear();
      for (const uint32_t n : c.settings.productFineProxyPasses) {
        if (!fine.empty()) fine += '/';
        fine += std::to_string(n);
      }
    }
    char label[128];
    std::snprintf(label, sizeof label, "chosen: %u passes, map %u, fine %s, area %s",
                  c.settings.maxPasses, c.settings.shadowMapSize, fine.c_str(),
                  c.settings.areaPenumbrae ? "on" : "off");
    text(label, p + cv::Point(14, 16));
  }
  std::vector<uint8_t> png;
  if (!cv::imencode(".png", img, png)) {
    throw core::Error(path.string() + ": cannot encode the chart as PNG");
  }
  core::writeFileReplacing(path, png);
}

}  // namespace penumbra::reference
