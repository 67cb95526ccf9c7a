// A block pyramid's verdict for a family of tests, its report entry and its self-checks: what a
// session's scene runs (harness/verify/scene_verification.h) and `verify --images`
// (harness/commands/image_set_verify.h) share.
#pragma once

#include <cstddef>
#include <cstdint>
#include <functional>
#include <string>
#include <vector>

#include "harness/plan/scale_requirements.h"
#include "harness/verify/block_pyramid.h"
#include "harness/verify/report_compare.h"
#include "harness/verify/statistics.h"
#include "results/image.h"

namespace pcbench {

// A pyramid's verdict for the session's family: its p-value is the pyramid's smallest adjusted
// p (decide_family adjusts it again); its reason gives the tests and, per scale, the detectable
// bias and the requirement with the samples factor that would meet it.
Verdict pyramid_verdict(const PyramidResult& t, const ScaleRequirements& requirements,
                        std::string expect);

// Whether a scale's detectable bias meets its requirement, in words: "met", "not met; needs
// 1.09× the samples per pixel" (samples_factor), or "unknown" for a NaN detectable bias.
std::string requirement_status(double relative_mdb, double required);

// The comparison entry of a pyramid of a (run or image set id) against b ("exact", a run id, a
// set); `label` reads "E_a vs E_b".
Comparison pyramid_comparison(const PyramidResult& t, const ScaleRequirements& requirements,
                              std::string a, std::string b, std::string label,
                              std::string integrand, std::size_t replicates_a, std::string expect);

// The verifier's own check at one scale: a bias of twice the reported detectable size (at the
// family's threshold) put into the brightest block of that scale of one side's images, and the
// pyramid tested again; expected flagged.
struct BlockSelfCheck {
  std::uint32_t block = 0;  // edge in pixels of the scale checked
  BlockTest where = {};
  double bias = 0.0;
  PyramidResult result = {};
  // " (block 32 px 1,2 channel 1 + 2×MDB = 0.0123)", for the comparison's label.
  std::string label() const;
};

// One self-check per scale of `t` (so as many verdicts as t has scales), each retested by
// `retest` on `images` with the bias added.
std::vector<BlockSelfCheck> pyramid_self_checks(
    const PyramidResult& t, const std::vector<Image>& images,
    const std::function<PyramidResult(const std::vector<Image>&)>& retest);

// Copies the family's decision (v, after decide_family) into the comparison; where it differs,
// the reason names the coarsest scale at which some block differs.
void finish_comparison(Comparison& c, const Verdict& v);

// Per scene (integrand), the power its honest block comparisons reached at each scale: the
// largest relative detectable bias over them and whether the requirement holds, one line each,
// for the session's summary ("power on cornell: 8 px ≤ 23% (required ≤ 5%: missed, 21× the
// samples per pixel), ..."). Self-checks and comparisons expected biased are left out.
std::vector<std::string> scene_power_lines(const std::vector<Comparison>& comparisons);

}  // namespace pcbench
