// The enum name tables and the round-trip number format: every name parses
// back to its value, every unknown name gets the one message that names the
// field, the text and the names; numbers read back exactly.
#include "sampler/enum_names.h"

#include <gtest/gtest.h>

#include <charconv>
#include <cmath>
#include <cstdlib>
#include <stdexcept>
#include <string>
#include <vector>

#include "sampler/bluenoise/blue_noise_sets.h"
#include "sampler/bluenoise/gaussian_blue_noise.h"
#include "sampler/bluenoise/sliced_ot.h"
#include "sampler/io/round_trip.h"
#include "sampler/loss/boxes.h"
#include "sampler/optimize/optimizer.h"
#include "sampler/point.h"
#include "sampler/sequences/rng.h"
#include "sampler/sequences/sequence.h"

namespace nuld {
namespace {

std::string parseError(const auto &table, const std::string &text) {
  try {
    table.parse(text);
  } catch (const std::invalid_argument &e) {
    return e.what();
  }
  ADD_FAILURE() << "accepted '" << text << "'";
  return "";
}

// Every name, aliases included, parses to a value whose name parses back to it.
template <class E, std::size_t N>
void expectRoundTrips(const EnumTable<E, N> &table) {
  for (const auto &entry : table.entries) {
    SCOPED_TRACE(std::string(entry.name));
    EXPECT_TRUE(table.parse(entry.name) == entry.value);
    EXPECT_TRUE(table.parse(table.name(entry.value)) == entry.value);
  }
}

TEST(EnumNames, JoinsAlternativesInProse) {
  EXPECT_EQ(joinAlternatives({"a"}), "a");
  EXPECT_EQ(joinAlternatives({"a", "b"}), "a or b");
  EXPECT_EQ(joinAlternatives({"a", "b", "c"}), "a, b or c");
}

TEST(EnumNames, EveryNameRoundTrips) {
  expectRoundTrips(kDomainNames);
  expectRoundTrips(kBoxKindNames);
  expectRoundTrips(kSequenceKindNames);
  expectRoundTrips(kScrambleNames);
  expectRoundTrips(kMappingNames);
  expectRoundTrips(kObjectiveNames);
  expectRoundTrips(kUniformSotDomainNames);
  expectRoundTrips(kBlueNoiseBoundaryNames);
  expectRoundTrips(kBlueNoiseNames);
}

TEST(EnumNames, AliasesParseButAreNotListed) {
  EXPECT_EQ(parseBoxKind("two-point"), BoxKind::TwoPoint);
  EXPECT_EQ(toString(BoxKind::TwoPoint), "twopoint");
  EXPECT_EQ(parseEnum<SequenceKind>("independent"), SequenceKind::Random);
  EXPECT_EQ(
      kSequenceKindNames.names(),
      (std::vector<std::string>{"sobol", "halton", "random", "stratified", "pmj02", "lattice"}));
  EXPECT_EQ(kBoxKindNames.expected(), "multicorner, anchored or twopoint");
}

TEST(EnumNames, UnknownNamesGetOneMessage) {
  EXPECT_EQ(parseError(kBoxKindNames, "cube"),
            "unknown box kind 'cube' (expected multicorner, anchored or twopoint)");
  EXPECT_EQ(parseError(kScrambleNames, "xor"),
            "unknown scrambling 'xor' (expected owen, shift, cp, baker or none)");
  EXPECT_EQ(parseError(kDomainNames, "torus"),
            "unknown domain 'torus' (expected square, sphere or hemisphere)");
  EXPECT_EQ(parseError(kUniformSotDomainNames, "ball"),
            "unknown uniform domain 'ball' (expected disc or square)");
  // A likely typo gets the closest name (an edit distance of a third of the
  // word or less); far from every name, none.
  EXPECT_EQ(parseError(kBlueNoiseNames, "sot-warped"),
            "unknown blue-noise method 'sot-warped' (did you mean 'sot-mapped'?) (expected sot, "
            "sot-mapped, gbn or gbn-mapped)");
  EXPECT_EQ(
      parseError(kScrambleNames, "owem"),
      "unknown scrambling 'owem' (did you mean 'owen'?) (expected owen, shift, cp, baker or none)");
  EXPECT_THROW(parseObjective("l3"), std::invalid_argument);
  EXPECT_THROW(parseMapping(""), std::invalid_argument);
}

TEST(EnumNames, BlueNoiseRequestsKeepTheirNames) {
  for (const std::string &name : kBlueNoiseNames.names())
    EXPECT_EQ(parseBlueNoiseName(name).name(), name);
  EXPECT_TRUE(parseBlueNoiseName("gbn-mapped").mapped);
  EXPECT_EQ(parseBlueNoiseName("gbn").method, BlueNoiseMethod::Gaussian);
}

// The shortest spelling (as point-set files have always written), and the
// old 17-digit spellings of settings read back as the same double.
TEST(RoundTrip, ShortestTextReadsBackExactly) {
  EXPECT_EQ(formatRoundTrip(0.1), "0.1");
  EXPECT_EQ(formatRoundTrip(5e-7), "5e-07");
  EXPECT_EQ(formatRoundTrip(2000), "2000");
  EXPECT_EQ(formatRoundTrip(-0.25), "-0.25");
  EXPECT_EQ(std::strtod("0.10000000000000001", nullptr), 0.1);
  EXPECT_EQ(std::strtod("4.9999999999999998e-07", nullptr), 5e-7);
  Rng rng(7);
  for (int k = 0; k < 1000; ++k) {
    const double v = (rng.uniform() - 0.5) * std::pow(10.0, int(rng.uniform() * 40) - 20);
    const std::string text = formatRoundTrip(v);
    EXPECT_EQ(std::strtod(text.c_str(), nullptr), v) << text;
    char buf[32];
    EXPECT_EQ(std::string(buf, std::to_chars(buf, buf + sizeof buf, v).ptr), text);
  }
}

}  // namespace
}  // namespace nuld
