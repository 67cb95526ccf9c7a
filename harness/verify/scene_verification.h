// Verification of scene runs: block pyramids (from 8×8 tiles to the whole image) between every
// pair of estimators on the same scene (Welch on the replicates' block means, or the paired t on
// their differences where the runs share random streams: harness/plan/plan.h, paired_streams), and
// against the exact image where the scene has one (a furnace), checks that each scale flags a
// bias of twice its reported detectable size, and the image section of each run (EXR files,
// RMSE and relative MSE, equal-time relative MSE).
#pragma once

#include <filesystem>
#include <ostream>
#include <utility>
#include <vector>

#include "harness/plan/scale_requirements.h"
#include "harness/verify/image_statistics.h"
#include "harness/verify/reference_cache.h"
#include "harness/verify/report_compare.h"
#include "harness/verify/run_record.h"
#include "harness/verify/statistics.h"

namespace pcbench {

// The block pyramids (harness/verify/block_pyramid.h) of a session's scene runs, as comparisons
// for the session's family, which holds them and `other_tested` tested verdicts more and is
// decided at `alpha`: every detectable bias (and so the self-checks' injections, one per scale of
// each scene) is computed at the threshold that family applies (PyramidOptions::family_size),
// and each scale's is held to `requirements`.
std::vector<std::pair<Comparison, Verdict>> scene_block_comparisons(
    const std::vector<RunRecord>& records, double alpha, std::size_t other_tested,
    const ScaleRequirements& requirements);

// Writes each scene run's EXR files under folder/images/ (with its strategy images where the run
// gathered them: harness/verify/strategy_image_file.h) and fills its `image` section. Its errors
// are measured against the exact image, else the cache's converged image of the scene (when `cache`
// is given and holds one; unreadable entries are reported on `warn`), else the best-converged
// other honest run of the session. With `replicate_images`, each replicate image is written too
// (images/<id>_rep<k>.exr), named in files.replicates.
void write_scene_images(std::vector<RunRecord>& records, const std::filesystem::path& folder,
                        const ReferenceCache* cache, bool replicate_images, std::ostream& warn);

}  // namespace pcbench
