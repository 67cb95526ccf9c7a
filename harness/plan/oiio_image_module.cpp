// The pcbench_image_io module: ImageFileReader (harness/plan/image_file_reader.h) over
// OpenImageIO. Built as a shared module that pcbench opens with dlopen only when it reads an
// image, so that the other commands do not load OpenImageIO's libraries.
#include <OpenImageIO/imageio.h>

#include "harness/plan/image_file_reader.h"

namespace pcbench {
namespace {

class OiioImageFileReader final : public ImageFileReader {
 public:
  explicit OiioImageFileReader(std::unique_ptr<OIIO::ImageInput> input) : input_(std::move(input)) {
    const OIIO::ImageSpec& spec = input_->spec();
    header_.plugin = input_->format_name();
    header_.pixel_format = spec.format.c_str();
    header_.float_pixels = spec.format == OIIO::TypeDesc::FLOAT;
    header_.width = static_cast<std::uint32_t>(spec.width);
    header_.height = static_cast<std::uint32_t>(spec.height);
    header_.channel_names = spec.channelnames;
    for (int c = 0; c < spec.nchannels; ++c) {
      const OIIO::TypeDesc type = spec.channelformat(c);
      header_.channel_formats.emplace_back(type == OIIO::TypeDesc::HALF    ? "half"
                                           : type == OIIO::TypeDesc::FLOAT ? "float"
                                                                           : type.c_str());
    }
  }

  const ImageFileHeader& header() const override { return header_; }

  bool read_pixels(std::vector<float>& pixels, std::string& error) override {
    const OIIO::ImageSpec& spec = input_->spec();
    pixels.resize(std::size_t{header_.width} * header_.height *
                  static_cast<std::size_t>(spec.nchannels));
    if (input_->read_image(0, 0, 0, spec.nchannels, OIIO::TypeDesc::FLOAT, pixels.data())) {
      return true;
    }
    error = input_->geterror();
    return false;
  }

 private:
  std::unique_ptr<OIIO::ImageInput> input_;
  ImageFileHeader header_;
};

}  // namespace
}  // namespace pcbench

extern "C" pcbench::ImageFileReader* pcbench_open_image_file(const char* path, std::string* error) {
  std::unique_ptr<OIIO::ImageInput> input = OIIO::ImageInput::open(path);
  if (!input) {
    *error = OIIO::geterror();
    return nullptr;
  }
  return new pcbench::OiioImageFileReader(std::move(input));
}
