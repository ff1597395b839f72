#include "backends/neural_backend.h"

#include <algorithm>
#include <array>
#include <chrono>
#include <cstdlib>
#include <map>
#include <mutex>
#include <stdexcept>
#include <tuple>

#include "materials/disney_target.h"
#include "materials/sphere_map.h"
#include "renderer/smooth_lights.h"
#include "sampler/io/content_hash.h"
#include "sampler/io/pointset_metadata.h"
#include "sampler/sequences/rng.h"
#include "sampler/sequences/scrambling.h"
#include "sampler/sequences/sequence.h"
#include "sampler/targets/grid_target.h"

namespace nuld {

namespace {

constexpr std::uint64_t kNeuralSalt = 0x6e657572616cull;

// The lobe banks every NeuralBackend of this process has made, in front of
// the installed store (LobeBankStore: the set cache, across processes). A
// lobe bank is a function of the model, the table and N alone (its offsets
// come from the table's spec, not from the render's seed: the renderer's
// shift and the per-pixel choice of set randomize each render), and so is
// its serving test's verdict; so the repeats of a study, the renders of a
// session and, with a store, later processes make and test each table's
// bank once, as the study's optimized banks are made once into the set
// cache.
class LobeBankCache {
 public:
  using Key = std::tuple<std::uint64_t, std::string, std::size_t>;  // model, table spec, N
  template <class Make>
  LobeBank get(const Key &key, const Target &table, Make make) {
    std::shared_ptr<const LobeBankStore> store;
    {
      const std::lock_guard lock(mutex_);
      if (const auto it = banks_.find(key); it != banks_.end()) return it->second;
      store = store_;
    }
    // Outside the lock: other tables go on meanwhile.
    const auto &[model, spec, n] = key;
    std::optional<LobeBank> bank = store ? store->load(model, table, n) : std::nullopt;
    if (!bank) {
      bank = make();
      if (store) store->save(model, table, n, *bank);
    }
    const std::lock_guard lock(mutex_);
    // A bank is small (16 sets of N points); a long session of renders of
    // many scenes at many spp keeps at most this many.
    if (banks_.size() >= kMaxBanks) banks_.clear();
    return banks_.try_emplace(key, std::move(*bank)).first->second;
  }
  void setStore(std::shared_ptr<const LobeBankStore> store) {
    const std::lock_guard lock(mutex_);
    store_ = std::move(store);
  }
  void clear() {
    const std::lock_guard lock(mutex_);
    banks_.clear();
  }

 private:
  static constexpr std::size_t kMaxBanks = 4096;
  std::mutex mutex_;
  std::map<Key, LobeBank> banks_;
  std::shared_ptr<const LobeBankStore> store_;
};

LobeBankCache &lobeBankCache() {
  static LobeBankCache cache;
  return cache;
}

// The serving test of a lobe bank (renderer/README.md, "Lobe routes": a
// route serves a lobe only where it is measured at least as good as the
// classic one): the smooth lights (smooth_lights.h) on the table's
// hemisphere, estimated kDealRepeats times with N points that follow the
// table: the bank's sets as BankBackend deals them (one instance, shifted in
// the table's CDF square) and Owen-Sobol through the table's inverse CDF
// (what the bank's fallback and sobol-tabulated give). The bank serves when
// its summed relative variance is no larger. (The constant light's estimate
// is exact for both: it adds nothing.)
constexpr std::size_t kDealRepeats = 64;
bool dealsAtLeastAsWell(const PointSet &bank, const GridTarget &table, std::uint64_t seed) {
  const std::size_t n = bank.n;
  std::array<std::vector<double>, kSmoothLights> dealt, owen;
  std::vector<Point2> u(n);
  const auto add = [&](auto &sums, auto &&point) {
    std::array<double, kSmoothLights> s{};
    for (std::size_t i = 0; i < n; ++i) {
      const Vec3 w = sphereDirection(point(i));
      for (int k = 0; k < kSmoothLights; ++k) s[k] += smoothLight(k, w) / double(n);
    }
    for (int k = 0; k < kSmoothLights; ++k) sums[k].push_back(s[k]);
  };
  for (std::size_t r = 0; r < kDealRepeats; ++r) {
    const std::uint64_t key = mix64(seed + r);
    const auto set = bank.instance(key % bank.instances());
    add(dealt, [&](std::size_t i) {
      return table.invert(cranleyPatterson(table.primaryOf(set[i]), key)).x;
    });
    generateSet({SequenceKind::Sobol, Scramble::Owen, key}, 0, u, 0);
    add(owen, [&](std::size_t i) { return table.invert(u[i]).x; });
  }
  return summedRelativeVariance(dealt) <= summedRelativeVariance(owen);
}

}  // namespace

void setLobeBankStore(std::shared_ptr<const LobeBankStore> store) {
  lobeBankCache().setStore(std::move(store));
}

void forgetLobeBanks() { lobeBankCache().clear(); }

std::string shippedLobeModel() {
  if (const char *env = std::getenv("NULD_LOBE_MODEL"); env && *env) return env;
  return std::string(NULD_SOURCE_DIR) + "/models/disney.nuldnet";
}

bool isLobeFamily(const NeuralGenerator &generator) {
  return generator.family().spec().rfind("family:disney", 0) == 0;
}

NeuralBackend::NeuralBackend(std::string name, const std::string &modelPath, std::uint64_t seed,
                             bool shift)
    : BankBackend(std::move(name), {}, seed, kNeuralSalt),
      source_(modelPath),
      // The network waits for the first bank to make: with every bank in
      // the set cache, the render never loads LibTorch.
      generator_(NeuralGenerator::load(modelPath, NeuralGenerator::NetworkLoad::OnFirstUse)) {
  const std::string family = generator_.family().spec();
  lobeFamily_ = isLobeFamily(generator_);
  // A lobe model's sets follow their table only roughly (tools/experiments/
  // neural_lobe_model.md, "The graph generator in primary space"), which would
  // bias every pixel; shifted in the table's primary space (its CDF map,
  // GridTarget::primaryOf), every point follows the table exactly and the
  // estimate is unbiased.
  setShifted(modelDealing(generator_, shift) == Dealing::Shifted);
  allowNoBanks(lobeFamily_);
  if (generator_.gammaDimension() > 0 && !lobeFamily_)
    throw std::invalid_argument(
        source_ + ": a model for the family '" + family +
        "' needs a gamma that no sampling context of a render gives; the renderer takes "
        "models of one target (the scene's environment map, or uniform) and of family:disney "
        "(gamma = the lobe's view direction)");
  if (const std::string why = generator_.notRandomizedReason(); !why.empty())
    throw std::invalid_argument(source_ + ": " + why +
                                "; a render from them would be biased; retrain without it");
}

std::size_t NeuralBackend::bankSets() const {
  std::size_t sets = 0;
  for (const SetBank &b : banks()) sets += b.sets.instances();
  return sets;
}

void NeuralBackend::prepare(std::size_t spp, const SamplingTargets &targets) {
  // A graph model makes sets of any size; the supplement's network its own.
  const std::size_t n = spp;
  if (!generator_.anySize() && spp != generator_.settings().n)
    throw BackendRefusal(
        source_ + ": the model makes sets of " + std::to_string(generator_.settings().n) +
        " points, but the render asks for " + std::to_string(spp) +
        " samples per pixel (use --spp " + std::to_string(generator_.settings().n) + ")");
  // The banks to make: one per gamma the scene asks for.
  std::vector<std::string> specs;
  std::vector<std::vector<double>> gammas;
  std::vector<const Target *> members;  // the tables themselves, which the model need not rebuild
  if (!lobeFamily_) {
    specs.push_back(generator_.family().target({})->spec());
    gammas.emplace_back();
    members.push_back(nullptr);
  } else {
    for (const Target *t : targets.lobes)
      if (const auto g = disneyFamilyGamma(generator_.family().spec(), t->spec())) {
        specs.push_back(t->spec());
        gammas.push_back(*g);
        members.push_back(t);
      }
    if (targets.lobes.empty())
      throw BackendRefusal(source_ +
                           ": no BSDF sample of the scene goes through a lobe table (no Disney "
                           "material, or the lobe routes keep every material's own sampler): "
                           "there is nothing for the model's sets to serve");
    if (specs.empty())
      throw BackendRefusal(
          source_ + ": the model's family '" + generator_.family().spec() +
          "' makes none of the scene's " + std::to_string(targets.lobes.size()) +
          " lobe tables (it serves a scene material with the family's parameters)");
  }
  madeSeconds_ = 0;
  if (specs != bankSpecs_ || n != bankN_) {
    const std::size_t total = std::clamp<std::size_t>((std::size_t(1) << 22) / n, 1, kMaxBankSets);
    const std::size_t each = lobeFamily_ ? std::min(total, kSetsPerGamma) : total;
    std::vector<SetBank> banks;
    declined_ = banksMade_ = 0;
    for (std::size_t k = 0; k < specs.size(); ++k) {
      // A table whose bank deals worse than Owen-Sobol through it keeps the
      // fallback's points (tools/experiments/neural_lobe_model.md): the verdict
      // is made with the bank, once.
      const auto *grid = dynamic_cast<const GridTarget *>(members[k]);
      const auto make = [&] {
        const auto start = std::chrono::steady_clock::now();
        // A lobe bank's offsets are keyed by its table (see LobeBankCache).
        const std::uint64_t offsets = lobeFamily_ ? hashString(specs[k]) : seed() + k;
        LobeBank made{generator_.generateSets(each, offsets, gammas[k], n, members[k]), true};
        if (lobeFamily_ && grid)
          made.serves = dealsAtLeastAsWell(made.sets, *grid, hashString(specs[k]));
        madeSeconds_ +=
            std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
        ++banksMade_;
        return made;
      };
      LobeBank made =
          lobeFamily_ && members[k] && generator_.fileChecksum() != 0
              ? lobeBankCache().get({generator_.fileChecksum(), specs[k], n}, *members[k], make)
              : make();
      if (measured_ && !made.serves) {
        ++declined_;
        continue;
      }
      SetBank bank{std::move(made.sets), source_};
      setMeta(bank.sets, meta::kTarget, specs[k]);
      banks.push_back(std::move(bank));
    }
    setBanks(std::move(banks));
    bankSpecs_ = specs;
    bankN_ = n;
  }
  BankBackend::prepare(spp, targets);
}

SamplerBackend::Report NeuralBackend::report() const {
  Report out = BankBackend::report();
  out.setsMadeSeconds = madeSeconds_;
  if (declined_ == 0) return out;
  const std::size_t found = bankSpecs_.size() - banksMade_;
  out.note = name() + ": " + std::to_string(declined_) + " of " +
             std::to_string(bankSpecs_.size()) +
             " lobe tables sampled Owen-Sobol through the table: the model's sets, as dealt, "
             "estimate smooth light under them worse than Owen-Sobol through the same table "
             "(measured when each bank was made; " +
             std::to_string(banksMade_) + " made now, " + std::to_string(found) +
             " found made in this process)";
  return out;
}

}  // namespace nuld
