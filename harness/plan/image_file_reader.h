// Opening a radiance image file through OpenImageIO, which pcbench loads only when a command reads
// one (`verify --images`). OpenImageIO links about 260 shared libraries, and loading and
// relocating them took about 1 s of every pcbench command, `pcbench --version` included
// (docs/findings/speed.md, "Start-up"); so OpenImageIO lives in a module of its own
// (harness/plan/oiio_image_module.cpp, built as pcbench_image_io next to pcbench) that
// image_file_reader.cpp opens with dlopen on the first image read.
#pragma once

#include <cstdint>
#include <memory>
#include <string>
#include <vector>

namespace pcbench {

// What a file says about itself before its pixels are read.
struct ImageFileHeader {
  std::string plugin = {};        // OpenImageIO's format name: openexr, hdr, pnm, png, ...
  std::string pixel_format = {};  // the file's pixel type as OpenImageIO names it: half, float, ...
  bool float_pixels = false;      // the file's pixel type is 32-bit float (PFM rather than PPM)
  std::uint32_t width = 0, height = 0;
  std::vector<std::string> channel_names = {};
  std::vector<std::string> channel_formats = {};  // per channel: half, float, uint8, ...
};

// One open file.
class ImageFileReader {
 public:
  virtual ~ImageFileReader() = default;
  virtual const ImageFileHeader& header() const = 0;
  // Every channel of every pixel as float, channel fastest; false with `error` set when the
  // pixels cannot be read (a truncated or damaged file).
  virtual bool read_pixels(std::vector<float>& pixels, std::string& error) = 0;
};

// Opens `path`; nullptr with `error` set when it cannot be read as an image. Throws InputError
// when the image module cannot be loaded (it names the path tried; PCBENCH_IMAGE_MODULE overrides
// it).
std::unique_ptr<ImageFileReader> open_image_file(const std::string& path, std::string& error);

// The module's one entry point, looked up by name (extern "C": no mangling to agree on).
using OpenImageFileFunction = ImageFileReader* (*)(const char* path, std::string* error);
inline constexpr const char* kOpenImageFileSymbol = "pcbench_open_image_file";

}  // namespace pcbench
