#include "harness/commands/verify_command.h"

#include <fmt/format.h>

#include <CLI/CLI.hpp>
#include <optional>
#include <variant>

#include "base/comma_list.h"
#include "base/errors.h"
#include "harness/run/replicate_farm.h"

namespace pcbench {
namespace {

// verify --images SET: the block tests on a set of image files.
struct ImageSetCheck {
  ImageSetRequest request;
  SessionOptions session;
};
// verify --estimates FILE: the run test on a file of estimates.
struct EstimatesCheck {
  ExternalRequest request;
  SessionOptions session;
};
using VerifyForm = std::variant<ImageSetCheck, EstimatesCheck, RunForm>;

// --images and --against as the files they name.
struct FileLists {
  std::string images;                  // comma-separated, or empty
  std::optional<std::string> against;  // comma-separated
};

// --images and --against as the one set each names: several words (a glob the shell expanded)
// become a comma-separated list. --against with --estimates takes one file.
FileLists gather_file_lists(const VerifyArguments& args) {
  FileLists lists{.images = join_names(args.image_files, ","), .against = std::nullopt};
  if (args.against_files.empty()) return lists;
  if (args.against_files.size() > 1 && args.image_files.empty()) {
    throw InputError(fmt::format(
        "command line: --against takes one file of estimates, not {} ({}); several files are "
        "an image set, which goes with --images",
        args.against_files.size(), join_names(args.against_files, " ")));
  }
  lists.against = join_names(args.against_files, ",");
  return lists;
}

ImageSetCheck image_set_check(const VerifyArguments& args, const FileLists& files,
                              const CommandContext& context) {
  const RunArguments& run = args.run;
  const bool selection = !run.estimators.empty() || !run.integrands.empty() ||
                         !run.params.empty() || !run.suite_path.empty() || run.exact ||
                         !args.external.estimates.empty() || args.external.reference ||
                         args.external.run_id;
  if (selection || run.resume) {
    throw InputError(
        "command line: --images verifies a set of image files; it takes no suite, --estimator, "
        "--integrand, --param, --exact, --estimates, --reference, --run-id or --resume");
  }
  ImageSetRequest request = args.images;
  request.images = files.images;
  request.against = files.against;
  request.paired = run.paired;
  if (!args.crop.empty()) request.read.crop = parse_crop(args.crop);
  // Only checked: the input files are read after this, and bad input must leave no folder.
  // The folder is made when the report and images are written (write_file_atomically).
  check_out_dir(run.out_dir, context.app.count("--out") > 0);
  return {.request = std::move(request), .session = run_session_options(run, context)};
}

// The options of --images, refused without it.
void check_no_image_options(const VerifyArguments& args) {
  const ImageSetRequest& images = args.images;
  const bool image_options = images.reference_image || images.reference_stderr || images.constant ||
                             !args.crop.empty() ||
                             images.read.channels != ImageReadOptions{}.channels ||
                             images.tile != ImageSetRequest{}.tile ||
                             images.expect != ImageSetRequest{}.expect || images.fail_underpowered;
  if (image_options) {
    throw InputError(
        "command line: --reference-image, --reference-stderr, --constant, --channels, --crop, "
        "--tile, --expect and --fail-underpowered go with --images SET");
  }
}

EstimatesCheck estimates_check(const VerifyArguments& args, const FileLists& files,
                               const CommandContext& context) {
  const RunArguments& run = args.run;
  const bool selection = !run.estimators.empty() || !run.integrands.empty() ||
                         !run.params.empty() || !run.suite_path.empty() || run.exact;
  if (selection) {
    throw InputError(
        "command line: --estimates verifies a file of estimates; it takes no suite, "
        "--estimator, --integrand, --param or --exact");
  }
  check_out_dir(run.out_dir, context.app.count("--out") > 0);  // as for --images
  ExternalRequest request = args.external;
  request.against = files.against;
  return {.request = std::move(request), .session = run_session_options(run, context)};
}

// The form the arguments ask for, checked.
VerifyForm parse_verify_form(const VerifyArguments& args, const CommandContext& context) {
  const FileLists files = gather_file_lists(args);
  const RunArguments& run = args.run;
  const bool estimates = !args.external.estimates.empty();
  if (run.resume && (run.exact || estimates)) {
    throw InputError(
        "command line: --resume continues an interrupted run or verify of a suite or selection; "
        "it takes no --exact or --estimates (they are not saved as they go)");
  }
  // Other ranks of an MPI job take no part in verifying files (harness/run/replicate_farm.h).
  if (this_rank() != 0 && (!files.images.empty() || estimates)) return RunForm{IdleRank{}};
  if (!files.images.empty()) return image_set_check(args, files, context);
  check_no_image_options(args);
  if (estimates) return estimates_check(args, files, context);
  check_resume_has_out(run, context.app);
  if (args.external.reference || files.against || args.external.run_id) {
    throw InputError("command line: --reference, --against and --run-id go with --estimates FILE");
  }
  return plan_run_form(run, context);
}

int execute(const ImageSetCheck& form, const CommandContext& context) {
  return run_image_set_verification(form.request, form.session, context.out, context.err);
}

int execute(const EstimatesCheck& form, const CommandContext& context) {
  return run_external_verification(form.request, form.session, context.out, context.err);
}

int execute(const RunForm& form, const CommandContext& context) {
  return run_form(form, context);
}

// --images and the options that go with it.
void add_image_options(CLI::App* verify, VerifyArguments& args) {
  verify
      ->add_option("--images", args.image_files,
                   "replicate images from any renderer (EXR, HDR or PFM), one seed per image: "
                   "files (several, as an unquoted glob expands), a folder, a quoted glob or a "
                   "comma-separated list")
      ->take_all();
  verify->add_option("--reference-image", args.images.reference_image,
                     "with --images: a converged reference image");
  verify->add_option("--reference-stderr", args.images.reference_stderr,
                     "with --reference-image: its per-pixel standard error image");
  verify->add_option("--constant", args.images.constant,
                     "with --images: an exact constant image, V or R,G,B (a furnace)");
  verify
      ->add_option("--channels", args.images.read.channels,
                   "with --images: the three channels to test (default R,G,B)")
      ->delimiter(',')
      ->expected(3);
  verify->add_option("--crop", args.crop, "with --images: the window X,Y,W,H to test");
  verify->add_option("--tile", args.images.tile, "with --images: tile edge in pixels (default 8)");
  verify->add_option("--expect", args.images.expect,
                     "with --images: consistent (default) or biased (a set with a known bias)");
  verify->add_flag("--fail-underpowered", args.images.fail_underpowered,
                   "with --images: exit 4 when the verdict is consistent but some scale misses "
                   "its power requirement (--require-mdb)");
}

}  // namespace

CLI::App* add_verify_command(CLI::App& app, VerifyArguments& args) {
  args.run.verify = true;
  CLI::App* verify = app.add_subcommand(
      "verify",
      "test E[estimate] = reference as one family (a negative control alone runs on its "
      "declared integrand)");
  add_run_options(verify, args.run);
  verify->add_option("--alpha", args.run.alpha, "family-wise false-alarm rate (default 0.01)")
      ->check(alpha_check());
  verify->add_flag("--exact", args.run.exact,
                   "enumerate the resampling step exactly (M <= 6, K <= 3) instead of sampling");
  verify->add_option("--estimates", args.external.estimates,
                     "replicate estimates from any renderer (.csv, .txt, .json or a report)");
  verify->add_option("--run-id", args.external.run_id,
                     "the run to take from a pcbench report given to --estimates");
  verify->add_option("--reference", args.external.reference,
                     "with --estimates: the value to test against, V or V±U (also V+-U)");
  verify
      ->add_option("--against", args.against_files,
                   "with --estimates: a second estimates file, tested two-sample (Welch); with "
                   "--images: a second independent image set, tested block by block (as --images)")
      ->take_all();
  add_image_options(verify, args);
  return verify;
}

int verify_command(const VerifyArguments& args, const CommandContext& context) {
  return std::visit([&](const auto& form) { return execute(form, context); },
                    parse_verify_form(args, context));
}

}  // namespace pcbench
