#include "harness/plan/image_set.h"

#include <fmt/format.h>
#include <fmt/ranges.h>
#include <glob.h>

#include <algorithm>
#include <cctype>
#include <charconv>
#include <cmath>
#include <cstring>
#include <filesystem>
#include <map>
#include <set>
#include <string_view>

#include "base/comma_list.h"
#include "base/errors.h"
#include "base/text_hash.h"
#include "harness/plan/image_file_reader.h"

namespace pcbench {
namespace {

namespace fs = std::filesystem;

constexpr const char* kFormats = "OpenEXR (.exr), Radiance HDR (.hdr) or PFM (.pfm)";

std::string lower(std::string text) {
  std::transform(text.begin(), text.end(), text.begin(),
                 [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
  return text;
}

bool image_extension(const fs::path& path) {
  const std::string ext = lower(path.extension().string());
  return ext == ".exr" || ext == ".hdr" || ext == ".pfm";
}

// pcbench's own statistics images, which sit beside its replicates (`<id>_rep<k>.exr`) in a
// report's images/ folder: `<id>_{mean,stderr,zmap,reference,strategies}.exr`,
// `images_{mean,stderr,zmap}.exr` and `reference_<key>.exr`. None is a replicate.
bool statistics_image(const fs::path& path) {
  const std::string stem = path.stem().string();
  for (const char* kind : {"_mean", "_stderr", "_zmap", "_reference", "_strategies"}) {
    if (stem.ends_with(kind)) return true;
  }
  return stem.starts_with("reference_");
}

// The run id of a pcbench replicate file, `<id>_rep<k>`, or "" for any other name.
std::string replicate_run_id(const fs::path& path) {
  const std::string stem = path.stem().string();
  const std::size_t at = stem.rfind("_rep");
  if (at == std::string::npos || at + 4 == stem.size()) return "";
  const bool digits = std::all_of(stem.begin() + static_cast<std::ptrdiff_t>(at + 4), stem.end(),
                                  [](unsigned char c) { return std::isdigit(c) != 0; });
  return digits ? stem.substr(0, at) : "";
}

// A folder given as a set holds replicates only: pcbench's statistics images, or the
// replicates of several of its runs, beside them would be read as replicates and pass with a
// meaningless detectable bias. Refused, naming the files and the glob that takes one run's.
void check_folder_holds_replicates(const std::string& folder, const std::vector<std::string>& files,
                                   const std::string& option) {
  std::vector<std::string> others;
  std::set<std::string> runs;
  for (const std::string& file : files) {
    if (statistics_image(file)) others.push_back(fs::path(file).filename().string());
    if (const std::string id = replicate_run_id(file); !id.empty()) runs.insert(id);
  }
  if (!others.empty()) {
    throw InputError(fmt::format(
        "command line: {} '{}': the folder holds images that are not replicates ({}): a folder "
        "must hold one set's replicates only; give them as a quoted glob, e.g. '{}/*_rep*.exr'",
        option, folder, join_names(others), folder));
  }
  if (runs.size() > 1) {
    throw InputError(fmt::format(
        "command line: {} '{}': the folder holds the replicates of {} runs ({}); give one run's "
        "as a quoted glob, e.g. '{}/{}_rep*.exr'",
        option, folder, runs.size(), join_names(runs), folder, *runs.begin()));
  }
}

std::vector<std::string> glob_files(const std::string& pattern) {
  glob_t found{};
  const int status = glob(pattern.c_str(), 0, nullptr, &found);
  std::vector<std::string> files;
  if (status == 0) {
    for (std::size_t i = 0; i < found.gl_pathc; ++i) files.emplace_back(found.gl_pathv[i]);
  }
  globfree(&found);
  std::sort(files.begin(), files.end());
  return files;
}

std::string stored_type(const std::string& format, const ImageFileHeader& header, int channel) {
  if (format == "hdr") return "rgbe";
  return header.channel_formats[static_cast<std::size_t>(channel)];
}

// FNV-1a over the pixel values' bytes: equal only for identical images (up to a collision of
// 2^-64, and then the message names two files to look at).
std::uint64_t content_hash(const Image& image) {
  const std::string_view bytes(reinterpret_cast<const char*>(image.values.data()),
                               image.values.size() * sizeof(double));
  return fnv1a(kFnvOffset, bytes);
}

// A comma list of finite numbers for `option` (--crop, --constant).
std::vector<double> parse_numbers(const std::string& text, const char* option) {
  std::vector<double> values;
  for (const std::string& part : split_commas(text)) {
    double value = 0.0;
    const auto [end, error] = std::from_chars(part.data(), part.data() + part.size(), value);
    if (part.empty() || error != std::errc() || end != part.data() + part.size() ||
        !std::isfinite(value)) {
      throw InputError(
          fmt::format("command line: {} '{}': '{}' is not a finite number", option, text, part));
    }
    values.push_back(value);
  }
  return values;
}

Image constant_image(const Image& like, const std::vector<double>& v, const std::string& text) {
  if (v.size() != 1 && v.size() != kImageChannels) {
    throw InputError(
        fmt::format("command line: --constant '{}': give V (every channel) or R,G,B", text));
  }
  Image image(like.width, like.height);
  for (std::size_t i = 0; i < image.values.size(); ++i) {
    image.values[i] = v.size() == 1 ? v[0] : v[i % kImageChannels];
  }
  return image;
}

void check_same_size(const Image& image, const Image& like, const std::string& what) {
  if (image.width != like.width || image.height != like.height) {
    throw InputError(fmt::format("command line: {} is {}x{} but the --images set is {}x{}", what,
                                 image.width, image.height, like.width, like.height));
  }
}

void check_image_count(std::size_t count, const std::string& option, const std::string& set,
                       std::size_t min_images) {
  if (count < min_images) {
    throw InputError(fmt::format(
        "command line: {} '{}': {} image(s); a standard error needs at least {} independent "
        "replicates (one seed each)",
        option, set, count, min_images));
  }
}

// Adds one image of a set after the set's checks: the size of the first, no pixels seen before.
void add_image(ImageSet& out, std::map<std::uint64_t, std::size_t>& seen, Image image,
               ImageFileFacts facts, const std::string& option) {
  const std::string& path = facts.path;
  if (!out.images.empty() &&
      (image.width != out.images.front().width || image.height != out.images.front().height)) {
    throw InputError(fmt::format("command line: {}: {} is {}x{} but {} is {}x{}", option, path,
                                 image.width, image.height, out.files.front().path,
                                 out.images.front().width, out.images.front().height));
  }
  const auto [it, inserted] = seen.emplace(content_hash(image), out.images.size());
  if (!inserted) {
    throw InputError(
        fmt::format("command line: {}: {} and {} hold the same pixels: the same replicate twice (a "
                    "reused seed or a copied file), which would understate the standard error",
                    option, out.files[it->second].path, path));
  }
  out.quantisation_bias =
      std::max(out.quantisation_bias, worst_quantisation_bias(facts.pixel_type));
  out.images.push_back(std::move(image));
  out.files.push_back(std::move(facts));
}

// No image of `set` in `other`, by content: a set tested against itself (the same files, or
// copies) agrees with a detectable bias that means nothing.
void check_sets_differ(const ImageSet& set, const ImageSet& other) {
  std::map<std::uint64_t, std::size_t> seen;
  for (std::size_t i = 0; i < set.images.size(); ++i) seen.emplace(content_hash(set.images[i]), i);
  for (std::size_t j = 0; j < other.images.size(); ++j) {
    const auto it = seen.find(content_hash(other.images[j]));
    if (it == seen.end()) continue;
    throw InputError(fmt::format(
        "command line: --images and --against hold the same image ({} and {}): a set tested "
        "against itself, or against copies of its files, agrees with a detectable bias that "
        "means nothing; give two independent sets (other seeds, or another renderer)",
        set.files[it->second].path, other.files[j].path));
  }
}

// --reference-image and its --reference-stderr into `input`.
void read_reference(const ImageSetRequest& request, ImageSetInput& input) {
  const Image& like = input.set.images.front();
  ImageFileFacts facts;
  input.reference = read_image_file(*request.reference_image, request.read, &facts);
  check_same_size(*input.reference, like, *request.reference_image);
  input.quantisation = std::max(input.quantisation, worst_quantisation_bias(facts.pixel_type));
  input.reference_pixel_type = facts.pixel_type;
  if (request.reference_stderr) {
    input.reference_stderr = read_image_file(*request.reference_stderr, request.read);
    check_same_size(*input.reference_stderr, like, *request.reference_stderr);
  }
}

}  // namespace

double worst_quantisation_bias(const std::string& pixel_type) {
  if (pixel_type == "half") return std::ldexp(1.0, -11);
  if (pixel_type == "rgbe") return std::ldexp(1.0, -7);
  return std::ldexp(1.0, -24);  // float (and anything wider)
}

std::vector<std::string> image_set_files(const std::string& set, const std::string& option) {
  std::vector<std::string> files;
  std::error_code error;
  if (fs::is_directory(set, error)) {
    for (const fs::directory_entry& entry : fs::directory_iterator(set, error)) {
      if (entry.is_regular_file() && image_extension(entry.path())) {
        files.push_back(entry.path().string());
      }
    }
    std::sort(files.begin(), files.end());
    if (files.empty()) {
      throw InputError(
          fmt::format("command line: {} '{}': the folder holds no {} file", option, set, kFormats));
    }
    check_folder_holds_replicates(set, files, option);
    return files;
  }
  if (set.find_first_of("*?[") != std::string::npos) {
    files = glob_files(set);
    if (files.empty()) {
      throw InputError(
          fmt::format("command line: {} '{}': the pattern matches no file", option, set));
    }
    return files;
  }
  for (const std::string& file : split_commas(set)) {
    if (file.empty()) {
      throw InputError(
          fmt::format("command line: {} '{}': an empty file name in the list", option, set));
    }
    files.push_back(file);
  }
  return files;
}

Image read_image_file(const std::string& path, const ImageReadOptions& options,
                      ImageFileFacts* facts) {
  std::string error;
  const std::unique_ptr<ImageFileReader> input = open_image_file(path, error);
  if (!input) {
    throw InputError(fmt::format("{}: cannot be read as an image: {}", path, error));
  }
  const ImageFileHeader& spec = input->header();
  // OpenImageIO reads PFM with its PNM plugin; only the float variant holds radiance.
  const std::string& plugin = spec.plugin;
  const std::string format = plugin == "pnm" && spec.float_pixels ? "pfm" : plugin;
  if (format != "openexr" && format != "hdr" && format != "pfm") {
    throw InputError(fmt::format("{}: a {} file ({}); radiance images are {}", path, plugin,
                                 spec.pixel_format, kFormats));
  }
  std::vector<int> channels;
  for (const std::string& name : options.channels) {
    const auto found = std::find(spec.channel_names.begin(), spec.channel_names.end(), name);
    if (found == spec.channel_names.end()) {
      throw InputError(fmt::format("{}: no channel '{}'; it has {} (choose with --channels)", path,
                                   name, fmt::join(spec.channel_names, ", ")));
    }
    channels.push_back(static_cast<int>(found - spec.channel_names.begin()));
  }
  const std::uint32_t width = spec.width;
  const std::uint32_t height = spec.height;
  const auto channel_count = static_cast<std::size_t>(spec.channel_names.size());
  std::vector<float> pixels;
  if (!input->read_pixels(pixels, error)) {
    throw InputError(
        fmt::format("{}: cannot read its pixels (truncated or damaged?): {}", path, error));
  }
  const CropWindow crop = options.crop.value_or(CropWindow{0, 0, width, height});
  if (crop.width == 0 || crop.height == 0 || crop.x + crop.width > width ||
      crop.y + crop.height > height) {
    throw InputError(fmt::format("{}: --crop {},{},{},{} is not inside its {}x{} pixels", path,
                                 crop.x, crop.y, crop.width, crop.height, width, height));
  }
  Image image(crop.width, crop.height);
  ImageFileFacts found{.path = path, .format = format};
  double worst = 0.0;
  for (int c : channels) {
    const std::string type = stored_type(format, spec, c);
    if (worst_quantisation_bias(type) >= worst) {
      worst = worst_quantisation_bias(type);
      found.pixel_type = type;
    }
  }
  for (std::uint32_t y = 0; y < crop.height; ++y) {
    for (std::uint32_t x = 0; x < crop.width; ++x) {
      const std::size_t pixel = std::size_t{crop.y + y} * width + (crop.x + x);
      for (std::uint32_t c = 0; c < kImageChannels; ++c) {
        image.at(x, y, c) = pixels[pixel * channel_count + static_cast<std::size_t>(channels[c])];
      }
    }
  }
  count_values(image, found);
  if (facts != nullptr) *facts = std::move(found);
  return image;
}

void count_values(const Image& image, ImageFileFacts& facts) {
  for (std::uint32_t y = 0; y < image.height; ++y) {
    for (std::uint32_t x = 0; x < image.width; ++x) {
      for (std::uint32_t c = 0; c < kImageChannels; ++c) {
        const double v = image.at(x, y, c);
        if (!std::isfinite(v)) {
          if (facts.nonfinite++ == 0) {
            facts.first_nonfinite_x = x;
            facts.first_nonfinite_y = y;
          }
        } else if (v < 0.0) {
          ++facts.negative;
        }
      }
    }
  }
}

ImageSet read_image_set(const std::string& set, const std::string& option,
                        const ImageReadOptions& options, std::size_t min_images) {
  const std::vector<std::string> paths = image_set_files(set, option);
  check_image_count(paths.size(), option, set, min_images);
  ImageSet out;
  std::map<std::uint64_t, std::size_t> seen;  // content hash -> file index
  for (const std::string& path : paths) {
    ImageFileFacts facts;
    Image image = read_image_file(path, options, &facts);
    add_image(out, seen, std::move(image), std::move(facts), option);
  }
  return out;
}

ImageSet image_set_of(std::vector<Image> images, std::vector<ImageFileFacts> facts,
                      const std::string& option, const std::string& set, std::size_t min_images) {
  check_image_count(images.size(), option, set, min_images);
  ImageSet out;
  std::map<std::uint64_t, std::size_t> seen;
  for (std::size_t i = 0; i < images.size(); ++i) {
    add_image(out, seen, std::move(images[i]), std::move(facts[i]), option);
  }
  return out;
}

CropWindow parse_crop(const std::string& text) {
  const std::vector<double> v = parse_numbers(text, "--crop");
  const bool integers =
      std::all_of(v.begin(), v.end(), [](double x) { return x >= 0 && x == std::floor(x); });
  if (v.size() != 4 || !integers || v[2] < 1 || v[3] < 1 || v[0] > 1e6 || v[1] > 1e6 ||
      v[2] > 1e6 || v[3] > 1e6) {
    throw InputError(fmt::format(
        "command line: --crop '{}': give X,Y,W,H, the top-left pixel and a size of at least 1",
        text));
  }
  return {static_cast<std::uint32_t>(v[0]), static_cast<std::uint32_t>(v[1]),
          static_cast<std::uint32_t>(v[2]), static_cast<std::uint32_t>(v[3])};
}

ImageSetInput read_image_set_input(const ImageSetRequest& request, ImagesInMemory loaded) {
  ImageSetInput input;
  input.set = loaded.set ? std::move(*loaded.set)
                         : read_image_set(request.images, "--images", request.read);
  input.quantisation = input.set.quantisation_bias;
  const Image& like = input.set.images.front();
  if (request.against) {
    input.other = loaded.other ? std::move(*loaded.other)
                               : read_image_set(*request.against, "--against", request.read);
    check_same_size(input.other->images.front(), like, "the --against set");
    if (request.paired && input.other->images.size() != input.set.images.size()) {
      throw InputError(fmt::format(
          "command line: --paired: {} images against {}; paired sets are replicate pairs "
          "(replicate k of both from the same seed)",
          input.set.images.size(), input.other->images.size()));
    }
    check_sets_differ(input.set, *input.other);
    input.quantisation = std::max(input.quantisation, input.other->quantisation_bias);
  } else if (loaded.reference) {
    check_same_size(*loaded.reference, like, *request.reference_image);
    input.reference = std::move(loaded.reference);
    input.reference_pixel_type = loaded.reference_pixel_type;
    input.quantisation =
        std::max(input.quantisation, worst_quantisation_bias(input.reference_pixel_type));
    if (loaded.reference_stderr) {
      check_same_size(*loaded.reference_stderr, like, *request.reference_stderr);
      input.reference_stderr = std::move(loaded.reference_stderr);
    }
  } else if (request.reference_image) {
    read_reference(request, input);
  } else {
    input.constant = parse_numbers(*request.constant, "--constant");
    input.reference = constant_image(like, input.constant, *request.constant);
  }
  return input;
}

}  // namespace pcbench
