// Neural lobe banks in the set cache (backends/set_cache.h,
// SetCacheLobeBankStore): a later process renders `neural` from the banks and
// serving verdicts an earlier one saved, without making them again; a
// changed model, table or N is another entry; an entry that cannot be read
// is made again.
#include <gtest/gtest.h>

#include <algorithm>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <optional>
#include <string>
#include <vector>

#include "backends/backend_registry.h"
#include "backends/neural_backend.h"
#include "backends/set_cache.h"
#include "materials/disney_target.h"
#include "renderer/render.h"
#include "sampler/io/pointset_io.h"
#include "sampler/io/pointset_metadata.h"
#include "sampler/targets/target_spec.h"
#include "scenes/scene_file.h"
#include "tests/common/temp_dir.h"

namespace nuld::study {
namespace {

namespace fs = std::filesystem;
using test::TempDir;

// NULD_CACHE set for the test's lifetime, and the store installed; the
// process's own banks are forgotten on both ends.
class CacheEnvironment {
 public:
  explicit CacheEnvironment(const fs::path &dir) {
    if (const char *old = std::getenv("NULD_CACHE")) old_ = old;
    setenv("NULD_CACHE", dir.c_str(), 1);
    setLobeBankStore(std::make_shared<SetCacheLobeBankStore>());
    forgetLobeBanks();
  }
  ~CacheEnvironment() {
    setLobeBankStore(nullptr);
    forgetLobeBanks();
    if (old_)
      setenv("NULD_CACHE", old_->c_str(), 1);
    else
      unsetenv("NULD_CACHE");
  }

 private:
  std::optional<std::string> old_;
};

std::vector<fs::path> neuralEntries(const fs::path &cache) {
  std::vector<fs::path> out;
  if (!fs::is_directory(cache / "sets")) return out;
  for (const auto &e : fs::directory_iterator(cache / "sets"))
    if (e.path().filename().string().starts_with("neural_")) out.push_back(e.path());
  std::sort(out.begin(), out.end());
  return out;
}

Image renderNeural(const LoadedScene &scene) {
  RenderOverrides change;
  change.spp = 16;
  change.width = 24, change.height = 16;
  change.integrator = IntegratorKind::Direct;
  const auto backend = makeBackend(parseBackend("neural"), 7);
  return render(scene.scene, change.appliedTo(scene.settings), *backend);
}

TEST(LobeBankStore, ALaterProcessRendersFromTheSavedBanks) {
  registerMaterialTargets();
  TempDir dir;
  const CacheEnvironment env(dir / "cache");
  const LoadedScene scene = loadScene("default", "");
  const Image first = renderNeural(scene);
  const std::vector<fs::path> entries = neuralEntries(dir / "cache");
  ASSERT_FALSE(entries.empty()) << "the banks were saved";
  for (const fs::path &e : entries) {
    const PointSet sets = readPointSet(e.string());
    const std::string serves = metaOr(sets, meta::kServes, "");
    EXPECT_TRUE(serves == "yes" || serves == "no") << e;
    EXPECT_EQ(sets.n, 16u);
  }
  std::vector<fs::file_time_type> written;
  for (const fs::path &e : entries) written.push_back(fs::last_write_time(e));

  // A later process: nothing in memory, the banks and verdicts on disk.
  forgetLobeBanks();
  EXPECT_EQ(renderNeural(scene).pixels, first.pixels);
  EXPECT_EQ(neuralEntries(dir / "cache"), entries) << "no bank made again";
  for (std::size_t i = 0; i < entries.size(); ++i)
    EXPECT_EQ(fs::last_write_time(entries[i]), written[i]) << entries[i];

  // An entry that cannot be read is made again, the same bank.
  { std::ofstream(entries[0], std::ios::binary | std::ios::trunc) << "torn"; }
  forgetLobeBanks();
  EXPECT_EQ(renderNeural(scene).pixels, first.pixels);
  EXPECT_NO_THROW(readPointSet(entries[0].string())) << "rewritten";
}

TEST(LobeBankStore, EntriesAreKeyedByModelTableAndN) {
  registerMaterialTargets();
  TempDir dir;
  const SetCache cache(dir / "cache");
  const auto table =
      makeTarget("disney:basecolor=0.9/0.85/0.8,metallic=0,roughness=0.6,theta=15,res=64,mix=1");
  const auto other =
      makeTarget("disney:basecolor=0.9/0.85/0.8,metallic=0,roughness=0.6,theta=25,res=64,mix=1");
  const fs::path entry = cache.modelEntry(1, *table, 16);
  EXPECT_EQ(cache.modelEntry(1, *table, 16), entry);
  EXPECT_NE(cache.modelEntry(2, *table, 16), entry);  // a changed model file
  EXPECT_NE(cache.modelEntry(1, *other, 16), entry);  // another table
  EXPECT_NE(cache.modelEntry(1, *table, 64), entry);  // another N
  EXPECT_TRUE(entry.filename().string().starts_with("neural_disney")) << entry;
}

}  // namespace
}  // namespace nuld::study
