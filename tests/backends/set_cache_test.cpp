// The shared set cache (backends/set_cache.h): keys by content, not path;
// entries that concurrent or killed writers never leave torn; list and clear.
#include "backends/set_cache.h"

#include <gtest/gtest.h>
#include <signal.h>
#include <sys/wait.h>
#include <unistd.h>

#include <chrono>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <set>
#include <sstream>
#include <thread>

#include "backends/optimized_sets.h"
#include "sampler/io/image_io.h"
#include "sampler/io/pointset_io.h"
#include "sampler/io/pointset_metadata.h"
#include "sampler/targets/target_spec.h"
#include "tests/common/temp_dir.h"

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
  std::ofstream(cache.setsDir() / "notes.txt") << "mine";
  const std::uintmax_t ours = cache.bytes() - fs::file_size(cache.setsDir() / "notes.txt");
  EXPECT_EQ(ours, 3 * fs::file_size(e));
  const CacheRemoval removed = cache.clear();
  EXPECT_EQ(removed.freed, ours);
  EXPECT_EQ(removed.removed, 3u);
  EXPECT_TRUE(removed.failed.empty());
  EXPECT_TRUE(cache.list().empty());
  EXPECT_TRUE(fs::exists(cache.setsDir() / "notes.txt")) << "clear removed a file it did not write";
}

// An entry proves itself on every use: one swapped for another entry's file
// (a whole, valid set file), one bit-flipped and one cut short are never
// served; each is moved aside, named by verify() first, and made again to
// the sets a clean cache makes.
TEST(SetCache, DamagedEntriesAreNeverServed) {
  TempDir dir;
  const SetCache cache(dir / "cache"), clean(dir / "clean");
  const auto t = makeTarget("gaussian:0.5,0.5,0.2"), other = makeTarget("gaussian:0.3,0.6,0.2");
  OptimizedSetsRequest r;
  r.n = 4, r.instances = 2, r.epochs = 5;
  const fs::path e = cache.entry(*t, optimizerSettings(*t, r)),
                 o = cache.entry(*other, optimizerSettings(*other, r));
  optimizedSets(*other, r, o);
  const PointSet want =
      readPointSet(optimizedSets(*t, r, clean.entry(*t, optimizerSettings(*t, r))).file.string());
  const auto damage = [&](const std::string &how) {
    optimizedSets(*t, r, e);
    if (how == "swapped") fs::copy_file(o, e, fs::copy_options::overwrite_existing);
    if (how == "cut") fs::resize_file(e, fs::file_size(e) - 8);
    if (how == "flipped") {
      std::fstream f(e, std::ios::in | std::ios::out | std::ios::binary);
      f.seekp(-20, std::ios::end);
      f.put(char(0x10));
    }
  };
  for (const std::string how : {"swapped", "cut", "flipped"}) {
    damage(how);
    const std::vector<std::string> problems = cache.verify();
    ASSERT_EQ(problems.size(), 1u) << how;
    EXPECT_NE(problems[0].find(e.filename().string()), std::string::npos) << problems[0];
    EXPECT_FALSE(verifiedEntry(e)) << how;
    EXPECT_TRUE(fs::exists(e.string() + ".corrupt")) << how;
    const OptimizedSets made = optimizedSets(*t, r, e);
    EXPECT_FALSE(made.cached) << how << ": a damaged entry was served";
    EXPECT_EQ(readPointSet(e.string()).points, want.points) << how;
    EXPECT_TRUE(cache.verify().empty()) << how;
    fs::remove(e);
  }
  // remove(KEY) takes one entry and its quarantined file, nothing else.
  optimizedSets(*t, r, e);
  const std::string key = e.stem().string().substr(e.stem().string().rfind('_') + 1);
  const CacheRemoval removed = cache.remove(key);
  EXPECT_EQ(removed.removed, 2u);
  EXPECT_FALSE(fs::exists(e));
  EXPECT_TRUE(fs::exists(o));
}

// nuld cache list and nuld bank print one listing: the whole target (two
// lobe targets that differ only at their end read apart), the seed and
// epochs each entry was made with (rows of one target made with another
// seed or epoch count read apart), and the age of its file.
TEST(SetCache, ListingShowsWholeTargetsSeedsEpochsAndAge) {
  TempDir dir;
  const SetCache cache(dir / "cache");
  const auto t = makeTarget("gaussian:0.5,0.5,0.2");
  const auto make = [&](std::uint64_t seed, int epochs) {
    OptimizedSetsRequest r;
    r.n = 4, r.instances = 2, r.epochs = epochs, r.seed = seed;
    const fs::path e = cache.entry(*t, optimizerSettings(*t, r));
    optimizedSets(*t, r, e);
    return e;
  };
  const fs::path a = make(1, 3);
  make(2, 3);
  make(1, 4);
  // Two entries whose targets share all but their last characters.
  const std::string lobe =
      "disney:basecolor=0.5,metallic=0,subsurface=0,specular=0.2,roughness=0.9,anisotropic=0,"
      "clearcoatgloss=1,theta=";
  PointSet set = readPointSet(a.string());
  setMeta(set, meta::kTarget, lobe + "65,res=64");
  writePointSet((cache.setsDir() / "lobe_n4_00000000000000aa.ptsb").string(), set);
  setMeta(set, meta::kTarget, lobe + "85,res=64");
  writePointSet((cache.setsDir() / "lobe_n4_00000000000000bb.ptsb").string(), set);
  const auto now = fs::file_time_type::clock::now();
  fs::last_write_time(a, now - std::chrono::hours(3));

  std::vector<SetListingRow> rows;
  for (const auto &e : cache.list()) rows.push_back({{"x"}, e});
  ASSERT_EQ(rows.size(), 5u);
  const std::vector<std::string> lines = setListing({"lead"}, rows, now);
  ASSERT_EQ(lines.size(), 6u);
  EXPECT_EQ(lines[0].substr(0, 4), "lead");
  for (const char *column : {"seed", "epochs", "age", "key", "target"})
    EXPECT_NE(lines[0].find(column), std::string::npos) << column;
  std::set<std::string> distinct(lines.begin(), lines.end());
  EXPECT_EQ(distinct.size(), lines.size());
  // Columns: lead, n, instances, seed, epochs, ...; the target last, whole.
  std::set<std::string> gaussians, lobes;
  for (std::size_t i = 1; i < lines.size(); ++i) {
    std::istringstream in(lines[i]);
    std::string lead, n, instances, seed, epochs;
    in >> lead >> n >> instances >> seed >> epochs;
    EXPECT_EQ(lead, "x");
    EXPECT_EQ(n, "4");
    EXPECT_EQ(instances, "2");
    const std::string target = lines[i].substr(lines[i].rfind(' ') + 1);
    if (target == "gaussian:0.5,0.5,0.2")
      gaussians.insert(seed + "/" + epochs);
    else
      lobes.insert(target);
    if (rows[i - 1].entry.file == a) EXPECT_NE(lines[i].find(" 3h "), std::string::npos);
  }
  EXPECT_EQ(gaussians, (std::set<std::string>{"1/3", "2/3", "1/4"}));
  EXPECT_EQ(lobes, (std::set<std::string>{lobe + "65,res=64", lobe + "85,res=64"}));
  EXPECT_EQ(rows[0].entry.key.size(), 16u);
  EXPECT_EQ(humanAge(std::chrono::seconds(90)), "90s");
  EXPECT_EQ(humanAge(std::chrono::hours(50)), "2d");
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
