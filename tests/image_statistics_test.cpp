#include <gtest/gtest.h>

#include <algorithm>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <limits>
#include <random>
#include <stdexcept>
#include <string>
#include <vector>

#include "results/exr_file.h"
#include "test_support.h"

namespace pcbench {
namespace {

// ---------------------------------------------------------------------------------------------
// EXR files

bool same_bits(const std::vector<float>& a, const std::vector<float>& b) {
  return a.size() == b.size() && std::memcmp(a.data(), b.data(), a.size() * sizeof(float)) == 0;
}

TEST(ExrFile, RoundTripIsBitwise) {
  TemporaryFolder folder;
  const std::filesystem::path file = folder.path() / "image.exr";
  constexpr std::uint32_t kW = 7, kH = 5;
  std::mt19937_64 rng(7);
  std::uniform_real_distribution<float> uniform(-1e6f, 1e6f);
  std::vector<ExrChannel> channels = {{"R", {}}, {"G", {}}, {"B", {}}, {"z", {}}};
  for (ExrChannel& channel : channels) {
    for (std::uint32_t i = 0; i < kW * kH; ++i) channel.values.push_back(uniform(rng));
  }
  // Values a lossy or half-float path would change.
  channels[3].values[0] = std::numeric_limits<float>::denorm_min();
  channels[3].values[1] = -0.0f;
  channels[3].values[2] = std::numeric_limits<float>::infinity();
  channels[3].values[3] = std::numeric_limits<float>::quiet_NaN();
  channels[3].values[4] = std::numeric_limits<float>::max();
  channels[3].values[5] = 1.0f + std::numeric_limits<float>::epsilon();
  write_exr(file, kW, kH, channels);
  EXPECT_EQ(files_under(folder.path()), std::vector<std::string>{"image.exr"});

  std::uint32_t width = 0, height = 0;
  const std::vector<ExrChannel> back = read_exr(file, width, height);
  EXPECT_EQ(width, kW);
  EXPECT_EQ(height, kH);
  ASSERT_EQ(back.size(), channels.size());
  for (const ExrChannel& written : channels) {
    const auto read = std::find_if(back.begin(), back.end(),
                                   [&](const ExrChannel& c) { return c.name == written.name; });
    ASSERT_NE(read, back.end()) << written.name;
    EXPECT_TRUE(same_bits(read->values, written.values)) << written.name;
  }

  // Writing again replaces the file.
  channels.resize(1);
  write_exr(file, kW, kH, channels);
  EXPECT_EQ(read_exr(file, width, height).size(), 1u);
  EXPECT_EQ(files_under(folder.path()), std::vector<std::string>{"image.exr"});
}

TEST(ExrFile, RgbImageRowMajorTopRowFirst) {
  TemporaryFolder folder;
  const std::filesystem::path file = folder.path() / "rgb.exr";
  Image image(3, 2);
  for (std::uint32_t y = 0; y < 2; ++y) {
    for (std::uint32_t x = 0; x < 3; ++x) {
      for (std::uint32_t c = 0; c < kImageChannels; ++c) {
        image.at(x, y, c) = 0.1 + x + 10.0 * y + 100.0 * c;
      }
    }
  }
  write_exr_rgb(file, image);
  std::uint32_t width = 0, height = 0;
  const std::vector<ExrChannel> back = read_exr(file, width, height);
  EXPECT_EQ(width, 3u);
  EXPECT_EQ(height, 2u);
  ASSERT_EQ(back.size(), 3u);
  const char* names = "RGB";
  for (std::uint32_t c = 0; c < kImageChannels; ++c) {
    const auto read = std::find_if(back.begin(), back.end(), [&](const ExrChannel& channel) {
      return channel.name == std::string(1, names[c]);
    });
    ASSERT_NE(read, back.end());
    for (std::uint32_t y = 0; y < 2; ++y) {
      for (std::uint32_t x = 0; x < 3; ++x) {
        EXPECT_EQ(read->values[y * 3 + x], static_cast<float>(image.at(x, y, c)));
      }
    }
  }
}

TEST(ExrFile, ExrheaderSeesFloatChannels) {
  const std::filesystem::path exrheader = "/usr/bin/exrheader";
  if (!std::filesystem::exists(exrheader)) {
    GTEST_SKIP() << "no " << exrheader << " (Debian package openexr)";
  }
  TemporaryFolder folder;
  const std::filesystem::path file = folder.path() / "rgb.exr";
  const std::filesystem::path listing = folder.path() / "header.txt";
  write_exr_rgb(file, Image(4, 3));
  const std::string command =
      exrheader.string() + " '" + file.string() + "' > '" + listing.string() + "' 2>&1";
  ASSERT_EQ(std::system(command.c_str()), 0) << read_text(listing);
  const std::string header = read_text(listing);
  EXPECT_NE(header.find("zip"), std::string::npos) << header;
  for (const char* channel : {"R", "G", "B"}) {
    EXPECT_NE(header.find(std::string(channel) + ", 32-bit floating-point"), std::string::npos)
        << header;
  }
  EXPECT_EQ(header.find("16-bit"), std::string::npos) << header;
}

TEST(ExrFile, FailuresThrowAndLeaveNoTemporary) {
  TemporaryFolder folder;
  const std::vector<ExrChannel> one = {{"Y", std::vector<float>(6, 1.0f)}};
  EXPECT_THROW(write_exr(folder.path() / "missing" / "a.exr", 3, 2, one), std::runtime_error);
  // The rename onto a folder fails after the temporary was written.
  std::filesystem::create_directory(folder.path() / "taken.exr");
  EXPECT_THROW(write_exr(folder.path() / "taken.exr", 3, 2, one), std::runtime_error);
  EXPECT_EQ(files_under(folder.path()), std::vector<std::string>{});

  EXPECT_THROW(write_exr(folder.path() / "a.exr", 2, 2, one), std::invalid_argument);
  EXPECT_THROW(write_exr(folder.path() / "a.exr", 0, 2, {{"Y", {}}}), std::invalid_argument);
  EXPECT_THROW(write_exr(folder.path() / "a.exr", 3, 2, {}), std::invalid_argument);
  EXPECT_THROW(write_exr(folder.path() / "a.exr", 3, 2, {one[0], one[0]}), std::invalid_argument);
  EXPECT_EQ(files_under(folder.path()), std::vector<std::string>{});

  std::uint32_t width = 0, height = 0;
  EXPECT_THROW(read_exr(folder.path() / "none.exr", width, height), std::runtime_error);
  write_text(folder.path() / "text.exr", "not an EXR file");
  EXPECT_THROW(read_exr(folder.path() / "text.exr", width, height), std::runtime_error);
}

}  // namespace
}  // namespace pcbench
