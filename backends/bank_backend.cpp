#include "backends/bank_backend.h"

#include <algorithm>
#include <filesystem>
#include <stdexcept>

#include "backends/backend_registry.h"
#include "renderer/padding.h"
#include "sampler/enum_names.h"
#include "sampler/io/pointset_io.h"
#include "sampler/io/pointset_metadata.h"
#include "sampler/sequences/rng.h"
#include "sampler/sequences/scrambling.h"
#include "sampler/targets/grid_target.h"
#include "sampler/targets/target_spec.h"

namespace nuld {

namespace fs = std::filesystem;

std::string SetBank::targetSpec() const { return metaOr(sets, meta::kTarget, "uniform"); }

bool SetBank::nested() const { return findMeta(sets, meta::kPrefixes) != nullptr; }

namespace {

// Sets for a tabulated lobe (what BSDF domains are asked for), not a map.
bool isLobeSpec(const std::string &spec) { return spec.rfind("disney", 0) == 0; }

SetBank loadBank(const fs::path &file) {
  SetBank bank{readPointSet(file.string()), file.string()};
  if (bank.sets.n == 0 || bank.sets.instances() == 0)
    throw std::invalid_argument(bank.source + ": the point-set file holds no points");
  return bank;
}

}  // namespace

std::vector<SetBank> loadSetBanks(const std::string &paths) {
  std::vector<SetBank> banks;
  std::size_t pos = 0;
  while (pos <= paths.size()) {
    const std::size_t comma = std::min(paths.find(',', pos), paths.size());
    const fs::path path = paths.substr(pos, comma - pos);
    pos = comma + 1;
    if (path.empty()) throw std::invalid_argument("'" + paths + "': an empty path in the list");
    std::error_code ec;
    if (!fs::is_directory(path, ec)) {
      banks.push_back(loadBank(path));
      continue;
    }
    // The whole directory, subdirectories included (a study's lobe banks
    // once lived in one per scene): a bank left out would be a silent
    // fallback.
    std::vector<fs::path> files;
    for (const auto &entry : fs::recursive_directory_iterator(path, ec)) {
      const std::string name = entry.path().filename().string();
      if (entry.is_regular_file() && !name.starts_with(".") && !name.ends_with(".ckpt") &&
          !name.ends_with(".options"))
        files.push_back(entry.path());
    }
    if (ec) throw std::invalid_argument(path.string() + ": cannot list the directory");
    if (files.empty()) throw std::invalid_argument(path.string() + ": no point-set files in it");
    std::sort(files.begin(), files.end());
    for (const fs::path &f : files) banks.push_back(loadBank(f));
  }
  return banks;
}

Dealing dealingOf(const SetBank &bank, bool shifted) {
  if (bank.targetSpec() == "uniform") return Dealing::Primary;
  return shifted ? Dealing::Shifted : Dealing::AsOptimized;
}

SetDealer::SetDealer(const SetBank &bank, const Target *target, Dealing dealing)
    : bank_(&bank), target_(target), dealing_(dealing) {
  if (dealing != Dealing::Shifted) return;
  const auto *grid = dynamic_cast<const GridTarget *>(target);
  if (!grid)
    throw std::invalid_argument("the target '" + (target ? target->spec() : bank.targetSpec()) +
                                "' has no CDF map to shift its sets in");
  pulledBack_.reserve(bank.sets.points.size());
  for (const Point2 &p : bank.sets.points) pulledBack_.push_back(grid->primaryOf(p));
}

void SetDealer::deal(std::size_t k, std::uint64_t shift, std::span<Point2> out) const {
  const auto first = std::ptrdiff_t(k * bank_->sets.n);
  if (dealing_ == Dealing::AsOptimized) {  // a nested bank's prefix when out is shorter
    std::copy_n(bank_->sets.points.begin() + first, out.size(), out.begin());
    return;
  }
  const auto primaries =
      (dealing_ == Dealing::Primary ? bank_->sets.points : pulledBack_).begin() + first;
  for (std::size_t i = 0; i < out.size(); ++i) {
    const Point2 u = cranleyPatterson(primaries[std::ptrdiff_t(i)], shift);
    out[i] = target_ ? target_->invert(u).x : u;
  }
}

BankBackend::BankBackend(std::string name, std::vector<SetBank> banks, std::uint64_t seed,
                         std::uint64_t salt, bool shifted)
    : name_(std::move(name)),
      seed_(seed),
      salt_(salt),
      fallback_(makeClassicBackend(BackendKind::Sobol, seed)),
      shifted_(shifted),
      setBounces_(backendEntry(BackendKind::Optimized).setBounces) {
  setBanks(std::move(banks));
}

void BankBackend::setBanks(std::vector<SetBank> banks) {
  for (const SetBank &b : banks) {
    if (b.sets.n == 0 || b.sets.instances() == 0)
      throw std::invalid_argument(b.source + ": the bank holds no points");
    for (const Point2 &p : b.sets.points)
      if (!inUnitSquare(p))
        throw std::invalid_argument(b.source + ": a point lies outside the unit square");
  }
  banks_ = std::move(banks);
  served_.clear();
  uniform_.reset();
}

// A learned row adds only what it learned: the first bounce's BSDF domains no
// lobe bank serves take the classic lobe routes (as sobol-tabulated), so a
// bank of environment sets is scored against the best classic mapping, not
// against the material's sampler alone; only a uniform bank, which serves
// those domains as primary points itself, keeps them.
bool BankBackend::samplesLobes() const {
  const auto has = [&](auto &&test) {
    return std::any_of(banks_.begin(), banks_.end(),
                       [&](const SetBank &b) { return test(b.targetSpec()); });
  };
  return has(isLobeSpec) || !has([](const std::string &spec) { return spec == "uniform"; });
}

void BankBackend::prepare(std::size_t spp, const SamplingTargets &targets) {
  for (Use &u : use_) u.served = 0, u.fellBack = 0;
  served_.clear();
  uniform_.reset();
  light_ = targets.light;
  lobes_ = targets.lobes;
  n_ = spp;
  if (banks_.empty()) {
    if (allowNoBanks_) return;
    throw std::invalid_argument(name_ + ": the backend has no point sets");
  }
  // Sets of exactly spp points first; then nested sets (optimized prefix by
  // prefix) of more, whose first spp points serve.
  std::vector<const SetBank *> sized;
  for (const SetBank &b : banks_)
    if (b.sets.n == spp) sized.push_back(&b);
  for (const SetBank &b : banks_)
    if (b.nested() && b.sets.n > spp) sized.push_back(&b);
  if (sized.empty()) {
    const std::string n = std::to_string(banks_.front().sets.n);
    throw BackendRefusal(banks_.front().source + ": the file holds sets of " + n + " points" +
                         (banks_.front().nested() ? " (nested: any spp up to " + n + ")" : "") +
                         ", but the render asks for " + std::to_string(spp) +
                         " samples per pixel (use --spp " + n + ")");
  }
  // A bank serves a target by spec, or by content (the same map under
  // another path or asset root: target_spec.h, followsTarget).
  // The hash reads the whole density (a large map's takes tens of ms), so
  // it is asked only when no spec matches.
  const auto bankFor = [&](const Target *t) -> const SetBank * {
    if (!t) return nullptr;
    const std::string spec = t->spec();
    for (const SetBank *b : sized)
      if (followsTarget(b->sets, spec, "")) return b;
    const std::string hash = t->contentHash();
    for (const SetBank *b : sized)
      if (followsTarget(b->sets, spec, hash)) return b;
    return nullptr;
  };
  note_.clear();
  for (const SetBank *b : sized)
    if (!uniform_ && b->targetSpec() == "uniform") {
      uniform_.emplace(*b, nullptr, Dealing::Primary);
      // A file that names no target may hold points already mapped to one:
      // taken as uniform, they would be mapped again, so the user hears it.
      if (!findMeta(b->sets, meta::kTarget))
        note_ = b->source + ": names no target (no '# " + std::string(meta::kTarget) +
                ": SPEC' line), so its points serve as uniform primary samples, which each "
                "light and BSDF maps by its own inverse CDF; if they already follow a target, "
                "add that line naming it, or '# " +
                std::string(meta::kTarget) + ": uniform' to keep this use without the note";
    }
  const auto serve = [&](const Target *t) {
    const SetBank *b = bankFor(t);
    if (!b) return;
    try {
      served_.push_back({t, SetDealer(*b, t, dealingOf(*b, shifted_))});
    } catch (const std::invalid_argument &e) {
      throw BackendRefusal(name_ + ": " + e.what());
    }
  };
  serve(targets.light);
  for (const Target *t : targets.lobes) serve(t);
  if (uniform_ || !served_.empty()) return;

  const SetBank &first = *sized.front();
  const Target *light = targets.light;
  std::string why = first.source + ": its points follow the target '" + first.targetSpec() +
                    "', but the scene's " +
                    (light ? "environment map samples '" + light->spec() + "'"
                           : std::string("has no environment map"));
  if (isLobeSpec(first.targetSpec()))
    why += " and none of its " + std::to_string(targets.lobes.size()) +
           " lobe tables is that lobe (optimize for the scene's materials with nuld study "
           "render, or use uniform points)";
  else
    why += " (optimize for the scene's map, or use uniform points)";
  throw BackendRefusal(why);
}

std::size_t BankBackend::pick(std::size_t instances, std::uint64_t pixel,
                              std::uint32_t domain) const {
  return hash3(seed_ ^ salt_, pixel, domain) % instances;
}

void BankBackend::primary(std::uint64_t pixel, std::uint32_t domain, std::span<Point2> out) const {
  const int depth = SampleLayout::bounceOf(domain);
  if (!uniform_ || depth >= setBounces_ || out.size() != n_) {
    if (uniform_ && depth == 0 && out.size() == n_)
      use_[2].fellBack.fetch_add(1, std::memory_order_relaxed);
    fallback_->primary(pixel, domain, out);
    return;
  }
  use_[2].served.fetch_add(1, std::memory_order_relaxed);
  const std::uint64_t shift = hash3(seed_, pixel, domain);
  uniform_->deal(pick(uniform_->instances(), pixel, domain), shift, out);
  shufflePoints(out, shift);
}

void BankBackend::primary1D(std::uint64_t pixel, std::uint32_t domain,
                            std::span<double> out) const {
  fallback_->primary1D(pixel, domain, out);
}

bool BankBackend::distributed(const Target &target, std::uint64_t pixel, std::uint32_t domain,
                              std::span<Point2> out) const {
  // Targets were matched by spec once in prepare(); here they are addresses.
  const auto it = std::find_if(served_.begin(), served_.end(),
                               [&](const Served &s) { return s.target == &target; });
  const int depth = SampleLayout::bounceOf(domain);
  Use &use = use_[&target == light_ ? 0 : 1];
  if (it == served_.end() || out.size() != n_) {
    if (depth == 0) use.fellBack.fetch_add(1, std::memory_order_relaxed);
    return false;
  }
  if (depth >= setBounces_ ||
      domain != (&target == light_ ? SampleLayout::light(depth) : SampleLayout::bsdf(depth)))
    return false;
  use.served.fetch_add(1, std::memory_order_relaxed);
  const std::uint64_t shift = hash3(seed_, pixel, domain);
  it->dealer.deal(pick(it->dealer.instances(), pixel, domain), shift, out);
  shufflePoints(out, shift);
  return true;
}

bool BankBackend::mapsPrimaryThrough(const Target &target) const {
  // A lobe table without a bank: the fallback's Owen-Sobol through the
  // table, bit for bit what sobol-tabulated gives (the strongest classic
  // route there). The renderer asks tables at the bounces they serve.
  if (std::find(lobes_.begin(), lobes_.end(), &target) == lobes_.end() ||
      std::any_of(served_.begin(), served_.end(),
                  [&](const Served &s) { return s.target == &target; }))
    return false;
  use_[1].fellBack.fetch_add(1, std::memory_order_relaxed);
  return true;
}

SamplerBackend::Report BankBackend::report() const {
  Report out;
  const char *names[] = {"light", "bsdf", "primary"};
  for (std::size_t k = 0; k < use_.size(); ++k)
    out.pairUse.push_back({names[k], use_[k].served.load(), use_[k].fellBack.load()});
  out.note = note_;
  return out;
}

}  // namespace nuld
