// Verification of scene runs: per 8×8 tile two-sample tests between every pair of independent
// estimators on the same scene (Welch on the replicates' tile means, Holm over tiles and
// channels), tile tests against the exact image where the scene has one (a furnace), a check
// that the tile test flags a bias of twice its reported detectable size, and the image section
// of each run (EXR files, RMSE and relative MSE, equal-time relative MSE).
#pragma once

#include <filesystem>
#include <ostream>
#include <utility>
#include <vector>

#include "harness/verify/image_statistics.h"
#include "harness/verify/reference_cache.h"
#include "harness/verify/report_compare.h"
#include "harness/verify/run_record.h"
#include "harness/verify/statistics.h"

namespace pcbench {

// A tile test's verdict for the session's family: its p-value is the smallest Holm-adjusted tile
// p (decide_family adjusts it again), its reason gives the tests, the detectable tile bias and
// the samples factor for the power requirement.
Verdict tile_verdict(const TileTestResult& t, std::string expect);

// The comparison entry of a tile test of a (run or image set id) against b ("exact", a run id,
// a set); `label` reads "E_a vs E_b".
Comparison tile_comparison(const TileTestResult& t, std::string a, std::string b, std::string label,
                           std::string integrand, std::size_t replicates_a, std::string expect);

// The tile tests of a session's scene runs, as comparisons for the session's family, which holds
// them and `other_tested` tested verdicts more and is decided at `alpha`: every detectable bias
// (and so the self-check's injection) is computed at the threshold that family applies
// (TileOptions::family_size).
std::vector<std::pair<Comparison, Verdict>> scene_tile_comparisons(
    const std::vector<RunRecord>& records, double alpha, std::size_t other_tested);

// Writes each scene run's EXR files under folder/images/ (with its strategy images where the run
// gathered them: harness/verify/strategy_image_file.h) and fills its `image` section. Its errors
// are measured against the exact image, else the cache's converged image of the scene (when `cache`
// is given and holds one; unreadable entries are reported on `warn`), else the best-converged
// other honest run of the session. With `replicate_images`, each replicate image is written too
// (images/<id>_rep<k>.exr), named in files.replicates.
void write_scene_images(std::vector<RunRecord>& records, const std::filesystem::path& folder,
                        const ReferenceCache* cache, bool replicate_images, std::ostream& warn);

}  // namespace pcbench
