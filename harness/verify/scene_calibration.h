// Calibration of the scene image test, the block pyramid (harness/verify/block_pyramid.h): does
// a comparison's verdict, at every scale, and its reported minimum detectable bias (MDB) at every
// scale mean what they say? The statistics per seed and over seeds are
// harness/verify/pyramid_calibration.h's; this file plans the runs and renders them per seed
// (harness/commands/tile_calibration.h prints and writes the result).
//
// A comparison of a scene is a pyramid of L scales (8×8 tiles, 16, 32, ... up to the whole
// image), n_s block×channel tests at scale s (one-sample t against an exact image, or Welch
// between two runs, on the replicates' block means), decided by a weighted Holm with weight
// 1 / (L n_s): rejected at α when its smallest adjusted p is <= α. Each comparison here is
// decided alone (a family of one comparison), at α = test_alpha, and its MDB at scale s is the
// one that decision's first step implies, at the scale's detection share α / (L n_s).
//
//  1. Size. For every seed each estimator renders R replicate images of each scene. A scene with
//     an exact image (the furnace) is tested against it, one row per estimator; every other scene
//     compares every pair of estimators (independent runs: their plans have different ids, so
//     different random streams, as in a session; with `paired`, runs that share their streams,
//     tested on replicate differences, as in a session with --paired). A row counts the seeds whose
//     comparison rejects (family-wise false alarms) and, per scale, the seeds whose comparison
//     rejects through that scale (its smallest adjusted p <= α). Holm is conservative and the tests
//     are correlated, so the rate is at most α overall and about α / L per scale (its share, also
//     reported): the failure is "more alarms than α allows", the one-sided binomial p-value
//     P(X >= alarms), X ~ Binomial(seeds, α), overall and per scale. The raw p-value of the
//     block holding the image centre (green) at each scale, which should be U(0, 1) across
//     seeds, is KS-tested.
//  2. Power, on the first pair of each compared scene, per scale: k × the comparison's own
//     reported MDB of one block of that scale added to every pixel of that block (its channel)
//     in the first estimator's images, and the whole pyramid tested again; the block chosen per
//     seed by two rules, the brightest (brightest_block, the session's 2×MDB self-check rule,
//     at every scale) and the fixed centre block. The injected block's statistic then moves by
//     exactly k·m (m = t_{1-s/2,ν} + t_{power,ν}, s the scale's share, ν the block's dof), so
//     its test rejects at s with probability shifted_t_power(k m, ν, s): the nominal power at
//     k = 1, about 0.8. A detection is the pyramid rejecting; the prediction is for the block's
//     own test at its share, also counted. The centre block is chosen before any sample is seen,
//     so its unbiased statistic is centred and the predictions hold for it; the brightest is
//     chosen on the sample tested, which can favour a block whose noise in a is positive
//     (mean_statistic), so a positive bias there may be found more often than predicted.
//
// Deterministic: seeds run in parallel, each into its own slot; a scene run is bitwise the same
// for any thread count.
#pragma once

#include <atomic>
#include <cstdint>
#include <string>
#include <vector>

#include "base/params.h"
#include "harness/verify/pyramid_calibration.h"
#include "harness/verify/run_calibration.h"  // CalibrationInterrupted

namespace pcbench {

struct TileCalibrationOptions {
  // Honest estimators (a negative control makes its rows fail: how the tests show the
  // calibration can fail). Compared scenes need at least two, each sampling every path.
  std::vector<std::string> estimators = {"pt", "plain"};
  // Scenes: with an exact image, tested against it; without, compared pairwise.
  std::vector<std::string> scenes = {"furnace", "cornell"};
  ParamText params = {};  // key -> value for the estimators and scenes (resolution, ...)
  // Samples per pixel per replicate image. Few: a tile mean averages 64 pixels × spp samples,
  // which is near normal already (a coarser block's mean more so); the calibration needs many
  // seeds, not converged images.
  std::uint64_t samples = 4;
  std::uint32_t replicates = 8;  // images per run (Welch dof up to 2R - 2)
  std::uint32_t seeds = 1000;
  std::uint64_t first_seed = 1;
  // Every comparison is decided alone at this α (a false alarm, or a detection, is a
  // rejection). 0.05 as for the runs' calibration: at the session's 0.01, 1000 seeds would
  // expect at most 10 false alarms (Holm being conservative, fewer), too few to measure a rate.
  double test_alpha = 0.05;
  // A row passes when its one-sided binomial p, and at every scale the scale's one-sided binomial
  // p and its centre block's KS p, are >= this: the error budget of the calibration itself.
  // With the defaults, 3 rows (furnace × 2 estimators, one cornell pair) × (1 + 2 × 3 scales)
  // tests at 1e-3 each, a correct pyramid fails it with probability <= 2.1% (Bonferroni; the
  // per-scale binomial tests, whose rates are about α / 3 against α, all but never fail, so
  // nearer 1.2%).
  double pass_threshold = 1e-3;
  // The k of the power curves (bias = k × the injected block's MDB); empty: no power curve.
  std::vector<double> bias_multipliers = {0.5, 1.0, 2.0};
  // Scene runs with paired streams (RunPlan::paired_streams), their pairs tested by the paired
  // pyramid: the calibration of the paired design (--paired).
  bool paired = false;
  const std::atomic<bool>* interrupted = nullptr;  // Ctrl-C: throws CalibrationInterrupted
};

// One size test: a comparison (against the exact image, or between two runs) once per seed,
// overall and per scale (harness/verify/pyramid_calibration.h).
struct TileSizeRow : PyramidSizeRow {
  std::string scene = {};
  std::uint32_t width = 0, height = 0;             // of the images
  std::string estimator_a = {}, estimator_b = {};  // b "exact" against the exact image
  std::string run_a = {}, run_b = {};              // plan ids (b "exact")
  bool biased = false;                             // a side is a negative control: expected to fail
};

// One power curve: a bias of k × its own MDB into one block of one scale of a's images.
struct TilePowerCurve : ScalePowerCurve {
  std::string scene = {};
  std::uint32_t width = 0, height = 0;
  std::string estimator_a = {}, estimator_b = {};  // the bias goes into a's images
  std::string run_a = {}, run_b = {};
};

struct TileCalibrationResult {
  TileCalibrationOptions options = {};
  std::vector<TileSizeRow> rows = {};  // per scene in order: exact rows, then pairs
  // Per compared scene (its first pair): the brightest block at each scale, finest first, then
  // the centre block at each scale.
  std::vector<TilePowerCurve> power = {};
  bool pass = false;  // every row passes (overall and at every scale)
  double wall_seconds = 0.0;
};

// Whether `integrand` names a scene (built-in or a scene file), so that `pcbench calibrate`
// calibrates the block pyramid on it. Throws InputError for an unknown name.
bool is_scene_name(const std::string& integrand);

// Runs the pyramid calibration. Throws InputError for bad options (unknown names, an analytic
// integrand, a compared scene with fewer than 2 estimators or one that cannot sample every path,
// fewer than 2 replicates or seeds, a non-finite or non-positive k), CalibrationInterrupted on
// Ctrl-C, and std::runtime_error if a run fails.
TileCalibrationResult calibrate_tiles(const TileCalibrationOptions& options);

}  // namespace pcbench
