// The reference cache (backends/reference_cache.h): a reference is rendered
// once per content and settings, found under another scene name, resumed
// from an interrupted run's passes, waited for while another run holds it,
// listed, and cleared without touching a file it did not write.
#include "backends/reference_cache.h"

#include <gtest/gtest.h>
#include <signal.h>
#include <sys/wait.h>
#include <unistd.h>

#include <atomic>
#include <chrono>
#include <filesystem>
#include <fstream>
#include <optional>
#include <thread>

#include "scenes/scene_file.h"
#include "tests/common/temp_dir.h"

namespace nuld {
namespace {

namespace fs = std::filesystem;
using test::TempDir;

ReferenceSettings smallReference() {
  ReferenceSettings s;
  s.spp = 8, s.passSpp = 2, s.backend = "halton";
  s.render.width = 10, s.render.height = 6;
  s.render.integrator = IntegratorKind::Path;
  return s;
}

TEST(ReferenceCache, RendersOnceAndIsFoundUnderAnotherName) {
  TempDir tmp;
  const ReferenceCache cache(tmp / "cache");
  const LoadedScene scene = loadScene("default", resolveAssetRoot(""));
  const ReferenceSettings s = smallReference();
  const CachedReference made = cachedReference(scene.scene, "default", s, cache);
  ASSERT_TRUE(made.result.complete);
  EXPECT_FALSE(made.found);
  EXPECT_EQ(made.result.passesRun, 4u);
  EXPECT_EQ(made.dir.parent_path(), cache.referencesDir());
  EXPECT_TRUE(made.dir.filename().string().ends_with("_" + referenceKey(made.description)))
      << made.dir;

  // The same content and settings under another name: found, nothing rendered.
  const CachedReference again = cachedReference(scene.scene, "renamed", s, cache);
  EXPECT_TRUE(again.found);
  EXPECT_EQ(again.result.passesRun, 0u);
  EXPECT_EQ(again.dir, made.dir);
  EXPECT_EQ(again.result.image.pixels, made.result.image.pixels);
  EXPECT_EQ(again.result.noise.variance, made.result.noise.variance);
  EXPECT_GT(again.result.totalSeconds, 0);

  // Another seed is another entry.
  ReferenceSettings other = s;
  other.seed += 1;
  const CachedReference second = cachedReference(scene.scene, "my_scene", other, cache);
  EXPECT_FALSE(second.found);
  EXPECT_NE(second.dir, made.dir);
  const auto entries = cache.list();
  ASSERT_EQ(entries.size(), 2u);
  EXPECT_EQ(entries[0].scene, "default");
  EXPECT_EQ(entries[1].scene, "my_scene") << "a name holding '_' is listed whole";
}

TEST(ReferenceCache, AnInterruptedReferenceResumesFromItsPassesBitForBit) {
  TempDir tmp;
  const ReferenceCache cache(tmp / "cache"), whole(tmp / "whole");
  const LoadedScene scene = loadScene("default", resolveAssetRoot(""));
  const ReferenceSettings s = smallReference();
  const CachedReference first = cachedReference(scene.scene, "default", s, cache, {}, 1);
  EXPECT_FALSE(first.result.complete);
  ASSERT_EQ(cache.list().size(), 1u);
  const ReferenceCache::Entry partial = cache.list().front();
  EXPECT_FALSE(partial.complete);
  EXPECT_EQ(partial.passesDone, 1u);
  EXPECT_EQ(partial.passes, 4u);
  EXPECT_EQ(partial.scene, "default");
  EXPECT_EQ(partial.resolution, "10x6");
  EXPECT_EQ(partial.spp, 8u);

  EXPECT_EQ(partial.lockedBy, 0);
  {  // a run making it now is named in the listing (this process holds the lock)
    const ReferenceLock making(partial.dir);
    ASSERT_TRUE(making.held());
    EXPECT_EQ(cache.list().front().lockedBy, long(::getpid()));
    const auto lines = referenceListing(cache.list());
    EXPECT_NE(lines[1].find("passes 1/4, pid " + std::to_string(::getpid()) + " making it"),
              std::string::npos)
        << lines[1];
  }
  EXPECT_EQ(cache.list().front().lockedBy, 0);

  const CachedReference rest = cachedReference(scene.scene, "default", s, cache);
  ASSERT_TRUE(rest.result.complete);
  EXPECT_FALSE(rest.found) << "three passes were rendered";
  EXPECT_EQ(rest.result.passesRun, 3u);
  const CachedReference uninterrupted = cachedReference(scene.scene, "default", s, whole);
  EXPECT_EQ(rest.result.image.pixels, uninterrupted.result.image.pixels);
  EXPECT_TRUE(cache.list().front().complete);

  const auto lines = referenceListing(cache.list());
  ASSERT_EQ(lines.size(), 2u);
  EXPECT_NE(lines[1].find("complete"), std::string::npos) << lines[1];
  EXPECT_NE(lines[1].find(referenceKey(rest.description)), std::string::npos) << lines[1];

  // Its age is that of its newest file: three hours old once every file
  // and the directory are set back so, and counted from any `now`.
  const auto threeHoursAgo = std::filesystem::file_time_type::clock::now() - std::chrono::hours(3);
  for (const auto &f : std::filesystem::directory_iterator(rest.dir))
    std::filesystem::last_write_time(f.path(), threeHoursAgo);
  std::filesystem::last_write_time(rest.dir, threeHoursAgo);
  EXPECT_NE(referenceListing(cache.list())[1].find("  3h  "), std::string::npos)
      << referenceListing(cache.list())[1];
  EXPECT_NE(
      referenceListing(cache.list(), threeHoursAgo + std::chrono::minutes(5))[1].find("  5m  "),
      std::string::npos);
}

// While another run holds the entry (a second descriptor's flock conflicts
// like another process's), a run waits, says so through its progress, and
// then finds the reference the other run left, rendering nothing.
TEST(ReferenceCache, ASecondRunWaitsForTheFirstAndFindsItsReference) {
  TempDir tmp;
  const ReferenceCache cache(tmp / "cache");
  const LoadedScene scene = loadScene("default", resolveAssetRoot(""));
  const ReferenceSettings s = smallReference();
  const CachedReference first = cachedReference(scene.scene, "default", s, cache);
  ASSERT_TRUE(first.result.complete);

  std::optional<ReferenceLock> other(std::in_place, first.dir);
  ASSERT_TRUE(other->held());
  std::atomic<bool> waiting = false, done = false;
  CachedReference second;
  std::thread run([&] {
    second = cachedReference(scene.scene, "default", s, cache, [&](const ReferenceProgress &p) {
      if (p.waiting) waiting = true;
    });
    done = true;
  });
  const auto start = std::chrono::steady_clock::now();
  while (!waiting && std::chrono::steady_clock::now() - start < std::chrono::seconds(30))
    std::this_thread::sleep_for(std::chrono::milliseconds(5));
  EXPECT_TRUE(waiting);
  std::this_thread::sleep_for(std::chrono::milliseconds(100));
  EXPECT_FALSE(done) << "the run went on while another held the entry";
  other.reset();
  run.join();
  EXPECT_TRUE(second.found);
  EXPECT_EQ(second.result.passesRun, 0u);
  EXPECT_EQ(second.result.image.pixels, first.result.image.pixels);
  EXPECT_EQ(referenceProgressText(ReferenceProgress{.waiting = true}),
            "waiting for another process making this reference");
}

TEST(ReferenceCache, ClearRemovesOnlyTheReferencesFiles) {
  TempDir tmp;
  const ReferenceCache cache(tmp / "cache");
  const LoadedScene scene = loadScene("default", resolveAssetRoot(""));
  const CachedReference made = cachedReference(scene.scene, "default", smallReference(), cache);
  const CachedReference other = [&] {
    ReferenceSettings s = smallReference();
    s.render.width = 8;
    return cachedReference(scene.scene, "default", s, cache);
  }();
  std::ofstream(other.dir / "notes.txt") << "mine";
  EXPECT_GT(cache.bytes(), 0u);
  EXPECT_GT(cache.clear().freed, 0u);
  EXPECT_FALSE(fs::exists(made.dir));
  EXPECT_TRUE(fs::exists(other.dir / "notes.txt"));
  EXPECT_FALSE(fs::exists(other.dir / "reference.exr"));
}

// A cached reference proves itself: its image swapped for another valid
// image of its size, or one of its halves edited, is named by verify(),
// never served, and rendered again to the clean image.
TEST(ReferenceCache, DamagedReferencesAreRenderedAgain) {
  TempDir tmp;
  const ReferenceCache cache(tmp / "cache");
  const LoadedScene scene = loadScene("default", resolveAssetRoot(""));
  const ReferenceSettings s = smallReference();
  const CachedReference made = cachedReference(scene.scene, "default", s, cache);
  ReferenceSettings otherSeed = s;
  otherSeed.seed += 7;
  const CachedReference other = cachedReference(scene.scene, "default", otherSeed, cache);
  EXPECT_TRUE(cache.verify().empty());
  for (const char *name : {"reference.exr", "reference.half1.exr"}) {
    fs::copy_file(other.dir / name, made.dir / name, fs::copy_options::overwrite_existing);
    const std::vector<std::string> problems = cache.verify();
    ASSERT_EQ(problems.size(), 1u) << name;
    EXPECT_NE(problems[0].find(name), std::string::npos) << problems[0];
    const CachedReference again = cachedReference(scene.scene, "default", s, cache);
    EXPECT_FALSE(again.found) << name << ": a damaged reference was served";
    EXPECT_EQ(again.result.image.pixels, made.result.image.pixels) << name;
    EXPECT_EQ(again.result.noise.variance, made.result.noise.variance) << name;
    EXPECT_TRUE(cache.verify().empty()) << name;
  }
}

// clear() skips an entry another process holds and names it, and removes
// the rest; the held entry is whole after.
TEST(ReferenceCache, ClearSkipsAnEntryAnotherProcessHolds) {
  TempDir tmp;
  const ReferenceCache cache(tmp / "cache");
  const LoadedScene scene = loadScene("default", resolveAssetRoot(""));
  const CachedReference held = cachedReference(scene.scene, "default", smallReference(), cache);
  ReferenceSettings s = smallReference();
  s.render.width = 8;
  const CachedReference free = cachedReference(scene.scene, "default", s, cache);
  int ready[2];
  ASSERT_EQ(::pipe(ready), 0);
  const pid_t holder = fork();
  ASSERT_GE(holder, 0);
  if (holder == 0) {
    const ReferenceLock lock(held.dir);
    [[maybe_unused]] const ssize_t n = ::write(ready[1], "x", 1);
    ::pause();
    ::_exit(0);
  }
  char c;
  ASSERT_EQ(::read(ready[0], &c, 1), 1);
  const CacheRemoval removed = cache.clear();
  ::kill(holder, SIGKILL);
  ::waitpid(holder, nullptr, 0);
  ASSERT_EQ(removed.skipped.size(), 1u);
  EXPECT_NE(removed.skipped[0].find(held.dir.string()), std::string::npos) << removed.skipped[0];
  EXPECT_TRUE(removed.failed.empty());
  EXPECT_TRUE(fs::exists(held.dir / "reference.exr"));
  EXPECT_FALSE(fs::exists(free.dir));
  EXPECT_TRUE(cache.verify().empty());
}

TEST(ReferenceCache, AnUnwritableCacheIsNamed) {
  TempDir tmp;
  std::ofstream(tmp / "file") << "x";
  const ReferenceCache cache(tmp / "file");  // a file where the cache's directory should be
  const LoadedScene scene = loadScene("default", resolveAssetRoot(""));
  try {
    cachedReference(scene.scene, "default", smallReference(), cache);
    FAIL() << "expected a refusal";
  } catch (const std::runtime_error &e) {
    EXPECT_NE(std::string(e.what()).find("NULD_CACHE"), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find((tmp / "file").string()), std::string::npos) << e.what();
  }
}

}  // namespace
}  // namespace nuld
