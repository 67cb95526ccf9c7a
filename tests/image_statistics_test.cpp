#include "harness/verify/image_statistics.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <limits>
#include <random>
#include <stdexcept>
#include <string>
#include <vector>

#include "harness/run/diagnostics.h"
#include "harness/verify/statistics.h"
#include "results/exr_file.h"
#include "test_support.h"
#include "tests/synthetic_images.h"

namespace pcbench {
namespace {

constexpr double kInf = std::numeric_limits<double>::infinity();
constexpr std::uint32_t kWidth = 64, kHeight = 48, kReplicates = 8;
constexpr double kSd = 0.5;

// ---------------------------------------------------------------------------------------------
// pixel_statistics and z_map

TEST(ImageStatisticsPixels, KnownNumbers) {
  std::vector<Image> images(3, Image(2, 1));
  for (std::uint32_t r = 0; r < 3; ++r) {
    images[r].at(0, 0, 0) = 1.0 + r;              // 1, 2, 3: mean 2, sd 1
    images[r].at(1, 0, 2) = 5.0;                  // constant: se 0
    images[r].at(1, 0, 1) = r == 0 ? -4.0 : 2.0;  // -4, 2, 2: mean 0, sd sqrt(12)
  }
  const PixelStatistics s = pixel_statistics(images);
  EXPECT_EQ(s.replicates, 3u);
  EXPECT_EQ(s.mean.width, 2u);
  EXPECT_EQ(s.mean.height, 1u);
  EXPECT_DOUBLE_EQ(s.mean.at(0, 0, 0), 2.0);
  EXPECT_DOUBLE_EQ(s.standard_error.at(0, 0, 0), 1.0 / std::sqrt(3.0));
  EXPECT_DOUBLE_EQ(s.mean.at(1, 0, 2), 5.0);
  EXPECT_EQ(s.standard_error.at(1, 0, 2), 0.0);
  EXPECT_DOUBLE_EQ(s.mean.at(1, 0, 1), 0.0);
  EXPECT_DOUBLE_EQ(s.standard_error.at(1, 0, 1), 2.0);  // sqrt(12 / 3)
  EXPECT_EQ(s.mean.at(0, 0, 1), 0.0);
  EXPECT_EQ(s.standard_error.at(0, 0, 1), 0.0);
}

TEST(ImageStatisticsPixels, RejectsFewReplicatesAndMixedSizes) {
  EXPECT_THROW(pixel_statistics(std::vector<Image>{}), std::invalid_argument);
  EXPECT_THROW(pixel_statistics(std::vector<Image>{Image(2, 2)}), std::invalid_argument);
  EXPECT_THROW(pixel_statistics(std::vector<Image>{Image(2, 2), Image(2, 3)}),
               std::invalid_argument);
  Image broken(2, 2);
  broken.values.pop_back();
  EXPECT_THROW(pixel_statistics(std::vector<Image>{Image(2, 2), broken}), std::invalid_argument);
}

TEST(ImageStatisticsZMap, TwoSidesAndExact) {
  PixelStatistics a{Image(2, 1), Image(2, 1), 4}, b{Image(2, 1), Image(2, 1), 4};
  a.mean.at(0, 0, 0) = 3.0, a.standard_error.at(0, 0, 0) = 0.3;
  b.mean.at(0, 0, 0) = 2.0, b.standard_error.at(0, 0, 0) = 0.4;
  a.mean.at(0, 0, 1) = 1.0;  // both se 0, means differ: certain
  b.mean.at(0, 0, 2) = 1.0;
  a.mean.at(1, 0, 0) = 7.0, b.mean.at(1, 0, 0) = 7.0;  // both se 0, equal: 0, not NaN
  const Image z = z_map(a, b);
  EXPECT_DOUBLE_EQ(z.at(0, 0, 0), 2.0);  // 1 / sqrt(0.09 + 0.16)
  EXPECT_EQ(z.at(0, 0, 1), kInf);
  EXPECT_EQ(z.at(0, 0, 2), -kInf);
  EXPECT_EQ(z.at(1, 0, 0), 0.0);
  EXPECT_EQ(z.at(1, 0, 1), 0.0);

  Image exact(2, 1);
  exact.at(0, 0, 0) = 3.6;
  exact.at(1, 0, 0) = 7.0;
  const Image ze = z_map(a, exact);
  EXPECT_NEAR(ze.at(0, 0, 0), -2.0, 1e-12);  // (3 - 3.6) / 0.3
  EXPECT_EQ(ze.at(0, 0, 1), kInf);
  EXPECT_EQ(ze.at(1, 0, 0), 0.0);

  EXPECT_THROW(z_map(a, Image(2, 2)), std::invalid_argument);
  b.mean = Image(1, 1);
  EXPECT_THROW(z_map(a, b), std::invalid_argument);
}

// ---------------------------------------------------------------------------------------------
// summarize_z

TEST(ImageStatisticsSummary, GuardsAndExpectedCount) {
  std::vector<Image> a(3, Image(3, 2)), b(5, Image(3, 2));
  for (Image& image : a) image.at(0, 0, 1) = 1.0;  // b all 0 there: low count
  b[4].at(2, 1, 0) = 3.0;                          // a all 0 there: low count
  a[0].at(1, 1, 2) = 1.0, b[0].at(1, 1, 2) = 1.0;  // both sample it
  Image z(3, 2);
  z.at(1, 0, 0) = -4.5;
  z.at(1, 0, 1) = 4.2;  // same pixel: counted once
  z.at(2, 0, 2) = 3.9;
  z.at(0, 1, 0) = kInf;
  const PixelTestSummary s = summarize_z(z, a, b);
  EXPECT_EQ(s.max_abs_z, kInf);
  EXPECT_EQ(s.pixels_beyond_4_sigma, 2u);
  EXPECT_EQ(s.low_count_pixels, 2u);
  // The smaller side has 3 replicates: 2 dof.
  EXPECT_DOUBLE_EQ(s.expected_beyond_4_sigma, 6.0 * 3.0 * student_t_p_value(4.0, 2.0));

  // Against an exact image: b is that one image, and the dof are a's.
  Image exact(3, 2);
  exact.at(0, 0, 1) = 1.0;
  exact.at(2, 0, 0) = 0.5;  // a all 0 there
  z.at(0, 1, 0) = std::nan("");
  const PixelTestSummary e = summarize_z(z, a, std::span(&exact, 1));
  EXPECT_TRUE(std::isnan(e.max_abs_z));
  EXPECT_EQ(e.low_count_pixels, 2u);  // (2, 0) and (1, 1)
  EXPECT_DOUBLE_EQ(e.expected_beyond_4_sigma, 6.0 * 3.0 * student_t_p_value(4.0, 2.0));

  EXPECT_THROW(summarize_z(z, std::span(a).first(1), b), std::invalid_argument);
  EXPECT_THROW(summarize_z(z, a, std::vector<Image>{}), std::invalid_argument);
  EXPECT_THROW(summarize_z(Image(2, 2), a, b), std::invalid_argument);
}

TEST(ImageStatisticsSummary, NullSamplesStayBelowTheBound) {
  const std::vector<Image> a = normal_replicates(kWidth, kHeight, kReplicates, 51, kSd);
  const std::vector<Image> b = normal_replicates(kWidth, kHeight, kReplicates, 52, kSd);
  const Image z = z_map(pixel_statistics(a), pixel_statistics(b));
  const PixelTestSummary s = summarize_z(z, a, b);
  EXPECT_EQ(s.low_count_pixels, 0u);
  EXPECT_GT(s.max_abs_z, 2.0);
  EXPECT_LE(s.pixels_beyond_4_sigma, 2.0 * s.expected_beyond_4_sigma + 3.0);
}

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
