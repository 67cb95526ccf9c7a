#include "harness/verify/block_verdicts.h"

#include <fmt/format.h>
#include <fmt/ranges.h>

#include <algorithm>
#include <cmath>
#include <map>
#include <utility>

#include "harness/verify/block_checks.h"

namespace pcbench {
namespace {

// The requirement of scale s of t.
std::optional<double> requirement(const PyramidResult& t, std::size_t s,
                                  const ScaleRequirements& requirements) {
  return requirements.at(t.scales[s].block, s == 0, s + 1 == t.scales.size());
}

std::string scale_label(std::uint32_t block, bool whole) {
  return whole ? fmt::format("{} px (the whole image)", block) : fmt::format("{} px", block);
}

}  // namespace

std::string requirement_status(double relative_mdb, double required) {
  if (std::isnan(relative_mdb)) return "unknown (a bright block's detectable bias is undefined)";
  if (relative_mdb <= required) return "met";
  return fmt::format("not met; needs {:.3g}× the samples per pixel",
                     samples_factor(relative_mdb, required));
}

Verdict pyramid_verdict(const PyramidResult& t, const ScaleRequirements& requirements,
                        std::string expect) {
  Verdict v;
  v.test = kBlockPyramidTest;
  v.p_value = t.min_p_adjusted;
  v.tested = true;
  v.expect = std::move(expect);
  std::size_t smallest = 0;
  std::vector<std::string> powers;
  for (std::size_t s = 0; s < t.scales.size(); ++s) {
    const ScaleTests& scale = t.scales[s];
    if (scale.min_p_adjusted < t.scales[smallest].min_p_adjusted) smallest = s;
    std::string power = fmt::format("{} ≤ {:.3g}% (worst bright block; median {:.3g}%)",
                                    scale_label(scale.block, s + 1 == t.scales.size()),
                                    100.0 * scale.worst_bright_relative_mdb,
                                    100.0 * scale.median_bright_relative_mdb);
    if (const std::optional<double> required = requirement(t, s, requirements)) {
      power += fmt::format(" (required ≤ {:.3g}%: {})", 100.0 * *required,
                           requirement_status(scale.worst_bright_relative_mdb, *required));
    }
    powers.push_back(std::move(power));
  }
  v.reason = fmt::format(
      "{} block×channel tests{} at {} scales, smallest adjusted p {:.3g} at {} px; detectable bias "
      "on bright blocks at the family's threshold: {}",
      t.tests, t.paired ? " (paired: on the differences of replicates with shared streams)" : "",
      t.scales.size(), t.min_p_adjusted, t.scales[smallest].block, fmt::join(powers, ", "));
  return v;
}

Comparison pyramid_comparison(const PyramidResult& t, const ScaleRequirements& requirements,
                              std::string a, std::string b, std::string label,
                              std::string integrand, std::size_t replicates_a, std::string expect) {
  Comparison c;
  c.a = std::move(a);
  c.b = std::move(b);
  c.test = kBlockPyramidTest;
  c.estimator = std::move(label);
  c.integrand = std::move(integrand);
  c.p_value = t.min_p_adjusted;
  c.expect = std::move(expect);
  c.replicates_a = replicates_a;
  c.paired = t.paired;
  for (std::size_t s = 0; s < t.scales.size(); ++s) {
    const ScaleTests& scale = t.scales[s];
    c.scales.push_back({.block = scale.block,
                        .columns = scale.columns,
                        .rows = scale.rows,
                        .tests = static_cast<std::uint32_t>(scale.tests.size()),
                        .bright_tests = scale.bright_tests,
                        .relative_mdb = scale.worst_bright_relative_mdb,
                        .median_relative_mdb = scale.median_bright_relative_mdb,
                        .alpha_share = scale.detection_share,
                        .min_p_adjusted = scale.min_p_adjusted,
                        .required_mdb = requirement(t, s, requirements)});
    for (const BlockTest& block : scale.tests) {
      c.block_p_values.push_back(
          {static_cast<std::uint32_t>(s), block.x, block.y, block.channel, block.p_adjusted});
    }
  }
  return c;
}

std::string BlockSelfCheck::label() const {
  return fmt::format(" (block {} px {},{} channel {} + 2×MDB = {:.3g})", block, where.x, where.y,
                     where.channel, bias);
}

std::vector<BlockSelfCheck> pyramid_self_checks(
    const PyramidResult& t, const std::vector<Image>& images,
    const std::function<PyramidResult(const std::vector<Image>&)>& retest) {
  std::vector<BlockSelfCheck> out;
  for (const ScaleTests& scale : t.scales) {
    BlockSelfCheck check{.block = scale.block, .where = brightest_block(scale)};
    check.bias = 2.0 * check.where.min_detectable_bias;
    check.result = retest(with_block_bias(images, check.where, scale.block, check.bias));
    out.push_back(std::move(check));
  }
  return out;
}

void finish_comparison(Comparison& c, const Verdict& v) {
  c.p_adjusted = v.p_adjusted;
  c.alpha = v.alpha;
  c.result = v.result;
  c.reason = v.reason;
  c.min_detectable_difference = v.min_detectable_bias;
  if (c.scales.empty() || c.result != "biased") return;
  std::vector<std::size_t> differing(c.scales.size(), 0);
  for (const Comparison::BlockP& b : blocks_differing(c)) ++differing[b.scale];
  for (std::size_t s = c.scales.size(); s-- > 0;) {
    if (differing[s] == 0) continue;
    const Comparison::Scale& scale = c.scales[s];
    c.reason = fmt::format("coarsest scale that differs: {}, {} of {} block×channel tests; {}",
                           scale_label(scale.block, s + 1 == c.scales.size()), differing[s],
                           scale.tests, c.reason);
    return;
  }
}

std::vector<std::string> scene_power_lines(const std::vector<Comparison>& comparisons) {
  // Per integrand in report order: per scale, the worst relative MDB and its requirement.
  std::vector<std::string> order;
  std::map<std::string, std::vector<Comparison::Scale>> worst;
  for (const Comparison& c : comparisons) {
    if (c.scales.empty() || c.expect != "consistent" || c.a.ends_with("+injected")) continue;
    auto [it, inserted] = worst.try_emplace(c.integrand, c.scales);
    if (inserted) {
      order.push_back(c.integrand);
      continue;
    }
    // NaN sticks: an unknown power must not read as enough.
    const auto worse = [](double& mdb, double other) {
      mdb = std::isnan(mdb) || std::isnan(other) ? other + mdb : std::max(mdb, other);
    };
    for (std::size_t s = 0; s < std::min(it->second.size(), c.scales.size()); ++s) {
      worse(it->second[s].relative_mdb, c.scales[s].relative_mdb);
      worse(it->second[s].median_relative_mdb, c.scales[s].median_relative_mdb);
    }
  }
  std::vector<std::string> lines;
  for (const std::string& integrand : order) {
    const std::vector<Comparison::Scale>& scales = worst.at(integrand);
    std::vector<std::string> parts;
    bool met = true;
    for (std::size_t s = 0; s < scales.size(); ++s) {
      const Comparison::Scale& scale = scales[s];
      std::string part = fmt::format("{} ≤ {:.3g}% (median {:.3g}%)",
                                     scale_label(scale.block, s + 1 == scales.size()),
                                     100.0 * scale.relative_mdb, 100.0 * scale.median_relative_mdb);
      if (scale.required_mdb) {
        met = met && scale.relative_mdb <= *scale.required_mdb;
        part += fmt::format(" (required ≤ {:.3g}%: {})", 100.0 * *scale.required_mdb,
                            requirement_status(scale.relative_mdb, *scale.required_mdb));
      }
      parts.push_back(std::move(part));
    }
    lines.push_back(fmt::format("power on {}: {}; {}", integrand, fmt::join(parts, ", "),
                                met ? "every requirement met" : "some requirement missed"));
  }
  return lines;
}

}  // namespace pcbench
