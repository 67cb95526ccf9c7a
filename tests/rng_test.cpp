#include "base/rng.h"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <random>
#include <set>
#include <vector>

#include "base/philox_lanes.h"
#include "tests/test_support.h"

namespace pcbench {
namespace {

// Known-answer vectors of Philox4x32-10 from Random123's kat_vectors.
TEST(RngPhilox, MatchesRandom123KnownAnswers) {
  EXPECT_EQ(philox4x32_10({0, 0, 0, 0}, {0, 0}),
            (PhiloxCounter{0x6627e8d5u, 0xe169c58du, 0xbc57ac4cu, 0x9b00dbd8u}));
  EXPECT_EQ(philox4x32_10({0xffffffffu, 0xffffffffu, 0xffffffffu, 0xffffffffu},
                          {0xffffffffu, 0xffffffffu}),
            (PhiloxCounter{0x408f276du, 0x41c83b0eu, 0xa20bc7c6u, 0x6d5451fdu}));
  EXPECT_EQ(philox4x32_10({0x243f6a88u, 0x85a308d3u, 0x13198a2eu, 0x03707344u},
                          {0xa4093822u, 0x299f31d0u}),
            (PhiloxCounter{0xd16cfe09u, 0x94fdccebu, 0x5001e420u, 0x24126ea1u}));
}

// The SIMD lanes give each counter's block exactly, for every count around the lane width (the
// tail of a partial group included).
TEST(RngPhilox, ManyMatchesOneByOne) {
  const PhiloxKey key{0xa4093822u, 0x299f31d0u};
  // Around both lane widths (8 and 16), with and without a padded tail.
  for (std::size_t n : {0u, 1u, 7u, 8u, 9u, 15u, 16u, 17u, 23u, 31u, 32u, 33u, 64u}) {
    std::vector<PhiloxCounter> counters(n), out(n);
    for (std::uint32_t i = 0; i < n; ++i) counters[i] = {i * 2654435761u, i, ~i, 0x5a5a0000u + i};
    philox4x32_10_many(counters, key, out);
    for (std::size_t i = 0; i < n; ++i) EXPECT_EQ(out[i], philox4x32_10(counters[i], key)) << i;
    for (const PhiloxLanes lanes :
         {PhiloxLanes::kScalar, PhiloxLanes::kAvx2, PhiloxLanes::kAvx512}) {
      if (!philox_lanes_supported(lanes)) continue;
      std::vector<PhiloxCounter> with(n);
      philox4x32_10_many_with(lanes, counters, key, with);
      EXPECT_EQ(with, out) << "lanes " << static_cast<int>(lanes) << ", n = " << n;
    }
  }
}

// A stream's blocks and numbers in lanes are each consecutive counter's block and its two
// uniforms, for every group size (each tail: one block at a time, one to four vectors), with
// every way this machine has, and across word 0's wrap.
TEST(RngPhilox, UniformsMatchOneByOne) {
  const PhiloxKey key{0x3c6ef372u, 0xa54ff53au};
  for (const std::uint32_t start : {0u, 0xfffffff5u}) {
    const PhiloxCounter first{start, 17u, 0x0badf00du, 0x03000005u};
    for (std::size_t n = 1; n <= kPhiloxUniformGroup; ++n) {
      std::vector<PhiloxCounter> expected(n);
      std::vector<double> expected_u(2 * n);
      for (std::size_t i = 0; i < n; ++i) {
        PhiloxCounter c = first;
        c[0] += static_cast<std::uint32_t>(i);
        expected[i] = philox4x32_10(c, key);
        expected_u[2 * i] = RandomStream::uniform_of(expected[i], 0);
        expected_u[2 * i + 1] = RandomStream::uniform_of(expected[i], 2);
      }
      for (const PhiloxLanes lanes :
           {PhiloxLanes::kScalar, PhiloxLanes::kAvx2, PhiloxLanes::kAvx512}) {
        if (!philox_lanes_supported(lanes)) continue;
        std::vector<PhiloxCounter> blocks(n);
        std::vector<double> u(2 * n);
        philox_uniforms_with(lanes, first, key, blocks, u);
        EXPECT_EQ(blocks, expected) << "lanes " << static_cast<int>(lanes) << ", n = " << n;
        EXPECT_EQ(u, expected_u) << "lanes " << static_cast<int>(lanes) << ", n = " << n;
      }
    }
  }
}

// Every way this machine has ran above: say which, so that a log shows what was covered.
TEST(RngPhilox, LanesThisMachineHas) {
  EXPECT_TRUE(philox_lanes_supported(PhiloxLanes::kScalar));
  std::printf("philox lanes: avx2 %d, avx512 %d\n", philox_lanes_supported(PhiloxLanes::kAvx2),
              philox_lanes_supported(PhiloxLanes::kAvx512));
}

// A stream handed its first block gives the numbers of the stream that computes it.
TEST(RngStream, PrecomputedFirstBlockGivesTheSameNumbers) {
  const StreamId id{.key = 0x123456789abcdefull,
                    .replicate = 3,
                    .purpose = StreamPurpose::kLightPool,
                    .sample = 9,
                    .path = 2};
  const PhiloxCounter first = RandomStream::first_counter(id);
  std::vector<PhiloxCounter> block(1);
  philox4x32_10_many(std::span(&first, 1), RandomStream::key_of(id), block);
  RandomStream a(id), b(id, block[0]);
  for (int i = 0; i < 20; ++i) {
    EXPECT_EQ(a.uniform(), b.uniform());
    EXPECT_EQ(a.uniform_index(1000), b.uniform_index(1000));
  }
}

// The streams of consecutive samples, first blocks computed a group at a time, are the streams
// each sample's id makes: across group boundaries and past the count asked for.
TEST(RngStream, SampleStreamsAreEachSamplesStream) {
  StreamId id{.key = 0xfeedfacecafebeefull,
              .replicate = 5,
              .purpose = StreamPurpose::kResampling,
              .path = 0};
  for (std::uint32_t count : {1u, 63u, 64u, 65u, 130u}) {
    SampleStreams streams(id, 1000, count);
    for (std::uint32_t i = 0; i < count + 3; ++i) {
      RandomStream batched = streams.next();
      id.sample = 1000 + i;
      RandomStream one(id);
      for (int k = 0; k < 5; ++k) EXPECT_EQ(batched.uniform(), one.uniform()) << count << " " << i;
      EXPECT_EQ(batched.uniform_index(17), one.uniform_index(17));
    }
  }
}

// uniforms(out) gives the numbers uniform() gives one at a time and leaves the stream where they
// leave it: from every position within a block (after uniform_index's single words too), for
// counts across its group of blocks, and followed by either kind of draw.
TEST(RngStream, BulkUniformsAreTheOneByOneNumbers) {
  const StreamId id{
      .key = 0x5eed, .replicate = 2, .purpose = StreamPurpose::kCameraPath, .sample = 4, .path = 1};
  for (int lead = 0; lead < 4; ++lead) {
    for (std::size_t count : {0u, 1u, 2u, 3u, 7u, 9u, 11u, 17u, 25u, 33u, 63u, 64u, 65u, 200u}) {
      RandomStream bulk(id), one(id);
      for (int k = 0; k < lead; ++k) {  // single words shift the position by one
        EXPECT_EQ(bulk.uniform_index(97), one.uniform_index(97));
      }
      std::vector<double> out(count);
      bulk.uniforms(out);
      for (std::size_t i = 0; i < count; ++i) {
        EXPECT_EQ(out[i], one.uniform()) << lead << " " << count << " " << i;
      }
      for (int k = 0; k < 3; ++k) {
        EXPECT_EQ(bulk.uniform(), one.uniform()) << lead << " " << count;
        EXPECT_EQ(bulk.uniform_index(1000), one.uniform_index(1000)) << lead << " " << count;
      }
    }
  }
}

// A stream's numbers are its blocks in counter order, read as rng.h says, however they were
// computed (one at a time, or several ahead in lanes after read_ahead()): a model made of
// philox4x32_10 alone, against a long mix of uniform(), uniform_index() and uniforms() that crosses
// many refills.
TEST(RngStream, NumbersAreItsBlocksInCounterOrder) {
  struct Model {
    PhiloxKey key;
    PhiloxCounter counter;
    PhiloxCounter block{};
    int next = 4;
    void refill() {
      block = philox4x32_10(counter, key);
      ++counter[0];
      next = 0;
    }
    double uniform() {
      if (next > 2) refill();
      const double u = RandomStream::uniform_of(block, next);
      next += 2;
      return u;
    }
    std::uint32_t uniform_index(std::uint32_t n) {
      if (next >= 4) refill();
      return static_cast<std::uint32_t>((std::uint64_t{block[next++]} * n) >> 32);
    }
  };
  const StreamId id{
      .key = 0xa5a5, .replicate = 7, .purpose = StreamPurpose::kCameraPath, .sample = 3, .path = 9};
  for (const bool ahead : {false, true}) {
    RandomStream stream(id);
    if (ahead) stream.read_ahead();
    Model model{RandomStream::key_of(id), RandomStream::first_counter(id)};
    std::mt19937 choose(2024);
    std::vector<double> bulk;
    for (int op = 0; op < 3000; ++op) {
      switch (choose() % 3) {
        case 0:
          ASSERT_EQ(stream.uniform(), model.uniform()) << ahead << " " << op;
          break;
        case 1:
          ASSERT_EQ(stream.uniform_index(1000003), model.uniform_index(1000003))
              << ahead << " " << op;
          break;
        default:
          bulk.resize(choose() % 40);
          stream.uniforms(bulk);
          for (double u : bulk) ASSERT_EQ(u, model.uniform()) << ahead << " " << op;
          break;
      }
    }
  }
}

TEST(RngStream, SameIdGivesSameNumbers) {
  const StreamId id{
      .key = 42, .replicate = 3, .purpose = StreamPurpose::kCameraPath, .sample = 17, .path = 5};
  RandomStream a(id), b(id);
  for (int i = 0; i < 100; ++i) EXPECT_EQ(a.uniform(), b.uniform());
}

TEST(RngStream, EveryFieldOfTheIdChangesTheNumbers) {
  const StreamId base{
      .key = 42, .replicate = 3, .purpose = StreamPurpose::kLightPool, .sample = 17, .path = 5};
  std::vector<StreamId> ids(6, base);
  ids[1].key = 43;
  ids[2].replicate = 4;
  ids[3].purpose = StreamPurpose::kResampling;
  ids[4].sample = 18;
  ids[5].path = 6;
  std::set<double> firsts;
  for (const StreamId& id : ids) firsts.insert(RandomStream(id).uniform());
  EXPECT_EQ(firsts.size(), ids.size());
}

TEST(RngStream, UniformsLieInTheUnitInterval) {
  RandomStream rng({.key = 9});
  for (int i = 0; i < 100000; ++i) {
    const double u = rng.uniform();
    ASSERT_GE(u, 0.0);
    ASSERT_LT(u, 1.0);
  }
}

// Chi-square test of uniformity over 64 bins; false-alarm budget 1e-6 for this fixed seed.
TEST(RngStream, UniformsPassChiSquare) {
  constexpr int kBins = 64;
  constexpr int kDraws = 640000;
  std::vector<double> counts(kBins, 0.0);
  RandomStream rng({.key = 2024, .purpose = StreamPurpose::kResampling});
  for (int i = 0; i < kDraws; ++i) counts[static_cast<std::size_t>(rng.uniform() * kBins)] += 1.0;
  EXPECT_GT(chi_square_uniform_p_value(counts), 1e-6);
}

// Neighbouring streams (consecutive samples, as the runner uses them) must not be correlated:
// the Pearson correlation of their first uniforms over many pairs is ~N(0, 1/n).
TEST(RngStream, NeighbouringStreamsAreUncorrelated) {
  constexpr int kPairs = 100000;
  double sum_xy = 0, sum_x = 0, sum_y = 0, sum_xx = 0, sum_yy = 0;
  for (std::uint32_t s = 0; s < kPairs; ++s) {
    const double x = RandomStream({.key = 5, .sample = s}).uniform();
    const double y = RandomStream({.key = 5, .sample = s + 1}).uniform();
    sum_xy += x * y;
    sum_x += x;
    sum_y += y;
    sum_xx += x * x;
    sum_yy += y * y;
  }
  const double n = kPairs;
  const double r = (sum_xy - sum_x * sum_y / n) /
                   std::sqrt((sum_xx - sum_x * sum_x / n) * (sum_yy - sum_y * sum_y / n));
  // |z| > 5 has probability 6e-7 under independence.
  EXPECT_LT(std::fabs(r * std::sqrt(n)), 5.0);
}

TEST(RngStream, UniformIndexCoversItsRange) {
  RandomStream rng({.key = 11});
  std::vector<int> seen(7, 0);
  for (int i = 0; i < 7000; ++i) {
    const std::uint32_t k = rng.uniform_index(7);
    ASSERT_LT(k, 7u);
    ++seen[k];
  }
  for (int count : seen) EXPECT_GT(count, 800);
}

}  // namespace
}  // namespace pcbench
