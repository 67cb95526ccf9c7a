#include "results/exr_file.h"

#include <ImathBox.h>
#include <ImfChannelList.h>
#include <ImfFrameBuffer.h>
#include <ImfHeader.h>
#include <ImfInputFile.h>
#include <ImfOutputFile.h>
#include <fmt/format.h>

#include <climits>
#include <exception>
#include <set>
#include <stdexcept>
#include <system_error>

namespace pcbench {
namespace {

void check_arguments(std::uint32_t width, std::uint32_t height,
                     const std::vector<ExrChannel>& channels) {
  // OpenEXR addresses pixels with int coordinates.
  if (width == 0 || height == 0 || width > INT_MAX || height > INT_MAX) {
    throw std::invalid_argument(fmt::format("EXR image size {}x{} is not valid", width, height));
  }
  if (channels.empty()) throw std::invalid_argument("EXR image without channels");
  const std::size_t count = std::size_t{width} * height;
  std::set<std::string> names;
  for (const ExrChannel& channel : channels) {
    if (channel.name.empty()) throw std::invalid_argument("EXR channel without a name");
    if (!names.insert(channel.name).second) {
      throw std::invalid_argument(fmt::format("EXR channel '{}' given twice", channel.name));
    }
    if (channel.values.size() != count) {
      throw std::invalid_argument(fmt::format("EXR channel '{}' has {} values, not {}x{} = {}",
                                              channel.name, channel.values.size(), width, height,
                                              count));
    }
  }
}

// The scope closes the OutputFile, which writes its line offset table: only then is the file
// complete and may be renamed.
void write_file(const std::filesystem::path& file, std::uint32_t width, std::uint32_t height,
                const std::vector<ExrChannel>& channels) {
  Imf::Header header(static_cast<int>(width), static_cast<int>(height));
  header.compression() = Imf::ZIP_COMPRESSION;
  Imf::FrameBuffer frame;
  for (const ExrChannel& channel : channels) {
    header.channels().insert(channel.name, Imf::Channel(Imf::FLOAT));
    frame.insert(channel.name,
                 Imf::Slice::Make(Imf::FLOAT, channel.values.data(), header.dataWindow()));
  }
  Imf::OutputFile out(file.c_str(), header);
  out.setFrameBuffer(frame);
  out.writePixels(static_cast<int>(height));
}

}  // namespace

void write_exr(const std::filesystem::path& path, std::uint32_t width, std::uint32_t height,
               const std::vector<ExrChannel>& channels) {
  check_arguments(width, height, channels);
  std::filesystem::path temporary = path;
  temporary += ".tmp";
  try {
    write_file(temporary, width, height, channels);
    std::filesystem::rename(temporary, path);
  } catch (const std::exception& error) {
    // Iex exceptions and filesystem errors alike; never leave the partial file behind.
    std::error_code ignored;
    std::filesystem::remove(temporary, ignored);
    throw std::runtime_error(
        fmt::format("cannot write EXR file '{}': {}", path.string(), error.what()));
  }
}

std::vector<ExrChannel> rgb_channels(const Image& image, const std::string& layer) {
  const std::size_t count = image.pixel_count();
  if (image.values.size() != count * kImageChannels) {
    throw std::invalid_argument("Image has the wrong number of values for its size");
  }
  const std::string prefix = layer.empty() ? "" : layer + ".";
  std::vector<ExrChannel> channels = {{prefix + "R", {}}, {prefix + "G", {}}, {prefix + "B", {}}};
  for (std::uint32_t c = 0; c < kImageChannels; ++c) {
    std::vector<float>& values = channels[c].values;
    values.resize(count);
    for (std::size_t i = 0; i < count; ++i) {
      values[i] = static_cast<float>(image.values[i * kImageChannels + c]);
    }
  }
  return channels;
}

void write_exr_rgb(const std::filesystem::path& path, const Image& image) {
  write_exr(path, image.width, image.height, rgb_channels(image));
}

std::vector<ExrChannel> read_exr(const std::filesystem::path& path, std::uint32_t& width,
                                 std::uint32_t& height) {
  try {
    Imf::InputFile in(path.c_str());
    const Imath::Box2i window = in.header().dataWindow();
    const std::int64_t w = std::int64_t{window.max.x} - window.min.x + 1;
    const std::int64_t h = std::int64_t{window.max.y} - window.min.y + 1;
    std::vector<ExrChannel> channels;
    for (auto it = in.header().channels().begin(); it != in.header().channels().end(); ++it) {
      if (it.channel().type != Imf::FLOAT) continue;
      channels.push_back({it.name(), std::vector<float>(static_cast<std::size_t>(w * h))});
    }
    // Slices are inserted after the vector has stopped growing: they hold its buffers.
    Imf::FrameBuffer frame;
    for (ExrChannel& channel : channels) {
      frame.insert(channel.name, Imf::Slice::Make(Imf::FLOAT, channel.values.data(), window));
    }
    in.setFrameBuffer(frame);
    in.readPixels(window.min.y, window.max.y);
    width = static_cast<std::uint32_t>(w);
    height = static_cast<std::uint32_t>(h);
    return channels;
  } catch (const std::exception& error) {
    throw std::runtime_error(
        fmt::format("cannot read EXR file '{}': {}", path.string(), error.what()));
  }
}

}  // namespace pcbench
