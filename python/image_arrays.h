// numpy arrays as pcbench images: a set of replicates (R, H, W, C) and a single image (H, W, C)
// or (H, W), float32 or float64, copied exactly into the harness's double-precision images.
// Their checks are the harness's (harness/plan/image_set.h: at least 2 replicates, none twice)
// plus one of their own: a non-finite value is a ValueError naming replicate and pixel (an array
// has no file format to blame; the CLI instead counts them in a file and fails their tile).
#pragma once

#include <pybind11/numpy.h>

#include <array>
#include <string>

#include "harness/plan/image_set.h"

namespace pcbench::python {

// Which three channels of C fill R, G, B: indices, or empty for (0, 1, 2), or (0, 0, 0) when
// C is 1.
using ChannelIndices = std::array<std::size_t, kImageChannels>;

// "float" for float32 (as a float EXR stores it), "double" for float64.
std::string pixel_type_of(const pybind11::array& array);

// The replicates of `array` (R, H, W, C) as a set named `name` (its files are `name[r]`).
// Throws InputError for another shape or dtype, a channel index outside C, a non-finite value,
// fewer than 2 replicates or one twice.
ImageSet image_set_from_array(const pybind11::array& array, const std::string& name,
                              const std::optional<ChannelIndices>& channels);

// One image (H, W, C) or (H, W), checked as above.
Image image_from_array(const pybind11::array& array, const std::string& name,
                       const std::optional<ChannelIndices>& channels);

// "16 x 32 x 48 x 3 float32 array": what an array is called in messages and the report (no
// parentheses: a comparison's label puts its self-check's scale in them).
std::string describe_array(const pybind11::array& array);

}  // namespace pcbench::python
