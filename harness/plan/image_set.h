// Sets of replicate images from any renderer, read for `pcbench verify --images`: OpenEXR,
// Radiance HDR (RGBE) and PFM through OpenImageIO; and the whole input of that command (the set
// and what it is tested against), read and checked. The tests are the command's
// (harness/commands/image_set_verify.h).
//
// A set is R >= 2 independent renders of one scene (one seed each). Everything that would make
// the tile tests meaningless is bad input here, before anything is written: unreadable or
// truncated files, another format, images of different sizes, a missing channel, the same
// replicate twice (identical pixels: a seed reused, or a file copied). Non-finite and negative
// pixels are not bad input: they are counted per file and located, and kept, so that the tile
// holding a NaN fails its test as in pcbench's own verification.
#pragma once

#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "results/image.h"

namespace pcbench {

// A window of the image to test: x, y of its top-left pixel, width, height.
struct CropWindow {
  std::uint32_t x = 0, y = 0, width = 0, height = 0;
};

struct ImageReadOptions {
  // The three channels of the file to test, in the order they fill R, G, B (a grey image:
  // "Y,Y,Y" tests its one channel three times, which only costs power).
  std::vector<std::string> channels = {"R", "G", "B"};
  std::optional<CropWindow> crop = {};
};

// What one file held beyond its pixels.
struct ImageFileFacts {
  std::string path = {};
  std::string format = {};      // OpenImageIO's name: openexr, hdr, pfm
  std::string pixel_type = {};  // as stored: half, float, rgbe (8-bit shared exponent)
  std::uint64_t nonfinite = 0;  // NaN or ±inf values over the tested channels
  std::optional<std::uint32_t> first_nonfinite_x = {}, first_nonfinite_y = {};
  std::uint64_t negative = 0;  // values below 0 (a filter with negative lobes makes them)
};

// The worst relative rounding of one stored value, by pixel type: half's 11 significant bits
// round to within 2^-11; RGBE's 8-bit mantissa of the largest channel is truncated by the
// common encoders, so one value may lose up to one step, 2^-7 of itself at mantissa 128; float
// rounds to within 2^-24. A tile mean inherits at most the same relative bias from it.
double worst_quantisation_bias(const std::string& pixel_type);

struct ImageSet {
  std::vector<Image> images;
  std::vector<ImageFileFacts> files;
  // The largest worst_quantisation_bias over the files.
  double quantisation_bias = 0.0;
};

// The files of SET: a folder (its .exr, .hdr and .pfm files, sorted by name), a glob pattern
// (sorted matches), or a comma-separated list. Throws InputError naming `option` when nothing
// matches, and for a folder that holds more than one set's replicates: pcbench's statistics
// images (`<id>_mean.exr`, `_stderr`, `_zmap`, `_reference`, `_strategies`, `images_*.exr`,
// `reference_*.exr`, named) or the replicates `<id>_rep<k>` of several runs.
std::vector<std::string> image_set_files(const std::string& set, const std::string& option);

// One image: the chosen channels, cropped. Throws InputError (file, what is wrong, the valid
// choices) for a file that cannot be read, a format other than the three, or a missing channel.
Image read_image_file(const std::string& path, const ImageReadOptions& options,
                      ImageFileFacts* facts = nullptr);

// A set of at least `min_images` images of one size; throws InputError as above, and for fewer
// images, different sizes, or two files with identical pixels (named both).
ImageSet read_image_set(const std::string& set, const std::string& option,
                        const ImageReadOptions& options, std::size_t min_images = 2);

// The facts of an image's values into `facts`: its non-finite values (the first located, x and y
// in the image) and its negative values.
void count_values(const Image& image, ImageFileFacts& facts);

// A set of images already in memory (the Python module's arrays), one ImageFileFacts each (its
// path names the image), checked as read_image_set checks files; `set` names it in messages.
ImageSet image_set_of(std::vector<Image> images, std::vector<ImageFileFacts> facts,
                      const std::string& option, const std::string& set,
                      std::size_t min_images = 2);

// `verify --images` as asked.
struct ImageSetRequest {
  std::string images;                                // --images SET
  std::optional<std::string> against = {};           // --against SET2
  std::optional<std::string> reference_image = {};   // --reference-image FILE
  std::optional<std::string> reference_stderr = {};  // --reference-stderr FILE
  std::optional<std::string> constant = {};          // --constant V or R,G,B
  ImageReadOptions read = {};                        // --channels, --crop
  std::uint32_t tile = 8;                            // --tile
  std::string expect = "consistent";                 // --expect
  // --paired (with --against): replicate k of both sets comes from the same random streams, so
  // each block is tested on the replicate differences (harness/verify/block_pyramid.h).
  bool paired = false;
  // --fail-underpowered: a consistent verdict whose scales miss a power requirement exits 4.
  bool fail_underpowered = false;
};

// Parses --crop X,Y,W,H. Throws InputError.
CropWindow parse_crop(const std::string& text);

// The set and what it is tested against, read and checked.
struct ImageSetInput {
  ImageSet set;
  std::optional<ImageSet> other = {};  // --against
  // --reference-image with its --reference-stderr, or --constant's image.
  std::optional<Image> reference = {}, reference_stderr = {};
  std::string reference_pixel_type = "float";
  std::vector<double> constant = {};  // --constant's values (one, or R, G, B)
  double quantisation = 0.0;  // the worst-case quantisation bias of the files' pixel formats
};

// Sides of a request that are already in memory (the Python module's arrays); the request's
// names for them label them in messages and the report.
struct ImagesInMemory {
  std::optional<ImageSet> set = {}, other = {};
  std::optional<Image> reference = {}, reference_stderr = {};
  std::string reference_pixel_type = "float";
};

// Reads `request`'s set and the one thing it is tested against (--against, --reference-image
// or --constant; the request says exactly one), all of one size; what `loaded` holds is taken
// instead of read. Throws InputError naming the file or option, and when an image of --against
// has the pixels of one of --images (the same files, or copies, on both sides).
ImageSetInput read_image_set_input(const ImageSetRequest& request, ImagesInMemory loaded = {});

}  // namespace pcbench
