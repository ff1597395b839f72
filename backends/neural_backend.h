#pragma once
// The `neural:MODEL` backend: point sets from a trained neural generator
// (sampler/neural), dealt out by the bank mechanism (backends/bank_backend.h).
// The generator is conditioned on an offset z; prepare() draws a bank of
// offsets and generates their sets in one batched inference, and each
// (pixel, pair) picks one by hash, so neighbouring pixels get different sets
// as with a per-pixel z, without one network call per pixel.
//
//  - A model for the scene's environment map serves the first bounce's light
//    pair; a model for the uniform target serves the first bounce's pairs as
//    primary points under a Cranley-Patterson shift per (pixel, pair).
//  - A model for a `family:disney` target family is conditioned on the lobe's
//    gamma = (theta_o, phi_o): it makes one bank per lobe table of the scene
//    that the family contains (the same material), at that table's gamma, and
//    serves the first bounce's BSDF pair there; a `family:disney-material`
//    model does so for every table of its layout, any material. Its sets are
//    Cranley-Patterson shifted in the table's primary space per (pixel,
//    pair), as `shifted:PATHS` does, so that every point follows the table
//    exactly (a generator's sets follow it only roughly). A table's bank
//    serves only where, dealt so, it estimates smooth light under the table
//    at least as well as Owen-Sobol through it (the fallback's points, what
//    sobol-tabulated gives); the tables it fails keep the fallback, and
//    note() says how many. Other families have no sampling context in a
//    render and are refused.
//
// The supplement's network makes sets of its trained N only, so it serves
// that spp alone; a graph model serves any spp (banks remade per spp).

#include <memory>
#include <optional>
#include <string>

#include "backends/bank_backend.h"
#include "sampler/neural/neural_generator.h"

namespace nuld {

// The model the word `neural` names without a file: $NULD_LOBE_MODEL when
// set, else the tracked models/disney.nuldnet of this checkout
// (models/README.md says how it was trained).
std::string shippedLobeModel();

// How a model's sets are dealt (SetDealer), in renders and in the
// integration study alike: a lobe family's (`family:disney...`) shifted in
// their table's primary space, any other model's as generated unless
// `shift` (the word's +shift) asks for every set shifted.
bool isLobeFamily(const NeuralGenerator &generator);
inline Dealing modelDealing(const NeuralGenerator &generator, bool shift = false) {
  return shift || isLobeFamily(generator) ? Dealing::Shifted : Dealing::AsOptimized;
}

// A lobe model's bank for one table at one N, and whether it passed the
// serving test there (it serves only then; NeuralBackend).
struct LobeBank {
  PointSet sets;
  bool serves = false;
};

// Where lobe banks outlive the process: the tools install the set cache
// (backends/set_cache.h) so that a second process finds the banks, and
// their verdicts, that the first made. Keyed by the model file's checksum,
// the table (its content) and N. A store's errors are its own to report: a
// bank it cannot load is made again, one it cannot save is used anyway.
class LobeBankStore {
 public:
  virtual ~LobeBankStore() = default;
  virtual std::optional<LobeBank> load(std::uint64_t model, const Target &table,
                                       std::size_t n) const = 0;
  virtual void save(std::uint64_t model, const Target &table, std::size_t n,
                    const LobeBank &bank) const = 0;
};
// The store every NeuralBackend asks after its process's own banks; nullptr
// (the default): none, banks live as long as the process.
void setLobeBankStore(std::shared_ptr<const LobeBankStore> store);
// Forgets the lobe banks this process holds (its own cache, not the store):
// for tests of the store.
void forgetLobeBanks();

class NeuralBackend final : public BankBackend {
 public:
  // The banks hold at most this many sets in all (fewer when N is large: at
  // most 2^22 points in all); a lobe family's model makes kSetsPerGamma per
  // lobe table. Each pixel's set is a random draw from its bank either way,
  // so a pixel's expected error does not depend on the bank's size; a
  // smaller bank only shares sets between more pixels, and costs less to
  // generate (tools/experiments/neural_lobe_model.md, "The graph generator in
  // primary space").
  static constexpr std::size_t kMaxBankSets = 4096;
  static constexpr std::size_t kSetsPerGamma = 16;

  // `shift`: every set shifted (neural+shift), not only a lobe family's.
  NeuralBackend(std::string name, const std::string &modelPath, std::uint64_t seed,
                bool shift = false);

  bool samplesLobes() const override { return lobeFamily_; }
  void prepare(std::size_t spp, const SamplingTargets &targets) override;

  std::size_t bankSets() const;
  // The bank's counts, what the model's sets were declined for, and the
  // seconds its banks took to make.
  Report report() const override;
  // Every lobe table its model makes is served, measured or not: for the
  // tests and experiments that examine the sets as dealt (takes effect at
  // the next prepare()).
  void serveEveryTable() {
    measured_ = false;
    bankSpecs_.clear();
  }

 private:
  std::string source_;
  NeuralGenerator generator_;
  bool lobeFamily_ = false;
  std::vector<std::string> bankSpecs_;  // the targets of the banks made so far
  std::size_t bankN_ = 0;               // and their set size
  std::size_t declined_ = 0;            // tables whose bank failed the serving test
  std::size_t banksMade_ = 0;           // banks the last prepare() made (the rest were found)
  bool measured_ = true;                // whether banks must pass it to serve
  double madeSeconds_ = 0;              // making banks in the last prepare()
};

}  // namespace nuld
