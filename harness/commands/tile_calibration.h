// Calibration of the scene tile test (harness/verify/image_statistics.h): does a tile comparison's
// verdict and its reported minimum detectable bias (MDB) mean what they say?
//
// A comparison of a scene is T = tiles × 3 tile×channel tests (one-sample t against an exact
// image, or Welch between two runs, on the replicates' tile means), Holm over the T, rejected at
// α when its smallest Holm-adjusted p is <= α, i.e. when some raw tile p is <= α / T. Each
// comparison here is decided alone (a family of one comparison), at α = test_alpha, and its MDB
// is the one that decision threshold implies (decide_tiles' share α / T).
//
//  1. Size. For every seed each estimator renders R replicate images of each scene. A scene with
//     an exact image (the furnace) is tested against it, one row per estimator; every other scene
//     compares every pair of estimators (independent runs: their plans have different ids, so
//     different random streams, as in a session). A row counts the seeds whose comparison
//     rejects (family-wise false alarms). Holm is conservative and the tests of one tile's
//     channels are correlated, so the rate is at most α, not α itself: the failure is "more
//     alarms than α allows", the one-sided binomial p-value P(X >= alarms), X ~ Binomial(seeds,
//     α). The smallest adjusted p over seeds is not uniform (it is T × a minimum), so it is not
//     KS-tested; instead the raw p-value of one fixed tile×channel test (the tile at the image
//     centre, green), which should be U(0, 1) across seeds, is (Kolmogorov–Smirnov).
//  2. Power, on the first pair of each compared scene, with the bias added to one tile×channel
//     of the first estimator's images, chosen per seed by two rules: the brightest tile
//     (brightest_tile, the session's 2×MDB self-check rule) and the fixed centre tile.
//     (a) k × that comparison's own reported MDB of that tile, for each k: the bias is then
//         k × m × the sample's own estimated standard error (m = t_{1-s/2,ν} + t_{power,ν},
//         s = α / T, ν the tile's Welch dof). Adding a constant to every replicate leaves the
//         spread alone, so the tile's statistic moves by exactly k·m and its test rejects with
//         probability P(T_ν > t_{1-s/2,ν} - k·m) + P(T_ν < -t_{1-s/2,ν} - k·m)
//         (shifted_t_power; the nominal power at k = 1), if the unbiased statistic T_ν is
//         Student's t with the Welch dof. The prediction is the mean of that over seeds.
//     (b) a fixed δ_k = k × the median over seeds of that MDB, the same in every seed: the
//         power a bias of that size really has, predicted by the noncentral t with
//         noncentrality δ_k / the RMS over seeds of the tile's standard error and the median
//         Welch dof (as harness/commands/calibration.cpp predicts the runs' power).
//     A detection is the comparison rejecting; the prediction is for the injected tile's own
//     test (its raw p <= s, Holm's first threshold), also counted: the other tiles' false alarms
//     add at most the row's false-alarm rate. The centre tile is chosen before any sample is
//     seen, so its unbiased statistic is centred and the predictions hold for it. The brightest
//     tile is chosen on the sample tested: where two tiles are about as bright, the largest tile
//     mean of a favours the one whose noise in a is positive, so its unbiased statistic is not
//     centred (mean_statistic) and a positive bias there is found more often than predicted;
//     that curve measures the self-check as a session runs it.
//
// Deterministic: seeds run in parallel, each into its own slot; a scene run is bitwise the same
// for any thread count.
#pragma once

#include <atomic>
#include <cstdint>
#include <iosfwd>
#include <nlohmann/json_fwd.hpp>
#include <string>
#include <vector>

#include "base/params.h"
#include "harness/run/diagnostics.h"
#include "harness/session/session.h"

namespace pcbench {

struct TileCalibrationOptions {
  // Honest estimators (a negative control makes its rows fail: how the tests show the
  // calibration can fail). Compared scenes need at least two, each sampling every path.
  std::vector<std::string> estimators = {"pt", "plain"};
  // Scenes: with an exact image, tested against it; without, compared pairwise.
  std::vector<std::string> scenes = {"furnace", "cornell"};
  ParamText params = {};  // key -> value for the estimators and scenes (resolution, ...)
  // Samples per pixel per replicate image. Few: a tile mean averages 64 pixels × spp samples,
  // which is near normal already; the calibration needs many seeds, not converged images.
  std::uint64_t samples = 4;
  std::uint32_t replicates = 8;  // images per run (Welch dof up to 2R - 2)
  std::uint32_t seeds = 1000;
  std::uint64_t first_seed = 1;
  // Every comparison is decided alone at this α (a false alarm, or a detection, is a
  // rejection). 0.05 as for the runs' calibration: at the session's 0.01, 1000 seeds would
  // expect at most 10 false alarms (Holm being conservative, fewer), too few to measure a rate.
  double test_alpha = 0.05;
  // A row passes when its one-sided binomial p and its fixed tile's KS p are both >= this: the
  // error budget of the calibration itself. With the defaults, 3 rows (furnace × 2 estimators,
  // one cornell pair) × 2 tests at 1e-3 each, a correct tile test fails it with probability
  // <= 0.6% (Bonferroni).
  double pass_threshold = 1e-3;
  // The k of the power curves (bias = k × MDB); empty: no power curve.
  std::vector<double> bias_multipliers = {0.5, 1.0, 2.0};
  const std::atomic<bool>* interrupted = nullptr;  // Ctrl-C: throws CalibrationInterrupted
};

// One size test: a comparison (against the exact image, or between two runs) once per seed.
struct TileSizeRow {
  std::string scene = {};
  std::uint32_t width = 0, height = 0;             // of the images
  std::string estimator_a = {}, estimator_b = {};  // b "exact" against the exact image
  std::string run_a = {}, run_b = {};              // plan ids (b "exact")
  bool biased = false;                             // a side is a negative control: expected to fail
  std::uint32_t seeds = 0;
  std::uint32_t tests = 0;                  // T tile×channel tests per comparison
  std::vector<double> min_p_adjusted = {};  // per seed, in seed order
  std::uint64_t false_alarms = 0;           // seeds with min_p_adjusted <= test_alpha
  double expected_false_alarms = 0.0;       // seeds × test_alpha: what Holm allows at most
  double false_alarm_rate = 0.0;
  double wilson_low = 0.0, wilson_high = 1.0;  // 95% Wilson interval of the rate
  double binomial_p_value = 1.0;               // two-sided, against Binomial(seeds, test_alpha)
  double binomial_upper_p_value = 1.0;         // P(X >= false_alarms): the pass criterion
  // The fixed tile×channel test whose raw p-values across seeds are KS-tested.
  std::uint32_t fixed_tile_x = 0, fixed_tile_y = 0, fixed_channel = 0;
  std::vector<double> fixed_tile_p_values = {};  // per seed
  KsResult fixed_tile_ks = {};
  // Median over seeds of the comparison's worst bright-tile relative MDB (what it can see).
  double median_bright_relative_mdb = 0.0;
  bool pass = false;
};

// Detections at one k.
struct TilePowerPoint {
  double multiplier = 0.0;  // k
  // (a) k × each seed's own reported MDB of its brightest tile.
  std::uint32_t detections = 0;       // the comparison rejected
  std::uint32_t tile_detections = 0;  // the injected tile's own raw p <= α / T
  double detection_rate = 0.0;
  double wilson_low = 0.0, wilson_high = 1.0;  // of detection_rate, 95%
  double tile_detection_rate = 0.0;
  double tile_wilson_low = 0.0, tile_wilson_high = 1.0;
  double predicted_power = 0.0;  // mean over seeds of shifted_t_power(k m, ν, α / T)
  // (b) the fixed bias δ_k = k × median MDB in every seed.
  double fixed_bias = 0.0;
  std::uint32_t fixed_detections = 0;
  std::uint32_t fixed_tile_detections = 0;
  double fixed_detection_rate = 0.0;
  double fixed_wilson_low = 0.0, fixed_wilson_high = 1.0;
  double fixed_tile_detection_rate = 0.0;
  double fixed_tile_wilson_low = 0.0, fixed_tile_wilson_high = 1.0;
  double fixed_predicted_power = 0.0;  // noncentral t: δ_k / rms_stderr, median dof, α / T
};

// Which tile×channel test took the bias, and in how many seeds.
struct InjectedTile {
  std::uint32_t tile_x = 0, tile_y = 0, channel = 0;
  std::uint32_t seeds = 0;
};

struct TilePowerCurve {
  std::string scene = {};
  std::uint32_t width = 0, height = 0;
  std::string estimator_a = {}, estimator_b = {};  // the bias goes into a's images
  std::string run_a = {}, run_b = {};
  // Which tile×channel test takes the bias in each seed: "brightest" (brightest_tile, the
  // session's self-check rule, chosen on the very sample tested) or "centre" (the tile holding
  // the image centre, green: chosen before any sample is seen).
  std::string tile_rule = {};
  std::uint32_t seeds = 0;
  std::uint32_t tests = 0;
  double share = 0.0;       // α / T: the tile threshold the MDB is computed at
  double median_mdb = 0.0;  // over seeds, of the injected tile
  double rms_stderr = 0.0;  // of the injected tile's difference, sqrt of the mean of se²
  double median_dof = 0.0;  // of the injected tile's Welch test
  // Mean over seeds of the injected tile's statistic before the bias: 0 in expectation for a
  // tile chosen without looking at the sample; positive when choosing the largest mean of a
  // favours tiles whose noise in a happened to be positive (then the bias is found more often
  // than the prediction, which assumes the unbiased statistic is Student's t).
  double mean_statistic = 0.0;
  double median_relative_mdb = 0.0;               // median of MDB / the injected tile's mean
  std::vector<InjectedTile> injected_tiles = {};  // most seeds first
  std::vector<TilePowerPoint> points = {};
};

struct TileCalibrationResult {
  TileCalibrationOptions options = {};
  std::vector<TileSizeRow> rows = {};  // per scene in order: exact rows, then pairs
  std::vector<TilePowerCurve> power = {};
  bool pass = false;  // every row passes
  double wall_seconds = 0.0;
};

// Whether `integrand` names a scene (built-in or a scene file), so that `pcbench calibrate`
// calibrates the tile test on it. Throws InputError for an unknown name.
bool is_scene_name(const std::string& integrand);

// Runs the tile calibration. Throws InputError for bad options (unknown names, an analytic
// integrand, a compared scene with fewer than 2 estimators or one that cannot sample every path,
// fewer than 2 replicates or seeds, a non-finite or non-positive k), CalibrationInterrupted on
// Ctrl-C, and std::runtime_error if a run fails.
TileCalibrationResult calibrate_tiles(const TileCalibrationOptions& options);

// The report's optional top-level `tile_calibration` ($defs/tileCalibration in
// results/report.schema.json).
nlohmann::ordered_json tile_calibration_json(const TileCalibrationResult& result);

// The size table, then each power curve.
void print_tile_calibration(const TileCalibrationResult& result, std::ostream& out);

// `pcbench calibrate` on scenes: runs calibrate_tiles(), prints it, writes a report whose
// `tile_calibration` holds it. Exit 0 when every size row passes, 1 when one does not.
int run_tile_calibration(const TileCalibrationOptions& options, const SessionOptions& session,
                         std::ostream& out, std::ostream& err);

}  // namespace pcbench
