// The job of ranks as a single process sees it (no launcher: rank 0 of 1),
// and the byte records results travel in between ranks. The multi-rank
// behaviour is checked end to end under mpirun (tests/tools/mpi_test.sh).

#include "backends/ranks.h"

#include <gtest/gtest.h>

#include <stdexcept>

namespace nuld::study {
namespace {

TEST(Ranks, WithoutALauncherTheJobIsOneProcess) {
  const Ranks &ranks = Ranks::world();
  EXPECT_EQ(ranks.rank(), 0);
  EXPECT_EQ(ranks.size(), 1);
  EXPECT_TRUE(ranks.root());
  EXPECT_FALSE(ranks.distributed());
  EXPECT_EQ(ranks.broadcast("abc"), "abc");
  EXPECT_EQ(ranks.gather("xyz"), std::vector<std::string>{"xyz"});
  ranks.barrier();
}

// In a single process each task is run and collected in turn, in order.
TEST(Ranks, RoundsRunAndCollectEveryTaskInOrder) {
  std::vector<std::string> events;
  runInRounds(
      Ranks::world(), 4,
      [&](std::size_t i) {
        events.push_back("run " + std::to_string(i));
        return std::to_string(i * i);
      },
      [&](std::size_t i, const std::string &bytes) {
        events.push_back("collect " + std::to_string(i) + "=" + bytes);
      });
  EXPECT_EQ(events, (std::vector<std::string>{"run 0", "collect 0=0", "run 1", "collect 1=1",
                                              "run 2", "collect 2=4", "run 3", "collect 3=9"}));
  runInRounds(
      Ranks::world(), 0, [](std::size_t) -> std::string { throw std::logic_error("no task"); },
      [](std::size_t, const std::string &) { FAIL(); });
}

TEST(ByteRecords, EveryKindRoundTrips) {
  Image image{3, 2, 3, {}};
  for (int i = 0; i < 18; ++i) image.pixels.push_back(0.5f * float(i) - 1e-30f);
  PointSet set;
  set.n = 2;
  set.points = {{0.1, 0.2}, {0.3, 0.4}, {0.5, 0.6}, {0.7, 0.875}};
  set.metadata = {{"target", "uniform"}, {"empty", ""}};
  const std::vector<std::string> row{"a", "", "c,d"};
  const std::string bytes =
      ByteWriter().put(1.25).put(std::size_t(7)).put(true).put(row).put(image).put(set).take();

  ByteReader r(bytes);
  EXPECT_EQ(r.get<double>(), 1.25);
  EXPECT_EQ(r.get<std::size_t>(), 7u);
  EXPECT_TRUE(r.get<bool>());
  EXPECT_EQ(r.get<std::vector<std::string>>(), row);
  const Image back = r.get<Image>();
  EXPECT_EQ(back.width, 3);
  EXPECT_EQ(back.height, 2);
  EXPECT_EQ(back.pixels, image.pixels);
  const PointSet backSet = r.get<PointSet>();
  EXPECT_EQ(backSet.n, 2u);
  EXPECT_EQ(backSet.points, set.points);
  EXPECT_EQ(backSet.metadata, set.metadata);
}

// A record cut short is an error that says so, never a read past its end.
TEST(ByteRecords, ATruncatedRecordIsRefused) {
  const std::string bytes = ByteWriter().put(std::vector<double>{1, 2, 3}).take();
  for (std::size_t cut : {std::size_t(0), std::size_t(4), bytes.size() - 1}) {
    const std::string part = bytes.substr(0, cut);
    ByteReader r(part);
    try {
      r.get<std::vector<double>>();
      FAIL() << "cut at " << cut;
    } catch (const std::runtime_error &e) {
      EXPECT_NE(std::string(e.what()).find("ended early"), std::string::npos);
    }
  }
}

}  // namespace
}  // namespace nuld::study
