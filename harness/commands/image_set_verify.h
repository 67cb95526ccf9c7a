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

#include "harness/plan/image_set.h"
#include "harness/session/session.h"

namespace pcbench {

// Reads, tests, writes the report and prints the verdict. Bad input throws InputError before
// anything is written. Exit 0 when the comparison comes out as expected and the self-check is
// flagged, 1 otherwise.
int run_image_set_verification(const ImageSetRequest& request, const SessionOptions& options,
                               std::ostream& out, std::ostream& err);

}  // namespace pcbench
