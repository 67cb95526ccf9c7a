// `pcbench verify --images`: replicate image sets from "another renderer", written here in each
// format with OpenImageIO itself (known values plus noise from pcbench's own generator), tested
// end to end; bad input; and the round trip of pcbench's own replicates (--replicate-images).
//
// Error budget: each consistent case is one family at alpha = 0.01 with a fixed seed; the biased
// cases are asserted only where the reported detectable bias is below the injected one.
#include <fmt/format.h>
#include <gtest/gtest.h>

#include <OpenImageIO/imageio.h>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <limits>
#include <string>
#include <vector>

#include "base/rng.h"
#include "harness/plan/image_set.h"
#include "harness/verify/block_pyramid.h"
#include "test_support.h"

namespace pcbench {
namespace {

namespace fs = std::filesystem;

constexpr std::uint32_t kSize = 32;
constexpr std::uint32_t kReplicates = 8;

// The "renderer": radiance 0.5, 0.8, 1.1 per channel plus uniform noise of ±`noise`, times
// `scale` inside the tile at (8..15, 8..15) of channel 0.
std::vector<float> render(std::uint32_t replicate, double noise, double tile_scale = 1.0,
                          std::uint64_t key = 7) {
  RandomStream rng({.key = key, .replicate = replicate});
  std::vector<float> pixels(std::size_t{kSize} * kSize * 3);
  for (std::uint32_t y = 0; y < kSize; ++y) {
    for (std::uint32_t x = 0; x < kSize; ++x) {
      for (std::uint32_t c = 0; c < 3; ++c) {
        double v = 0.5 + 0.3 * c + noise * (2.0 * rng.uniform() - 1.0);
        if (c == 0 && x >= 8 && x < 16 && y >= 8 && y < 16) v *= tile_scale;
        pixels[(std::size_t{y} * kSize + x) * 3 + c] = static_cast<float>(v);
      }
    }
  }
  return pixels;
}

// PFM by hand: OpenImageIO 2.4 reads PFM but has no writer for it. The format is a text header
// ("PF", width height, -1 for little-endian) and float RGB rows from the bottom up.
void write_pfm(const fs::path& path, const std::vector<float>& pixels, std::uint32_t width) {
  const std::size_t height = pixels.size() / 3 / width;
  std::ofstream out(path, std::ios::binary);
  out << "PF\n" << width << " " << height << "\n-1.0\n";
  for (std::size_t y = height; y-- > 0;) {
    out.write(reinterpret_cast<const char*>(&pixels[y * width * 3]),
              static_cast<std::streamsize>(width * 3 * sizeof(float)));
  }
}

void write(const fs::path& path, const std::vector<float>& pixels, OIIO::TypeDesc stored,
           std::uint32_t width = kSize) {
  if (path.extension() == ".pfm") return write_pfm(path, pixels, width);
  std::unique_ptr<OIIO::ImageOutput> out = OIIO::ImageOutput::create(path.string());
  ASSERT_TRUE(out) << OIIO::geterror();
  const OIIO::ImageSpec spec(static_cast<int>(width), static_cast<int>(pixels.size() / 3 / width),
                             3, stored);
  ASSERT_TRUE(out->open(path.string(), spec)) << out->geterror();
  ASSERT_TRUE(out->write_image(OIIO::TypeDesc::FLOAT, pixels.data())) << out->geterror();
  ASSERT_TRUE(out->close());
}

class ImageSetVerify : public ::testing::Test {
 protected:
  // R replicates named set/<stem>_<r>.<ext>.
  std::string write_set(const std::string& set, const std::string& ext, OIIO::TypeDesc stored,
                        double tile_scale = 1.0, std::uint64_t key = 7) {
    const fs::path folder = at(set);
    fs::create_directories(folder);
    for (std::uint32_t r = 0; r < kReplicates; ++r) {
      write(folder / fmt::format("r{}.{}", r, ext), render(r, 0.2, tile_scale, key), stored);
    }
    return folder.string();
  }
  fs::path at(const std::string& name) const { return folder_.path() / name; }

 private:
  TemporaryFolder folder_;
};

TEST_F(ImageSetVerify, EachFormatAgainstTheExactConstant) {
  for (const auto& [ext, stored] :
       {std::pair{"exr", OIIO::TypeDesc::FLOAT}, std::pair{"exr", OIIO::TypeDesc::HALF},
        std::pair{"pfm", OIIO::TypeDesc::FLOAT}, std::pair{"hdr", OIIO::TypeDesc::FLOAT}}) {
    const std::string name =
        fmt::format("{}{}", ext, stored == OIIO::TypeDesc::HALF ? "-half" : "");
    const std::string set = write_set(name, ext, stored);
    const CliResult r = cli({"verify", "--images", set, "--constant", "0.5,0.8,1.1", "-q", "--out",
                             at(name + "-report").string()});
    ASSERT_EQ(r.status, 0) << name << ": " << r.out << r.err;
    const nlohmann::json report = report_at(at(name + "-report"));
    const auto& c = report["comparisons"];
    // The comparison, then one 2×MDB self-check per scale of its pyramid, each flagged.
    const std::size_t scales = c[0]["scales"].size();
    EXPECT_EQ(scales, pyramid_block_sizes(kSize, kSize, 8).size());
    ASSERT_EQ(c.size(), 1 + scales);
    EXPECT_EQ(c[0]["result"], "consistent") << name;
    for (std::size_t s = 1; s <= scales; ++s) {
      EXPECT_EQ(c[s]["result"], "biased") << name << ": the 2xMDB self-check at scale " << s;
      EXPECT_EQ(c[s]["scales"].size(), scales);
    }
    const auto& sets = report["image_sets"];
    EXPECT_EQ(sets["files"].size(), kReplicates);
    EXPECT_EQ(sets["width"], kSize);
    const double quantisation = sets["worst_quantisation_bias"].get<double>();
    if (std::string(ext) == "hdr") {
      EXPECT_EQ(sets["files"][0]["pixel_type"], "rgbe");
      EXPECT_DOUBLE_EQ(quantisation, std::ldexp(1.0, -7));
    } else if (stored == OIIO::TypeDesc::HALF) {
      EXPECT_EQ(sets["files"][0]["pixel_type"], "half");
      EXPECT_DOUBLE_EQ(quantisation, std::ldexp(1.0, -11));
    } else {
      EXPECT_EQ(sets["files"][0]["pixel_type"], "float");
    }
    EXPECT_TRUE(fs::exists(at(name + "-report") / "images/images_zmap.exr"));
  }
}

TEST_F(ImageSetVerify, AKnownBiasIsFlaggedWherePowerAllows) {
  const std::string honest = write_set("honest", "exr", OIIO::TypeDesc::FLOAT);
  const std::string other =
      write_set("other", "pfm", OIIO::TypeDesc::FLOAT, 1.0, /*key=*/8);  // independent seeds
  const std::string biased = write_set("biased", "exr", OIIO::TypeDesc::FLOAT, 1.3);
  // Two independent honest sets agree.
  EXPECT_EQ(
      cli({"verify", "--images", honest, "--against", other, "-q", "--out", at("pair").string()})
          .status,
      0);
  const double mdb = report_at(at("pair"))["comparisons"][0]["tile_relative_mdb"].get<double>();
  // A 30% bias in one tile's red channel, above the detectable bias (14% with this noise and 8
  // replicates): flagged.
  ASSERT_LT(mdb, 0.3);
  const CliResult r = cli({"verify", "--images", biased, "--against", other, "--expect", "biased",
                           "-q", "--out", at("flagged").string()});
  EXPECT_EQ(r.status, 0) << r.out;
  EXPECT_EQ(report_at(at("flagged"))["comparisons"][0]["result"], "biased");
  // Expected consistent, it differs: exit 1.
  EXPECT_EQ(cli({"verify", "--images", biased, "--constant", "0.5,0.8,1.1", "-q", "--out",
                 at("differs").string()})
                .status,
            1);
}

TEST_F(ImageSetVerify, BadInputExitsTwoAndWritesNothing) {
  const std::string set = write_set("good", "exr", OIIO::TypeDesc::FLOAT);
  const std::string first = (fs::path(set) / "r0.exr").string();
  const std::string second = (fs::path(set) / "r1.exr").string();
  write(at("small.exr"), std::vector<float>(16 * 16 * 3, 1.0f), OIIO::TypeDesc::FLOAT, 16);
  std::ofstream(at("garbage.exr")) << "not an image";
  // A truncated copy of a real file.
  const std::uintmax_t size = fs::file_size(first);
  fs::copy_file(first, at("truncated.exr"));
  fs::resize_file(at("truncated.exr"), size / 2);
  write(at("ldr.png"), std::vector<float>(kSize * kSize * 3, 0.5f), OIIO::TypeDesc::UINT8);

  const std::vector<std::pair<std::vector<std::string>, std::string>> cases = {
      {{"--images", first, "--constant", "1"}, "at least 2"},
      {{"--images", first + "," + first, "--constant", "1"}, "hold the same pixels"},
      {{"--images", first + "," + at("small.exr").string(), "--constant", "1"}, "is 16x16"},
      {{"--images", first + "," + at("garbage.exr").string(), "--constant", "1"}, "cannot be read"},
      {{"--images", first + "," + at("truncated.exr").string(), "--constant", "1"},
       "truncated.exr"},
      {{"--images", first + "," + at("ldr.png").string(), "--constant", "1"}, "radiance images"},
      {{"--images", set, "--constant", "1", "--channels", "R,G,A"}, "no channel 'A'"},
      {{"--images", set}, "exactly one of"},
      {{"--images", set, "--constant", "1", "--against", set}, "exactly one of"},
      {{"--images", set, "--constant", "x"}, "not a finite number"},
      {{"--images", set, "--constant", "1,2"}, "R,G,B"},
      {{"--images", set, "--constant", "1", "--crop", "30,30,8,8"}, "not inside"},
      {{"--images", at("nothing-*.exr").string(), "--constant", "1"}, "matches no file"},
      {{"--images", set, "--reference-stderr", first, "--constant", "1"}, "--reference-image"},
      {{"-e", "plain", "-i", "cornell", "--constant", "1"}, "go with --images"},
      {{"--images", set, "--constant", "1", "--require-mdb", "image=1.5"},
       "not a fraction in (0, 1)"},
      {{"--images", set, "--constant", "1", "--require-mdb", "24=0.05"},
       "not a scale of the pyramid"},
      {{"--images", set, "--constant", "1", "--require-mdb", "whole=0.05"}, "tile (the finest"},
      {{"--images", set, "--constant", "1", "--require-mdb", "image"}, "SCALE=FRACTION"},
  };
  for (const auto& [args, message] : cases) {
    std::vector<std::string> command = {"verify"};
    command.insert(command.end(), args.begin(), args.end());
    command.insert(command.end(), {"-q", "--out", at("out").string()});
    const CliResult r = cli(command);
    EXPECT_EQ(r.status, 2) << message << "\n" << r.err;
    EXPECT_NE(r.err.find(message), std::string::npos) << r.err;
    // Not even the folder: it is made only once the input has been read and checked.
    EXPECT_FALSE(fs::exists(at("out"))) << message;
  }
}

// A folder given as a set holds replicates only: pcbench's own statistics images beside them
// (its images/ folder) or the replicates of two runs are refused, naming the files.
TEST_F(ImageSetVerify, AFolderHoldsReplicatesOnly) {
  const std::string set = write_set("folder", "exr", OIIO::TypeDesc::FLOAT);
  write(fs::path(set) / "run1_mean.exr", render(0, 0.0), OIIO::TypeDesc::FLOAT);
  write(fs::path(set) / "run1_stderr.exr", render(1, 0.0), OIIO::TypeDesc::FLOAT);
  const CliResult mixed = cli({"verify", "--images", set, "--constant", "0.5,0.8,1.1", "-q",
                               "--out", at("mixed").string()});
  EXPECT_EQ(mixed.status, 2) << mixed.out;
  EXPECT_NE(mixed.err.find("run1_mean.exr, run1_stderr.exr"), std::string::npos) << mixed.err;
  EXPECT_NE(mixed.err.find("not replicates"), std::string::npos) << mixed.err;
  EXPECT_FALSE(fs::exists(at("mixed")));

  const fs::path runs = at("two-runs");
  fs::create_directories(runs);
  for (std::uint32_t r = 0; r < 2; ++r) {
    write(runs / fmt::format("aaa_rep{}.exr", r), render(r, 0.2), OIIO::TypeDesc::FLOAT);
    write(runs / fmt::format("bbb_rep{}.exr", r), render(r + 2, 0.2), OIIO::TypeDesc::FLOAT);
  }
  const CliResult two = cli({"verify", "--images", runs.string(), "--constant", "0.5,0.8,1.1", "-q",
                             "--out", at("two").string()});
  EXPECT_EQ(two.status, 2);
  EXPECT_NE(two.err.find("the replicates of 2 runs (aaa, bbb)"), std::string::npos) << two.err;
}

// The same files, or copies of them, on both sides: bad input, not a tight "consistent".
TEST_F(ImageSetVerify, ASetAgainstItselfIsRefused) {
  const std::string set = write_set("self", "exr", OIIO::TypeDesc::FLOAT);
  const CliResult same =
      cli({"verify", "--images", set, "--against", set, "-q", "--out", at("same").string()});
  EXPECT_EQ(same.status, 2) << same.out;
  EXPECT_NE(same.err.find("hold the same image"), std::string::npos) << same.err;
  // One copied file among independent ones is enough.
  const std::string other = write_set("self-other", "exr", OIIO::TypeDesc::FLOAT, 1.0, 8);
  fs::copy_file(fs::path(set) / "r3.exr", fs::path(other) / "r3.exr",
                fs::copy_options::overwrite_existing);
  const CliResult copy =
      cli({"verify", "--images", set, "--against", other, "-q", "--out", at("copy").string()});
  EXPECT_EQ(copy.status, 2);
  EXPECT_NE(copy.err.find("r3.exr"), std::string::npos) << copy.err;
  EXPECT_FALSE(fs::exists(at("same")));
  EXPECT_FALSE(fs::exists(at("copy")));
}

// The report's whole-image figures are the sets' own: means over pixels and channels, their
// standard errors across replicates, both counts, the whole-image t and its dof.
TEST_F(ImageSetVerify, WholeImageFiguresOfBothSides) {
  const std::string set = write_set("figures", "exr", OIIO::TypeDesc::FLOAT);
  const std::string other = write_set("figures-other", "exr", OIIO::TypeDesc::FLOAT, 1.0, 8);
  ASSERT_EQ(cli({"verify", "--images", set, "--against", other, "-q", "--out", at("pair").string()})
                .status,
            0);
  const nlohmann::json pair = report_at(at("pair"))["comparisons"][0];
  // Radiance 0.8 on average, uniform noise of ±0.2 (sd 0.2/√3 per value) over 3072 values: the
  // whole-image mean's standard error is about 0.0021 per replicate / √8 = 0.00074.
  EXPECT_NEAR(pair["mean_a"].get<double>(), 0.8, 0.005);
  EXPECT_NEAR(pair["mean_b"].get<double>(), 0.8, 0.005);
  EXPECT_GT(pair["stderr_a"].get<double>(), 0.0003);
  EXPECT_LT(pair["stderr_a"].get<double>(), 0.0015);
  EXPECT_GT(pair["stderr_b"].get<double>(), 0.0003);
  EXPECT_EQ(pair["replicates_a"], kReplicates);
  EXPECT_EQ(pair["replicates_b"], kReplicates);
  EXPECT_GT(pair["dof"].get<double>(), kReplicates - 1.0);
  EXPECT_DOUBLE_EQ(pair["statistic"].get<double>(),
                   (pair["mean_a"].get<double>() - pair["mean_b"].get<double>()) /
                       std::hypot(pair["stderr_a"].get<double>(), pair["stderr_b"].get<double>()));
  ASSERT_EQ(cli({"verify", "--images", set, "--constant", "0.5,0.8,1.1", "-q", "--out",
                 at("exact").string()})
                .status,
            0);
  const nlohmann::json exact = report_at(at("exact"))["comparisons"][0];
  EXPECT_NEAR(exact["mean_b"].get<double>(), (0.5 + 0.8 + 1.1) / 3.0, 1e-12);  // summed pixels
  EXPECT_EQ(exact["stderr_b"].get<double>(), 0.0);
  EXPECT_EQ(exact["replicates_b"], 0);
  EXPECT_EQ(exact["dof"].get<double>(), kReplicates - 1.0);
}

// An unmet power requirement says "not met" with the factor, the median beside the worst block,
// self-checks in words of their own; --fail-underpowered turns an unmet requirement into exit 4.
TEST_F(ImageSetVerify, PowerRequirementsInPlainWords) {
  const std::string set = write_set("power", "exr", OIIO::TypeDesc::FLOAT);
  // 0.01% over the image is far below what 8 replicates of this noise detect.
  const std::vector<std::string> command = {"verify",       "--images",    set,
                                            "--constant",   "0.5,0.8,1.1", "--require-mdb",
                                            "image=0.0001", "--out",       ""};
  auto with_out = [&](const std::string& out, bool fail) {
    std::vector<std::string> c = command;
    c.back() = at(out).string();
    if (fail) c.push_back("--fail-underpowered");
    return cli(c);
  };
  const CliResult loose = with_out("loose", false);
  EXPECT_EQ(loose.status, 0) << loose.out << loose.err;
  EXPECT_NE(loose.out.find("required ≤ 0.01%: not met; needs"), std::string::npos) << loose.out;
  EXPECT_EQ(loose.out.find("met at about"), std::string::npos) << loose.out;
  const nlohmann::json report = report_at(at("loose"));
  const auto& c = report["comparisons"];
  EXPECT_FALSE(c[0]["requirements_met"].get<bool>());
  // The median beside the worst, per scale.
  EXPECT_NE(loose.out.find("(worst bright block; median "), std::string::npos) << loose.out;
  for (const auto& scale : c[0]["scales"]) {
    EXPECT_GT(scale["median_relative_mdb"].get<double>(), 0.0);
    EXPECT_LE(scale["median_relative_mdb"].get<double>(), scale["relative_mdb"].get<double>());
  }
  // One line per self-check, each saying it is one and that it behaved as expected; no line
  // reads as a finding.
  std::size_t self_checks = 0;
  for (std::size_t at_line = 0;
       (at_line = loose.out.find("self-check (block", at_line)) != std::string::npos; ++at_line) {
    ++self_checks;
  }
  EXPECT_EQ(self_checks, c.size() - 1);
  EXPECT_EQ(loose.out.find("): biased"), std::string::npos) << loose.out;
  EXPECT_NE(loose.out.find(": flagged, as expected ("), std::string::npos) << loose.out;

  const CliResult strict = with_out("strict", true);
  EXPECT_EQ(strict.status, 4) << strict.out;
  EXPECT_NE(strict.out.find("--fail-underpowered"), std::string::npos) << strict.out;
  // Requirements that are met pass under --fail-underpowered.
  const CliResult met =
      cli({"verify", "--images", set, "--constant", "0.5,0.8,1.1", "--require-mdb", "tile=0.9",
           "--require-mdb", "image=0.5", "--fail-underpowered", "-q", "--out", at("met").string()});
  EXPECT_TRUE(report_at(at("met"))["comparisons"][0]["requirements_met"].get<bool>()) << met.out;
  EXPECT_EQ(met.status, 0) << met.out;
}

// `--images renders/*.exr` unquoted: the shell hands pcbench every file as its own word, which
// is the same set as the quoted pattern; several words after --against are a set too.
TEST_F(ImageSetVerify, SeveralFilesAsTheShellExpandsAGlob) {
  const std::string set = write_set("expanded", "exr", OIIO::TypeDesc::FLOAT);
  const std::string other = write_set("expanded-other", "exr", OIIO::TypeDesc::FLOAT, 1.0, 8);
  std::vector<std::string> command = {"verify", "--images"};
  std::vector<std::string> against = {"--against"};
  for (std::uint32_t r = 0; r < kReplicates; ++r) {
    command.push_back((fs::path(set) / fmt::format("r{}.exr", r)).string());
    against.push_back((fs::path(other) / fmt::format("r{}.exr", r)).string());
  }
  command.insert(command.end(), against.begin(), against.end());
  command.insert(command.end(), {"-q", "--out", at("expanded-report").string()});
  const CliResult r = cli(command);
  ASSERT_EQ(r.status, 0) << r.out << r.err;
  const nlohmann::json report = report_at(at("expanded-report"));
  EXPECT_EQ(report["image_sets"]["files"].size(), kReplicates);
  EXPECT_EQ(report["image_sets"]["against"]["files"].size(), kReplicates);
  // With --estimates, --against is one file.
  const CliResult estimates = cli({"verify", "--estimates", "a.csv", "--against", "b.csv", "c.csv",
                                   "-q", "--out", at("estimates").string()});
  EXPECT_EQ(estimates.status, 2);
  EXPECT_NE(estimates.err.find("--against takes one file of estimates"), std::string::npos)
      << estimates.err;
}

// The same renders stored as RGBE differ from the float ones by RGBE's rounding, which quiet
// images and a whole-image test can see: flagged, and the reason names the format's rounding. A
// real bias far beyond the rounding is flagged without that note.
TEST_F(ImageSetVerify, RgbeRoundingIsNamedInTheReason) {
  const auto write_quiet = [&](const std::string& name, const char* ext, double scale) {
    fs::create_directories(at(name));
    for (std::uint32_t r = 0; r < kReplicates; ++r) {
      std::vector<float> pixels = render(r, 1e-3, 1.0, 9);
      for (float& v : pixels) v = static_cast<float>(v * scale);
      write(at(name) / fmt::format("r{}.{}", r, ext), pixels, OIIO::TypeDesc::FLOAT);
    }
    return at(name).string();
  };
  const std::string floats = write_quiet("quiet-float", "exr", 1.0);
  const std::string rgbe = write_quiet("quiet-rgbe", "hdr", 1.0);
  const std::string shifted = write_quiet("quiet-float-shifted", "exr", 1.02);
  const CliResult rounded = cli({"verify", "--images", rgbe, "--against", floats, "--expect",
                                 "biased", "-q", "--out", at("rgbe-report").string()});
  ASSERT_EQ(rounded.status, 0) << rounded.out << rounded.err;
  const nlohmann::json rounded_report = report_at(at("rgbe-report"));
  const auto& c = rounded_report["comparisons"][0];
  EXPECT_EQ(c["result"], "biased");
  EXPECT_NE(c["reason"].get<std::string>().find("the format's rounding, not the renderer"),
            std::string::npos)
      << c["reason"];
  EXPECT_NE(c["reason"].get<std::string>().find("RGBE: 2^-7 of a pixel's largest channel"),
            std::string::npos);
  const CliResult real = cli({"verify", "--images", shifted, "--against", floats, "--expect",
                              "biased", "-q", "--out", at("shifted-report").string()});
  ASSERT_EQ(real.status, 0) << real.out << real.err;
  const nlohmann::json real_report = report_at(at("shifted-report"));
  const auto& d = real_report["comparisons"][0];
  EXPECT_EQ(d["result"], "biased");
  EXPECT_EQ(d["reason"].get<std::string>().find("rounding, not the renderer"), std::string::npos)
      << d["reason"];
}

// A NaN pixel is a defect, never dropped: its tile fails (exit 1), and the report and the
// warning locate it. Negative values are counted.
TEST_F(ImageSetVerify, NonFiniteAndNegativePixelsAreLocated) {
  const fs::path folder = at("nan");
  fs::create_directories(folder);
  for (std::uint32_t r = 0; r < kReplicates; ++r) {
    std::vector<float> pixels = render(r, 0.2);
    if (r == 3)
      pixels[(std::size_t{5} * kSize + 9) * 3 + 1] = std::numeric_limits<float>::quiet_NaN();
    if (r == 4) pixels[0] = -0.25f;
    write(folder / fmt::format("r{}.exr", r), pixels, OIIO::TypeDesc::FLOAT);
  }
  const CliResult r = cli({"verify", "--images", folder.string(), "--constant", "0.5,0.8,1.1", "-q",
                           "--out", at("report").string()});
  EXPECT_EQ(r.status, 1) << r.out;
  EXPECT_NE(r.err.find("r3.exr: 1 NaN or infinite value(s), the first at pixel (9, 5)"),
            std::string::npos)
      << r.err;
  EXPECT_NE(r.err.find("r4.exr: 1 negative value(s)"), std::string::npos) << r.err;
  const nlohmann::json report = report_at(at("report"));
  const auto& files = report["image_sets"]["files"];
  EXPECT_EQ(files[3]["nonfinite"], 1);
  EXPECT_EQ(files[3]["first_nonfinite"]["x"], 9);
  EXPECT_EQ(files[3]["first_nonfinite"]["y"], 5);
  EXPECT_EQ(files[4]["negative"], 1);
  EXPECT_EQ(report["comparisons"][0]["result"], "biased");
}

TEST_F(ImageSetVerify, CropAndChannels) {
  const std::string set = write_set("crop", "exr", OIIO::TypeDesc::FLOAT);
  ASSERT_EQ(cli({"verify", "--images", set, "--constant", "0.5", "--channels", "R,R,R", "--crop",
                 "16,0,16,16", "--tile", "4", "-q", "--out", at("report").string()})
                .status,
            0);
  const nlohmann::json report = report_at(at("report"));
  EXPECT_EQ(report["image_sets"]["width"], 16);
  EXPECT_EQ(report["image_sets"]["height"], 16);
  EXPECT_EQ(report["image_sets"]["tile"], 4);
}

// pcbench's own replicates, exported, verified through --images: the same verdicts as the
// in-process tile tests; a 1% global scale error is flagged where the reported detectable bias
// says the test can see it.
TEST_F(ImageSetVerify, RoundTripOfPcbenchReplicates) {
  const CliResult run =
      cli({"run", "-e", "pt,plain", "-i", "furnace", "-p", "resolution=16", "-n", "64", "-r", "8",
           "--replicate-images", "-q", "--out", at("run").string()});
  ASSERT_EQ(run.status, 0) << run.out << run.err;
  const nlohmann::json report = report_at(at("run"));
  const std::string pt = report["runs"][0]["id"], plain = report["runs"][1]["id"];
  const auto& files = report["runs"][0]["image"]["files"];
  ASSERT_EQ(files["replicates"].size(), 8u);
  const std::string images = (at("run") / "images").string();
  const std::string pt_set = images + "/" + pt + "_rep*.exr";
  const std::string exact = (at("run") / files["reference"].get<std::string>()).string();
  ASSERT_EQ(cli({"verify", "--images", pt_set, "--reference-image", exact, "-q", "--out",
                 at("exact").string()})
                .status,
            0);
  ASSERT_EQ(cli({"verify", "--images", pt_set, "--against", images + "/" + plain + "_rep*.exr",
                 "-q", "--out", at("pair").string()})
                .status,
            0);
  // The in-process verdicts agree.
  for (const auto& c : report["comparisons"]) {
    if (c["a"] == pt && (c["b"] == "exact" || c["b"] == plain)) {
      EXPECT_EQ(c["result"], "consistent");
    }
  }
  // Every replicate scaled by 1.01, rewritten: flagged, since the detectable bias is below 1%.
  const double mdb = report_at(at("exact"))["comparisons"][0]["tile_relative_mdb"].get<double>();
  ASSERT_LT(mdb, 0.01) << "the round trip's power: a 1% scale error must be detectable";
  fs::create_directories(at("scaled"));
  for (std::size_t k = 0; k < 8; ++k) {
    const Image image = read_image_file(fmt::format("{}/{}_rep{}.exr", images, pt, k), {});
    std::vector<float> pixels(image.values.size());
    for (std::size_t i = 0; i < pixels.size(); ++i) {
      pixels[i] = static_cast<float>(1.01 * image.values[i]);
    }
    write(at("scaled") / fmt::format("r{}.exr", k), pixels, OIIO::TypeDesc::FLOAT, 16);
  }
  const CliResult scaled =
      cli({"verify", "--images", at("scaled").string(), "--reference-image", exact, "--expect",
           "biased", "-q", "--out", at("flagged").string()});
  EXPECT_EQ(scaled.status, 0) << scaled.out;
}

}  // namespace
}  // namespace pcbench
