// The shared set cache (tools/study/set_cache.h): keys by content, not path;
// entries that concurrent or killed writers never leave torn; list and clear.
#include "tools/study/set_cache.h"

#include <gtest/gtest.h>
#include <signal.h>
#include <sys/wait.h>
#include <unistd.h>

#include <chrono>
#include <cstdlib>
#include <filesystem>
#include <thread>

#include "sampler/io/image_io.h"
#include "sampler/io/pointset_io.h"
#include "sampler/io/pointset_metadata.h"
#include "sampler/targets/target_spec.h"
#include "tests/common/temp_dir.h"
#include "tools/study/optimized_sets.h"

namespace nuld::study {
namespace {

namespace fs = std::filesystem;
using test::TempDir;

// A small map with a bright patch (a non-uniform density).
Image skyImage() {
  Image img;
  img.width = 16, img.height = 8, img.channels = 3;
  img.pixels.assign(std::size_t(16) * 8 * 3, 0.2f);
  for (int c = 0; c < 3; ++c) img.at(5, 2, c) = 40.0f;
  return img;
}

OptimizerSettings settingsFor(const Target &t, std::size_t n = 8, int epochs = 20) {
  OptimizedSetsRequest r;
  r.n = n;
  r.instances = 2;
  r.epochs = epochs;
  return optimizerSettings(t, r);
}

TEST(SetCache, KeysFollowContentNotPath) {
  TempDir dir;
  fs::create_directories(dir / "rootA/envmaps");
  fs::create_directories(dir / "rootB/maps");
  const std::string a = (dir / "rootA/envmaps/sky.exr").string(),
                    b = (dir / "rootB/maps/copy.exr").string(),
                    changed = (dir / "rootB/maps/changed.exr").string();
  writeImage(a, skyImage());
  writeImage(b, skyImage());
  Image edited = skyImage();
  edited.at(9, 6, 1) = 0.3f;  // one pixel
  writeImage(changed, edited);

  const SetCache cache(dir / "cache");
  const auto ta = makeTarget("envmap:" + a), tb = makeTarget("envmap:" + b),
             tc = makeTarget("envmap:" + changed), tm = makeTarget("envmap-mean:" + a);
  const fs::path ea = cache.entry(*ta, settingsFor(*ta));
  EXPECT_EQ(cache.entry(*tb, settingsFor(*tb)).filename().string().substr(10),
            ea.filename().string().substr(9))
      << "the same key for the same map under another root";
  EXPECT_NE(cache.entry(*tc, settingsFor(*tc)), ea) << "one changed pixel";
  EXPECT_NE(cache.entry(*tm, settingsFor(*tm)), ea) << "another importance weighting";
  EXPECT_NE(cache.entry(*ta, settingsFor(*ta, 8, 21)), ea) << "another optimizer setting";
  EXPECT_NE(cache.entry(*ta, settingsFor(*ta, 16)), ea) << "another N";
  EXPECT_EQ(ea.parent_path(), cache.setsDir());
  EXPECT_NE(ea.filename().string().find("envmap_sky_n8_"), std::string::npos) << ea;

  // Made through one path, the entry serves the other: optimizedSets
  // accepts it (same content) and reports it cached.
  OptimizedSetsRequest r;
  r.n = 8, r.instances = 2, r.epochs = 20;
  const OptimizedSets made = optimizedSets(*ta, r, ea);
  EXPECT_FALSE(made.cached);
  EXPECT_EQ(cache.entry(*tb, settingsFor(*tb)), ea) << "found by its key once made";
  const OptimizedSets again = optimizedSets(*tb, r, cache.entry(*tb, settingsFor(*tb)));
  EXPECT_TRUE(again.cached);
  const PointSet set = readPointSet(ea.string());
  EXPECT_TRUE(followsTarget(set, tb->spec(), tb->contentHash()));
  EXPECT_FALSE(followsTarget(set, tc->spec(), tc->contentHash()));
  EXPECT_EQ(metaOr(set, meta::kTargetHash, ""), ta->contentHash());
}

TEST(SetCache, ListsSizesAndClears) {
  TempDir dir;
  const SetCache cache(dir / "cache");
  EXPECT_TRUE(cache.list().empty());
  const auto t = makeTarget("gaussian:0.5,0.5,0.2");
  OptimizedSetsRequest r;
  r.n = 4, r.instances = 3, r.epochs = 10;
  const fs::path e = cache.entry(*t, optimizerSettings(*t, r));
  optimizedSets(*t, r, e);
  // A checkpoint and a writer's temporary are not entries, but count in size.
  fs::copy_file(e, e.string() + ".ckpt");
  fs::copy_file(e, cache.setsDir() / ".x.tmp123.ptsb");
  const auto list = cache.list();
  ASSERT_EQ(list.size(), 1u);
  EXPECT_EQ(list[0].n, 4u);
  EXPECT_EQ(list[0].instances, 3u);
  EXPECT_EQ(list[0].target, "gaussian:0.5,0.5,0.2");
  EXPECT_EQ(cache.bytes(), 3 * fs::file_size(e));
  EXPECT_EQ(cache.clear(), 3 * fs::file_size(e) / 1);
  EXPECT_TRUE(cache.list().empty());
  EXPECT_EQ(cache.bytes(), 0u);
}

// Writers killed at random moments while they write entries, and two
// writers of one entry at once: every visible entry reads whole.
TEST(SetCache, KilledAndConcurrentWritersLeaveNoTornEntry) {
  TempDir dir;
  const SetCache cache(dir / "cache");
  fs::create_directories(cache.setsDir());
  PointSet big;
  big.n = 4096;
  big.points.assign(std::size_t(4096) * 64, Point2{0.25, 0.75});  // a few MB
  const fs::path entry = cache.setsDir() / "big_n4096_0123456789abcdef.ptsb";
  for (int trial = 0; trial < 6; ++trial) {
    std::vector<pid_t> writers;
    for (int w = 0; w < 2; ++w) {
      const pid_t pid = fork();
      ASSERT_GE(pid, 0);
      if (pid == 0) {
        for (;;) writeOptimizedSets(entry, big);  // until killed
      }
      writers.push_back(pid);
    }
    std::this_thread::sleep_for(std::chrono::milliseconds(20 + 37 * trial));
    for (pid_t pid : writers) kill(pid, SIGKILL);
    for (pid_t pid : writers) waitpid(pid, nullptr, 0);
    for (const auto &e : cache.list()) {
      EXPECT_EQ(e.n, 4096u) << e.file << " is torn (trial " << trial << ")";
      EXPECT_EQ(e.instances, 64u);
    }
  }
  EXPECT_EQ(cache.list().size(), 1u);
  cache.clear();  // the killed writers' temporaries too
  EXPECT_EQ(cache.bytes(), 0u);
}

// A nested entry serves any spp up to its N for the same target and
// settings but for N; not another target, other settings or a larger spp.
TEST(SetCache, NestedEntriesServeSmallerSpp) {
  TempDir dir;
  const SetCache cache(dir / "cache");
  const auto t = makeTarget("gaussian:0.5,0.5,0.2"), other = makeTarget("gaussian:0.4,0.5,0.2");
  OptimizedSetsRequest r;
  r.n = 16, r.instances = 2, r.epochs = 10, r.nested = {4, 8};
  const fs::path made = cache.entry(*t, optimizerSettings(*t, r));
  optimizedSets(*t, r, made);
  OptimizedSetsRequest at8 = r;
  at8.n = 8, at8.nested = {4};
  EXPECT_EQ(cache.findNested(*t, optimizerSettings(*t, at8), 8), made);
  EXPECT_EQ(cache.findNested(*t, optimizerSettings(*t, at8), 5), made);
  EXPECT_TRUE(cache.findNested(*t, optimizerSettings(*t, at8), 32).empty()) << "too small";
  EXPECT_TRUE(cache.findNested(*other, optimizerSettings(*other, at8), 8).empty());
  at8.epochs = 11;
  EXPECT_TRUE(cache.findNested(*t, optimizerSettings(*t, at8), 8).empty()) << "other epochs";
}

TEST(SetCache, EnvironmentChoosesTheDirectory) {
  const char *saved = std::getenv("NULD_CACHE");
  const std::string keep = saved ? saved : "";
  setenv("NULD_CACHE", "/some/where", 1);
  EXPECT_EQ(SetCache::fromEnvironment().root(), fs::path("/some/where"));
  unsetenv("NULD_CACHE");
  setenv("XDG_CACHE_HOME", "/xdg", 1);
  EXPECT_EQ(SetCache::fromEnvironment().root(), fs::path("/xdg/nuld"));
  unsetenv("XDG_CACHE_HOME");
  if (saved) setenv("NULD_CACHE", keep.c_str(), 1);
}

}  // namespace
}  // namespace nuld::study
