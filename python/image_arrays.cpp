#include "image_arrays.h"

#include <fmt/format.h>
#include <fmt/ranges.h>

#include <vector>

#include "base/errors.h"

namespace pcbench::python {
namespace {

namespace py = pybind11;

std::vector<std::string> sizes_of(const py::array& array) {
  std::vector<std::string> sizes;
  for (py::ssize_t d = 0; d < array.ndim(); ++d) sizes.push_back(std::to_string(array.shape(d)));
  return sizes;
}

// numpy's way: "(24, 32, 3)".
std::string shape_text(const py::array& array) {
  const std::vector<std::string> sizes = sizes_of(array);
  return fmt::format("({}{})", fmt::join(sizes, ", "), sizes.size() == 1 ? "," : "");
}

bool is_float32(const py::array& array) {
  return array.dtype().is(py::dtype::of<float>());
}

void check_dtype(const py::array& array, const std::string& name) {
  if (!is_float32(array) && !array.dtype().is(py::dtype::of<double>())) {
    throw InputError(fmt::format("{}: dtype {}; give float32 or float64 (radiance values)", name,
                                 py::str(array.dtype()).cast<std::string>()));
  }
}

ChannelIndices channels_for(std::size_t channel_count, const std::optional<ChannelIndices>& chosen,
                            const std::string& name) {
  ChannelIndices channels = channel_count == 1 ? ChannelIndices{0, 0, 0} : ChannelIndices{0, 1, 2};
  if (chosen) channels = *chosen;
  for (std::size_t c : channels) {
    if (c >= channel_count) {
      throw InputError(fmt::format(
          "{}: channel {} is outside its {} channel(s); choose three of 0 to {} with channels=",
          name, c, channel_count, channel_count - 1));
    }
  }
  return channels;
}

// Replicate `r` of a (R, H, W, C) array of doubles (or an image with R = 1) as an Image with its
// facts; a non-finite value is an InputError naming where it is.
template <class T>
Image copy_image(const py::array_t<T, py::array::c_style | py::array::forcecast>& values,
                 std::size_t r, const ChannelIndices& channels, const std::string& path,
                 ImageFileFacts& facts) {
  const auto height = static_cast<std::uint32_t>(values.shape(1));
  const auto width = static_cast<std::uint32_t>(values.shape(2));
  const auto channel_count = static_cast<std::size_t>(values.shape(3));
  const T* data = values.data() + r * std::size_t{height} * width * channel_count;
  Image image(width, height);
  for (std::uint32_t y = 0; y < height; ++y) {
    for (std::uint32_t x = 0; x < width; ++x) {
      const T* pixel = data + (std::size_t{y} * width + x) * channel_count;
      for (std::uint32_t c = 0; c < kImageChannels; ++c) image.at(x, y, c) = pixel[channels[c]];
    }
  }
  count_values(image, facts);
  if (facts.nonfinite > 0) {
    throw InputError(fmt::format(
        "{}: {} NaN or infinite value(s), the first at pixel ({}, {}) (x, y: row {}, column {} of "
        "the replicate); pcbench does not drop non-finite values: find out why the renderer "
        "produced them",
        path, facts.nonfinite, *facts.first_nonfinite_x, *facts.first_nonfinite_y,
        *facts.first_nonfinite_y, *facts.first_nonfinite_x));
  }
  return image;
}

// The array as (R, H, W, C) in C order, of its own dtype.
template <class T>
ImageSet set_of(const py::array& array, const std::string& name,
                const std::optional<ChannelIndices>& chosen) {
  const auto values = py::array_t<T, py::array::c_style | py::array::forcecast>::ensure(array);
  const auto replicates = static_cast<std::size_t>(values.shape(0));
  const ChannelIndices channels =
      channels_for(static_cast<std::size_t>(values.shape(3)), chosen, name);
  std::vector<Image> images;
  std::vector<ImageFileFacts> facts;
  for (std::size_t r = 0; r < replicates; ++r) {
    ImageFileFacts f{.path = fmt::format("{}[{}]", name, r),
                     .format = "numpy",
                     .pixel_type = pixel_type_of(array)};
    images.push_back(copy_image<T>(values, r, channels, f.path, f));
    facts.push_back(std::move(f));
  }
  return image_set_of(std::move(images), std::move(facts), name, describe_array(array));
}

}  // namespace

std::string pixel_type_of(const py::array& array) {
  return is_float32(array) ? "float" : "double";
}

std::string describe_array(const py::array& array) {
  return fmt::format("{} {} array", fmt::join(sizes_of(array), " x "),
                     py::str(array.dtype()).cast<std::string>());
}

ImageSet image_set_from_array(const py::array& array, const std::string& name,
                              const std::optional<ChannelIndices>& channels) {
  check_dtype(array, name);
  if (array.ndim() != 4 || array.shape(1) == 0 || array.shape(2) == 0 || array.shape(3) == 0) {
    throw InputError(
        fmt::format("{}: shape {}; give (R, H, W, C): R replicates of H x W pixels with C channels",
                    name, shape_text(array)));
  }
  return is_float32(array) ? set_of<float>(array, name, channels)
                           : set_of<double>(array, name, channels);
}

Image image_from_array(const py::array& array, const std::string& name,
                       const std::optional<ChannelIndices>& channels) {
  check_dtype(array, name);
  if ((array.ndim() != 2 && array.ndim() != 3) || array.size() == 0) {
    throw InputError(
        fmt::format("{}: shape {}; give (H, W, C) or (H, W)", name, shape_text(array)));
  }
  const py::ssize_t channel_count = array.ndim() == 3 ? array.shape(2) : 1;
  py::array one = py::array::ensure(array);  // a new handle: reshape is not const
  one = one.reshape({py::ssize_t{1}, array.shape(0), array.shape(1), channel_count});
  const auto copy = [&]<class T>(T) {
    const auto values = py::array_t<T, py::array::c_style | py::array::forcecast>::ensure(one);
    ImageFileFacts facts{.path = name};
    return copy_image<T>(values, 0,
                         channels_for(static_cast<std::size_t>(channel_count), channels, name),
                         name, facts);
  };
  return is_float32(array) ? copy(float{}) : copy(double{});
}

}  // namespace pcbench::python
