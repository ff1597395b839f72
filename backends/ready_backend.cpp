#include "backends/ready_backend.h"

#include <cctype>
#include <cmath>
#include <stdexcept>

namespace nuld {

namespace fs = std::filesystem;

void SetSettings::validate() const {
  if (instances == 0) throw std::invalid_argument("--opt-instances: must be at least 1");
  if (!(unionWeight >= 0) || !std::isfinite(unionWeight))
    throw std::invalid_argument("--opt-union-weight: expected a finite weight >= 0");
  if (envObjective != Objective::SoftBoxes && envObjective != Objective::ExactL2asd)
    throw std::invalid_argument("--opt-objective: expected soft or l2asd");
}

namespace {

// Where "LABEL=WORD" splits (npos: no label). A '=' after a character no
// label may hold (a plugin path's '/' or ':') is the word's own.
std::size_t labelEnd(const std::string &word) {
  const std::size_t eq = word.find('=');
  if (eq == std::string::npos) return eq;
  for (std::size_t i = 0; i < eq; ++i) {
    const unsigned char c = static_cast<unsigned char>(word[i]);
    if (!(std::isalnum(c) || c == '-' || c == '_' || c == '.' || c == '+'))
      return std::string::npos;
  }
  return eq;
}

}  // namespace

std::string rowLabel(const std::string &word) {
  const std::size_t end = labelEnd(word);
  return end == std::string::npos ? word : word.substr(0, end);
}

std::string unlabelled(const std::string &word) {
  const std::size_t end = labelEnd(word);
  return end == std::string::npos ? word : word.substr(end + 1);
}

BackendWord parseBackendWord(const std::string &word) {
  if (labelEnd(word) == 0)
    throw std::invalid_argument("backend '" + word +
                                "': expected LABEL=WORD with a label of letters, digits, - _ . +");
  const BackendSpec spec = parseBackend(unlabelled(word), kRenders);
  return {word, rowLabel(word), spec, spec.setsToMake()};
}

bool BackendWord::samplesLobes() const {
  // Sets sample the lobe routes where no set serves (BankBackend), except
  // uniform sets, which serve the BSDF pair themselves.
  if (makesSets()) return sets != BackendSets::Uniform;
  return spec.entry().lobes && makeBackend(spec, 0)->samplesLobes();
}

ReadyBackend makeReadyBackend(const BackendWord &word, const Scene &scene,
                              const RenderSettings &settings, const std::string &sceneName,
                              const SetSettings &sets, std::uint64_t seed,
                              const std::vector<std::size_t> &sppFamily,
                              const SetProgress &progress) {
  ReadyBackend out;
  out.prepared = prepareBackend(word, scene, settings, sceneName, sets, seed, sppFamily, progress);
  out.backend = makeBackend(out.prepared.spec, seed);
  return out;
}

std::string slug(const std::string &name) {
  std::string base = name;
  if (const auto colon = base.find(':'); colon != std::string::npos)
    base = base.substr(0, colon) + "-" + fs::path(base.substr(colon + 1)).stem().string();
  else if (base.find('/') != std::string::npos || base.find('.') != std::string::npos)
    base = fs::path(base).stem().string();
  for (char &c : base)
    if (!(std::isalnum(static_cast<unsigned char>(c)) || c == '-' || c == '_')) c = '_';
  return base;
}

}  // namespace nuld
