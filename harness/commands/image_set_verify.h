// `pcbench verify --images SET`: the scene tile tests on replicate images from any renderer.
//
// SET holds R >= 2 independent renders of one scene (harness/plan/image_set.h). They are tested per
// tile, as pcbench's own scene runs are (harness/verify/image_statistics.h), against exactly one of
//   --against SET2                  another independent set: Welch per tile;
//   --reference-image F [--reference-stderr F2]
//                                   a converged image, with its own per-pixel standard error
//                                   (without one it is taken as exact, which the report says);
//   --constant V | R,G,B            an exact constant image (a furnace).
// The family is the comparison and its self-check (twice the reported detectable bias put into
// the brightest tile of SET, expected flagged), Holm at --alpha; the detectable bias is stated at
// the per-tile share that decides. The report holds both in `comparisons` and the inputs in
// `image_sets`; the mean, standard error and z map of SET are written as EXR beside it.
#pragma once

#include <iosfwd>
#include <nlohmann/json.hpp>
#include <vector>

#include "harness/plan/image_set.h"
#include "harness/session/session.h"
#include "harness/verify/report_compare.h"
#include "results/image.h"

namespace pcbench {

// The request's own checks, before any file is read: exactly one thing to test against, a tile
// of at least 1 pixel that --require-mdb's scales allow, --expect consistent or biased. Throws
// InputError.
void check_image_set_request(const ImageSetRequest& request, const SessionOptions& options);

// A set tested: the comparison and its self-checks (the comparison first), the report's
// `image_sets` (its `image_files` null until publish_image_set_verification writes them), and
// the set's mean, standard error and z map.
struct ImageSetVerification {
  std::vector<Comparison> comparisons;
  nlohmann::ordered_json image_sets;
  Image mean, standard_error, z;
};

struct ReportSections;  // harness/session/report.h

// The report's sections of a verification: its comparisons and image_sets.
ReportSections image_set_sections(const ImageSetVerification& verification);

// The family's tests on an input already read and checked (read_image_set_input, from files or
// from memory: the CLI and the Python module call this alike). Writes nothing.
ImageSetVerification verify_image_set(const ImageSetRequest& request, const ImageSetInput& input,
                                      const SessionOptions& options);

// Writes the mean, standard error and z map as EXR and the report into report_folder(options),
// prints each comparison's verdict on `out`; the exit status (below).
int publish_image_set_verification(ImageSetVerification verification, const SessionOptions& options,
                                   std::ostream& out, std::ostream& err);

// Whether every comparison (the comparison and its self-checks) came out as expected.
bool comparisons_as_expected(const std::vector<Comparison>& comparisons);

// Reads, tests, writes the report and prints the verdict. Bad input throws InputError before
// anything is written. Exit 0 when the comparison comes out as expected and the self-check is
// flagged, 1 otherwise.
int run_image_set_verification(const ImageSetRequest& request, const SessionOptions& options,
                               std::ostream& out, std::ostream& err);

}  // namespace pcbench
