#include "harness/commands/image_set_verify.h"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <limits>
#include <nlohmann/json.hpp>
#include <ostream>
#include <set>

#include "base/comma_list.h"
#include "base/errors.h"
#include "harness/session/publish.h"
#include "harness/session/report.h"
#include "harness/verify/block_pyramid.h"
#include "harness/verify/block_rounding.h"
#include "harness/verify/block_verdicts.h"
#include "harness/verify/image_statistics.h"
#include "harness/verify/report_compare.h"
#include "harness/verify/scene_verification.h"
#include "results/exr_file.h"

namespace pcbench {
namespace {

namespace fs = std::filesystem;
using Json = nlohmann::ordered_json;

Json files_json(const ImageSet& set) {
  Json files = Json::array();
  for (const ImageFileFacts& f : set.files) {
    Json entry = {{"path", f.path},
                  {"format", f.format},
                  {"pixel_type", f.pixel_type},
                  {"nonfinite", f.nonfinite},
                  {"negative", f.negative}};
    if (f.first_nonfinite_x) {
      entry["first_nonfinite"] = {{"x", *f.first_nonfinite_x}, {"y", *f.first_nonfinite_y}};
    }
    files.push_back(std::move(entry));
  }
  return files;
}

// Warns about what the files hold that is not bad input but must not pass unseen.
void warn_about_values(const ImageSet& set, std::ostream& err) {
  for (const ImageFileFacts& f : set.files) {
    if (f.nonfinite > 0) {
      err << fmt::format(
          "pcbench: warning: {}: {} NaN or infinite value(s), the first at pixel ({}, {}) of the "
          "tested window; its tile fails its test\n",
          f.path, f.nonfinite, *f.first_nonfinite_x, *f.first_nonfinite_y);
    }
    if (f.negative > 0) {
      err << fmt::format(
          "pcbench: warning: {}: {} negative value(s) (a reconstruction filter with negative "
          "lobes makes them; radiance itself is never negative)\n",
          f.path, f.negative);
    }
  }
}

// What the reference is, for the report and the comparison's b.
struct Against {
  std::string kind;  // images | reference | constant
  std::string label;
  Json json;
  std::string id;  // the comparison's b: against | reference | exact
};

// A set's rounding: its worst file's, relative to a pixel's largest channel if any file is RGBE.
SideRounding side_rounding(const Image& mean, const ImageSet& set) {
  const bool rgbe = std::any_of(set.files.begin(), set.files.end(),
                                [](const ImageFileFacts& f) { return f.pixel_type == "rgbe"; });
  return {&mean, set.quantisation_bias, rgbe};
}

// "RGBE: 2^-7 of a pixel's largest channel; half: 2^-11 of a value" for the formats involved.
std::string rounding_formats(const ImageSet& set, const ImageSet* other,
                             const std::string& reference_type) {
  std::set<std::string> types = {reference_type};
  for (const ImageSet* s : {&set, other}) {
    if (s == nullptr) continue;
    for (const ImageFileFacts& f : s->files) types.insert(f.pixel_type);
  }
  std::vector<std::string> parts;
  if (types.contains("rgbe")) parts.push_back("RGBE: 2^-7 of a pixel's largest channel");
  if (types.contains("half")) parts.push_back("half: 2^-11 of a value");
  if (parts.empty()) parts.push_back("float: 2^-24 of a value");
  return join_names(parts, "; ");
}

}  // namespace

void check_image_set_request(const ImageSetRequest& request, const SessionOptions& options) {
  const int references = static_cast<int>(request.against.has_value()) +
                         static_cast<int>(request.reference_image.has_value()) +
                         static_cast<int>(request.constant.has_value());
  if (references != 1) {
    throw InputError(
        "command line: --images needs exactly one of --against SET, --reference-image FILE and "
        "--constant V|R,G,B");
  }
  if (request.paired && !request.against) {
    throw InputError("command line: --paired with --images goes with --against SET2");
  }
  if (request.reference_stderr && !request.reference_image) {
    throw InputError("command line: --reference-stderr goes with --reference-image");
  }
  if (request.tile == 0) throw InputError("command line: --tile must be at least 1");
  options.scale_requirements.check_blocks(request.tile, "command line: --require-mdb");
  if (request.expect != "consistent" && request.expect != "biased") {
    throw InputError(
        fmt::format("command line: --expect '{}': consistent or biased", request.expect));
  }
}

namespace {

// What `input` is tested against, from the option that named it.
Against against_of(const ImageSetRequest& request, const ImageSetInput& input) {
  if (input.other) {
    return {"images",
            *request.against,
            {{"kind", "images"}, {"files", files_json(*input.other)}},
            "against"};
  }
  if (request.reference_image) {
    Against against{"reference",
                    *request.reference_image,
                    {{"kind", "reference"}, {"file", *request.reference_image}},
                    "reference"};
    against.json["stderr_file"] =
        request.reference_stderr ? Json(*request.reference_stderr) : Json(nullptr);
    return against;
  }
  return {"constant",
          "constant " + *request.constant,
          {{"kind", "constant"}, {"value", input.constant}},
          "exact"};
}

// An image's mean over its pixels and channels.
double whole_image_mean(const Image& image) {
  double sum = 0.0;
  for (const double v : image.values) sum += v;
  return sum / static_cast<double>(image.values.size());
}

std::vector<double> whole_image_means(const std::vector<Image>& images) {
  std::vector<double> means;
  for (const Image& image : images) means.push_back(whole_image_mean(image));
  return means;
}

// The comparison's whole-image figures (mean_a, mean_b, their standard errors, statistic, dof,
// replicate counts): the image's mean over pixels and channels, per replicate, tested as one
// value against the other side's (Welch), the reference's (its pixels' standard errors taken as
// independent) or the exact constant's.
void whole_image_figures(const ImageSetInput& input, Comparison& c) {
  const std::vector<double> a = whole_image_means(input.set.images);
  TwoSampleTest test;
  if (input.other) {
    const std::vector<double> b = whole_image_means(input.other->images);
    test = welch_two_sample(a, b);
    c.replicates_b = b.size();
  } else {
    const Image& reference = *input.reference;
    const double n = static_cast<double>(reference.values.size());
    double variance_b = 0.0;
    if (input.reference_stderr) {
      for (const double se : input.reference_stderr->values) variance_b += se * se;
      variance_b /= n * n;
    }
    const double n_a = static_cast<double>(a.size());
    double mean = 0.0, squares = 0.0;
    for (const double v : a) mean += v / n_a;
    for (const double v : a) squares += (v - mean) * (v - mean);
    test = welch_test(mean, squares / (n_a - 1.0) / n_a, n_a - 1.0, whole_image_mean(reference),
                      variance_b, std::numeric_limits<double>::infinity());
    c.replicates_b = 0;
  }
  set_test_figures(c, test);
}

// The family: the comparison and its self-checks, one per scale, decided together.
struct TestedFamily {
  PyramidResult result;
  std::vector<Comparison> comparisons;  // the comparison first, then the self-checks
};

TestedFamily test_family(const ImageSetInput& input, const Against& against,
                         const ImageSetRequest& request, const SessionOptions& options) {
  const Image& like = input.set.images.front();
  const std::size_t scales = pyramid_block_sizes(like.width, like.height, request.tile).size();
  const PyramidOptions blocks{.tile = request.tile,
                              .family_size = static_cast<std::uint32_t>(1 + scales),
                              .paired = request.paired};
  const auto test = [&](const std::vector<Image>& images) {
    if (input.other) return compare_blocks(images, input.other->images, options.alpha, blocks);
    if (input.reference_stderr) {
      return test_blocks_against_reference(images, *input.reference, *input.reference_stderr,
                                           options.alpha, blocks);
    }
    return test_blocks_against_exact(images, *input.reference, options.alpha, blocks);
  };
  const ScaleRequirements& requirements = options.scale_requirements;
  TestedFamily tested{.result = test(input.set.images), .comparisons = {}};
  const std::vector<BlockSelfCheck> checks =
      pyramid_self_checks(tested.result, input.set.images, test);

  const std::string label = "images vs " + against.label;
  const std::size_t count = input.set.images.size();
  std::vector<Verdict> verdicts = {pyramid_verdict(tested.result, requirements, request.expect)};
  tested.comparisons = {pyramid_comparison(tested.result, requirements, "images", against.id, label,
                                           "images", count, request.expect)};
  for (const BlockSelfCheck& check : checks) {
    verdicts.push_back(pyramid_verdict(check.result, requirements, "biased"));
    tested.comparisons.push_back(pyramid_comparison(check.result, requirements, "images+injected",
                                                    against.id, label + check.label(), "images",
                                                    count, "biased"));
  }
  std::vector<Verdict*> family;
  for (Verdict& v : verdicts) family.push_back(&v);
  decide_family(family, options.alpha);
  if (tested.result.scales.front().worst_bright_relative_mdb < input.quantisation) {
    verdicts.front().reason += fmt::format(
        "; the detectable tile bias is below the worst-case quantisation bias of the pixel "
        "format ({:.3g}%): a difference that small may be the format's rounding",
        100.0 * input.quantisation);
  }
  for (std::size_t i = 0; i < tested.comparisons.size(); ++i) {
    finish_comparison(tested.comparisons[i], verdicts[i]);
  }
  whole_image_figures(input, tested.comparisons.front());
  return tested;
}

// The set's pixel statistics and its z map against the other side.
struct PixelMaps {
  PixelStatistics stats;
  std::optional<PixelStatistics> other_stats;
  Image z;
  PixelTestSummary pixels;
};

PixelMaps pixel_maps(const ImageSetInput& input) {
  PixelMaps maps;
  maps.stats = pixel_statistics(input.set.images);
  if (input.other) maps.other_stats = pixel_statistics(input.other->images);
  maps.z = maps.other_stats ? z_map(maps.stats, *maps.other_stats)
           : input.reference_stderr
               ? z_map(maps.stats, PixelStatistics{.mean = *input.reference,
                                                   .standard_error = *input.reference_stderr,
                                                   .replicates = 0})
               : z_map(maps.stats, *input.reference);
  maps.pixels = summarize_z(
      maps.z, input.set.images,
      input.other ? std::span<const Image>(input.other->images) : std::span(&*input.reference, 1));
  return maps;
}

// Where every block that decides a difference differs by no more than the files' rounding,
// the reason says so (harness/verify/block_rounding.h).
void note_rounding(const ImageSetInput& input, const PixelMaps& maps,
                   const ImageSetRequest& request, TestedFamily& tested) {
  Comparison& comparison = tested.comparisons.front();
  if (comparison.result != "biased") return;
  const std::vector<SideRounding> sides = {
      side_rounding(maps.stats.mean, input.set),
      input.other ? side_rounding(maps.other_stats->mean, *input.other)
      : request.reference_image
          ? SideRounding{&*input.reference, worst_quantisation_bias(input.reference_pixel_type),
                         input.reference_pixel_type == "rgbe"}
          : SideRounding{}};
  const double ratio = worst_difference_over_rounding(comparison, tested.result, sides);
  if (ratio <= 1.0) {
    comparison.reason += fmt::format(
        "; every block that differs differs by at most {:.2g}× the worst-case rounding of the "
        "files' pixel format ({}): the format's rounding, not the renderer, may be what "
        "differs; write float EXR or PFM to test below it",
        ratio,
        rounding_formats(input.set, input.other ? &*input.other : nullptr,
                         input.reference_pixel_type));
  }
}

// The mean, standard error and z map as EXR files in folder/images/; their names by kind, or
// nothing when they cannot be written (said on `err`).
std::optional<Json> write_images(const fs::path& folder, const ImageSetVerification& maps,
                                 std::ostream& err) {
  Json files;
  try {
    fs::create_directories(folder / "images");
    const auto write = [&](const char* kind, const Image& image) {
      const std::string name = fmt::format("images/images_{}.exr", kind);
      write_exr_rgb(folder / name, image);
      files[kind] = name;
    };
    write("mean", maps.mean);
    write("stderr", maps.standard_error);
    write("zmap", maps.z);
  } catch (const std::exception& e) {
    err << "pcbench: error: cannot write the images of " << folder.string() << ": " << e.what()
        << "\n";
    return std::nullopt;
  }
  return files;
}

// The report's image_sets: the inputs, the pixel test and the image files.
Json image_sets_json(const ImageSetRequest& request, const ImageSetInput& input,
                     const Against& against, const PixelTestSummary& pixels, const Json& files) {
  const Image& like = input.set.images.front();
  Json crop = nullptr;
  if (request.read.crop) {
    crop = {{"x", request.read.crop->x},
            {"y", request.read.crop->y},
            {"width", request.read.crop->width},
            {"height", request.read.crop->height}};
  }
  return Json{
      {"images", request.images},
      {"files", files_json(input.set)},
      {"against", against.json},
      {"width", like.width},
      {"height", like.height},
      {"channels", request.read.channels},
      {"crop", crop},
      {"tile", request.tile},
      {"worst_quantisation_bias", input.quantisation},
      {"pixel_test",
       {{"test", "pixel-z"},
        {"statistic", std::isfinite(pixels.max_abs_z) ? Json(pixels.max_abs_z) : Json(nullptr)},
        {"pixels_beyond_4_sigma", pixels.pixels_beyond_4_sigma},
        {"expected_beyond_4_sigma_at_most", pixels.expected_beyond_4_sigma},
        {"low_count_pixels", pixels.low_count_pixels}}},
      {"image_files", files}};
}

// One printed line per comparison. A self-check's says so, in words of its own: under a
// consistent verdict its "biased" is the verifier working, not a finding.
std::string verdict_line(const Comparison& c) {
  if (c.a.ends_with("+injected")) {
    const std::string planted = c.estimator.substr(c.estimator.find(" ("));
    // Its reason's first part names the coarsest scale that differs; the power figures after it
    // are the comparison's own, printed on its line.
    return c.result == c.expect
               ? fmt::format("self-check{}: flagged, as expected ({})\n", planted,
                             c.reason.substr(0, c.reason.find(';')))
               : fmt::format(
                     "self-check{}: NOT flagged (expected flagged): the test cannot see "
                     "twice its own stated detectable bias ({})\n",
                     planted, c.reason);
  }
  return fmt::format("{}: {}{} ({})\n", c.estimator, c.result,
                     c.result == c.expect ? "" : fmt::format(" (expected {})", c.expect), c.reason);
}

// Every scale with a requirement meets it (a NaN detectable bias does not).
bool requirements_met(const Comparison& c) {
  return std::all_of(c.scales.begin(), c.scales.end(), [](const Comparison::Scale& s) {
    return !s.required_mdb || s.relative_mdb <= *s.required_mdb;
  });
}

}  // namespace

ImageSetVerification verify_image_set(const ImageSetRequest& request, const ImageSetInput& input,
                                      const SessionOptions& options) {
  const Against against = against_of(request, input);
  TestedFamily tested = test_family(input, against, request, options);
  const PixelMaps maps = pixel_maps(input);
  note_rounding(input, maps, request, tested);
  ImageSetVerification verification;
  verification.image_sets = image_sets_json(request, input, against, maps.pixels, Json(nullptr));
  verification.comparisons = std::move(tested.comparisons);
  verification.mean = maps.stats.mean;
  verification.standard_error = maps.stats.standard_error;
  verification.z = maps.z;
  return verification;
}

ReportSections image_set_sections(const ImageSetVerification& verification) {
  ReportSections sections;
  sections.comparisons = comparisons_json(verification.comparisons);
  sections.image_sets = verification.image_sets;
  return sections;
}

int publish_image_set_verification(ImageSetVerification verification, const SessionOptions& options,
                                   std::ostream& out, std::ostream& err) {
  const fs::path folder = report_folder(options);
  const std::optional<Json> files = write_images(folder, verification, err);
  if (!files) return kExitRunFailed;
  verification.image_sets["image_files"] = *files;
  for (const Comparison& c : verification.comparisons) out << verdict_line(c);
  if (!publish_report(options, folder, session_context(options), {},
                      image_set_sections(verification), out, err)) {
    return kExitRunFailed;
  }
  return comparisons_as_expected(verification.comparisons) ? kExitOk : kExitVerdictDiffers;
}

bool comparisons_as_expected(const std::vector<Comparison>& comparisons) {
  return std::all_of(comparisons.begin(), comparisons.end(),
                     [](const Comparison& c) { return c.result == c.expect; });
}

int run_image_set_verification(const ImageSetRequest& request, const SessionOptions& options,
                               std::ostream& out, std::ostream& err) {
  check_image_set_request(request, options);
  // Everything is read and checked before anything is written.
  const ImageSetInput input = read_image_set_input(request);
  ImageSetVerification verification = verify_image_set(request, input, options);
  warn_about_values(input.set, err);
  if (input.other) warn_about_values(*input.other, err);
  const Comparison comparison = verification.comparisons.front();
  const int status = publish_image_set_verification(std::move(verification), options, out, err);
  if (status != kExitOk) return status;
  if (request.fail_underpowered && comparison.expect == "consistent" &&
      !requirements_met(comparison)) {
    out << "power requirement not met (--fail-underpowered): exit 4; render more samples per "
           "pixel, as the line above says\n";
    return kExitUnderpowered;
  }
  return kExitOk;
}

}  // namespace pcbench
