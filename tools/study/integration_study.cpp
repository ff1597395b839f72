// The integration study's runner: the CSV it writes, the measurements per
// (integrand, sampler, N) and runIntegrateStudy, which resumes the CSV.

#include "tools/study/integration_study.h"

#include <algorithm>
#include <cctype>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <map>
#include <memory>
#include <optional>
#include <stdexcept>

#include "backends/bank_backend.h"
#include "backends/neural_backend.h"
#include "backends/optimized_sets.h"
#include "backends/ranks.h"
#include "backends/set_cache.h"
#include "backends/stopwatch.h"
#include "sampler/bluenoise/blue_noise_sets.h"
#include "sampler/io/output_folder.h"
#include "sampler/io/pointset_io.h"
#include "sampler/neural/neural_generator.h"
#include "sampler/optimize/optimizer.h"
#include "sampler/sequences/rng.h"
#include "sampler/sequences/scrambling.h"
#include "sampler/sequences/sequence.h"
#include "sampler/targets/grid_target.h"
#include "sampler/targets/target_spec.h"
#include "tools/study/integrate_estimators.h"
#include "tools/study/integrate_internal.h"

namespace nuld::study {
namespace fs = std::filesystem;

std::string joinNames(const std::vector<std::string> &names) {
  std::string out;
  for (const auto &n : names) out += (out.empty() ? "" : ", ") + n;
  return out;
}

// Reference and mean carry more digits than formatNumber's 6, so bias can be
// checked against them.
std::string formatPrecise(double v) {
  if (!std::isfinite(v)) return formatNumber(v);
  char buf[40];
  std::snprintf(buf, sizeof buf, "%.12g", v);
  return buf;
}

const std::vector<std::string> &integrateColumns() {
  static const std::vector<std::string> columns{"integrand",
                                                "domain",
                                                "sampler",
                                                "n",
                                                "instances",
                                                "reference",
                                                "mean",
                                                "bias",
                                                "bias_stderr",
                                                "std",
                                                "rmse",
                                                "rel_rmse",
                                                "mse_stderr",
                                                "gen_seconds_per_set",
                                                "setup_seconds_per_set"};
  return columns;
}

fs::path integrateCsvPath(const fs::path &outDir) { return outDir / "integrate.csv"; }

namespace {

// Loads a model and finds the integrands it serves; throws naming --neural.
NeuralModel loadModel(const SamplerChoice &s, const std::vector<Integrand> &integrands) {
  NeuralModel m;
  m.path = s.model;
  m.name = s.name;
  try {
    m.generator = std::make_shared<const NeuralGenerator>(NeuralGenerator::load(s.model));
  } catch (const std::exception &e) {
    throw std::runtime_error("--neural '" + s.model + "': cannot use the model: " + e.what());
  }
  const NeuralGenerator &g = *m.generator;
  if (const std::string why = g.notRandomizedReason(); !why.empty())
    throw std::runtime_error("--neural '" + s.model + "': " + why +
                             "; the study's error over instances would be mostly bias; retrain "
                             "without it");
  const bool fixed = g.gammaDimension() == 0;
  const std::string trainedFor = fixed ? g.family().target({})->spec() : g.family().spec();
  for (const Integrand &in : integrands) {
    if (g.domain() != in.domain()) continue;
    if (fixed) {
      if (sameTarget(trainedFor, in.target->spec())) m.gammaFor[in.name] = {};
    } else if (in.familyGamma) {
      if (auto gamma = in.familyGamma(g.family())) m.gammaFor[in.name] = *gamma;
    }
  }
  if (m.gammaFor.empty()) {
    std::vector<std::string> targets;
    for (const Integrand &in : integrands)
      targets.push_back(in.name + " (" + in.target->spec() + ")");
    throw std::invalid_argument(
        "--neural '" + s.model + "': the model's target '" + trainedFor +
        "' matches none of the integrands: " +
        (targets.empty() ? std::string("none selected") : joinNames(targets)));
  }
  return m;
}

// One row to make: an integrand, a sampler and N.
struct Task {
  const Integrand *in;
  const SamplerChoice *s;
  std::size_t n;
  const SetBank *bank = nullptr;  // a bank word's row: the bank it uses (planTasks)
};

// The banks of each bank word (optimized:PATHS, shifted:PATHS), by name.
using FileBanks = std::map<std::string, std::vector<SetBank>>;

// Whether `bank` serves integrand `in` as the renderer would deal it out:
// sets for the integrand's own target, matched as the renderer matches them
// (by spec, else by content: followsTarget), shifted through its CDF map
// (which grid targets have) or, unshifted, two instances at least (one
// estimate each); or uniform sets, shifted per instance and mapped by the
// inverse CDF.
// `targetHash` is the integrand's target's content hash, asked only for a
// bank that does not match by spec (it reads the whole density).
template <class Hash>
bool bankServes(const SetBank &bank, const Integrand &in, bool shifted, Hash &&targetHash) {
  if (bank.targetSpec() == "uniform") return true;
  const std::string spec = in.target->spec();
  if (!followsTarget(bank.sets, spec, "") && !followsTarget(bank.sets, spec, targetHash()))
    return false;
  return shifted ? dynamic_cast<const GridTarget *>(in.target.get()) != nullptr
                 : bank.sets.instances() >= 2;
}

// The bank a row of `s` uses at each N some bank serves the integrand at:
// the integrand's own target first, else uniform sets. The target's hash is
// read at most once.
std::map<std::size_t, const SetBank *> fileBanksFor(const std::vector<SetBank> &banks,
                                                    const Integrand &in, const SamplerChoice &s) {
  std::optional<std::string> hash;
  const auto targetHash = [&]() -> const std::string & {
    if (!hash) hash = in.target->contentHash();
    return *hash;
  };
  std::map<std::size_t, const SetBank *> out;
  for (const SetBank &b : banks) {
    if (!bankServes(b, in, s.shifted, targetHash)) continue;
    const SetBank *&chosen = out[b.sets.n];
    if (!chosen || (chosen->targetSpec() == "uniform" && b.targetSpec() != "uniform")) chosen = &b;
  }
  return out;
}

// A measured row as it travels to rank 0: the CSV values, the notes it
// raised and how many of its sets came from the cache.
struct RowResult {
  std::vector<std::string> row, notes;
  std::size_t setsFromCache = 0;

  std::string bytes() const { return ByteWriter().put(row).put(notes).put(setsFromCache).take(); }
  static RowResult from(std::string_view bytes) {
    ByteReader r(bytes);
    RowResult result;
    r.get(result.row);
    r.get(result.notes);
    r.get(result.setsFromCache);
    return result;
  }
};

class StudyRunner {
 public:
  StudyRunner(const IntegrateOptions &o, const IntegrateHooks &hooks, IntegrateSummary &summary)
      : o_(o), hooks_(hooks), summary_(summary) {}

  void note(const std::string &text) {
    summary_.notes.push_back(text);
    if (hooks_.message) hooks_.message(text);
  }
  void progress(const std::string &status) {
    if (hooks_.progress) hooks_.progress(done_, total_, status);
  }
  void setTotal(long total) { total_ = total; }
  void advance() { ++done_; }

 private:
  OptimizedSetsRequest bankRequest(std::size_t n) const {
    OptimizedSetsRequest request;
    request.n = n;
    request.instances = o_.optimizedInstances;
    request.epochs = o_.optEpochs;
    request.seed = o_.seed;
    request.objective = o_.optObjective;
    request.unionWeight = o_.optUnionWeight;
    return request;
  }
  fs::path bankPath(const Target &target, const OptimizedSetsRequest &request) const {
    const SetCache cache =
        o_.cacheDir.empty() ? SetCache::fromEnvironment() : SetCache(o_.cacheDir);
    return cache.entry(target, optimizerSettings(target, request));
  }

  // K optimized sets of N points for the target, from the cache (makeBanks
  // made those missing).
  PointSet bankFor(const Target &target, std::size_t n, double &secondsPerSet) {
    const OptimizedSetsRequest request = bankRequest(n);
    const OptimizedSets made = optimizedSets(target, request, bankPath(target, request));
    secondsPerSet = made.seconds / double(request.instances);
    PointSet set = readPointSet(made.file.string());
    if (set.n != n || set.instances() < request.instances)
      throw std::runtime_error(made.file.string() + ": expected " +
                               std::to_string(request.instances) + " sets of " + std::to_string(n) +
                               " points");
    return set;
  }

 public:
  // Makes the banks of optimized sets the rows need and are not cached yet
  // (makeMissingSets: one bank per rank and round); returns their files.
  std::vector<fs::path> makeBanks(const std::vector<const Task *> &rows, const Ranks &ranks) {
    std::vector<SetsJob> jobs;
    for (const Task *t : rows) {
      const OptimizedSetsRequest request = bankRequest(t->n);
      jobs.push_back({t->in->target.get(), request, bankPath(*t->in->target, request),
                      "optimizing " + shortSpec(t->in->target->spec()) +
                          " N=" + std::to_string(t->n) + " (" + std::to_string(request.instances) +
                          " sets)"});
    }
    int lastShown = -1;
    const std::vector<SetsJob> made = makeMissingSets(
        ranks, jobs,
        [&](std::size_t, std::size_t, const SetsJob &job, int epoch, int epochs, double) {
          const int percent = int(100.0 * epoch / epochs);
          if (percent == lastShown) return;
          lastShown = percent;
          progress(job.label + " epoch " + std::to_string(epoch) + "/" + std::to_string(epochs));
        });
    std::vector<fs::path> files;
    for (const SetsJob &job : made) {
      summary_.setsOptimized += job.request.instances;
      files.push_back(job.file);
    }
    return files;
  }

  // One row of the table, measured; its notes and cache count go with it to
  // rank 0. `madeNow`: the banks makeBanks made (not counted as cached).
  RowResult measureRow(const Task &t, const std::map<std::string, NeuralModel> &models,
                       const std::vector<fs::path> &madeNow) {
    const std::string domain = toString(t.in->domain()), n = std::to_string(t.n);
    const std::string row = t.in->name + " " + t.s->name + " N=" + n;
    RowResult result;
    const auto estimator = makeEstimator(
        o_, *t.s, t.s->kind == SamplerChoice::Kind::Neural ? &models.at(t.s->name) : nullptr,
        t.bank, [&](const Target &target, std::size_t n, double &secondsPerSet) {
          return bankFor(target, n, secondsPerSet);
        });
    const Measurement m = estimator->measure(*t.in, t.n);
    const std::size_t K = m.estimates.size();
    if (t.s->kind == SamplerChoice::Kind::Optimized) {
      const fs::path file = bankPath(*t.in->target, bankRequest(t.n));
      if (std::find(madeNow.begin(), madeNow.end(), file) == madeNow.end())
        result.setsFromCache = o_.optimizedInstances;
    }
    const EstimateStats st = summarize(m.estimates, t.in->reference);
    const std::vector<double> values{t.in->reference, st.mean,       st.bias,    st.biasStderr,
                                     st.std,          st.rmse,       st.relRmse, st.mseStderr,
                                     m.genSeconds,    m.setupSeconds};
    for (double v : values)
      if (!std::isfinite(v))
        throw std::runtime_error("study integrate: " + row + " gave a value that is not finite");
    if (m.zeroPdf > 0)
      result.notes.push_back(
          "note: " + row + ": " + std::to_string(m.zeroPdf) + " of " + std::to_string(K * t.n) +
          " points had zero density (or a non-finite weight) and counted as 0; this shows as "
          "bias");
    result.row = {t.in->name,
                  domain,
                  t.s->name,
                  n,
                  std::to_string(K),
                  formatPrecise(t.in->reference),
                  formatPrecise(st.mean),
                  formatNumber(st.bias),
                  formatNumber(st.biasStderr),
                  formatNumber(st.std),
                  formatNumber(st.rmse),
                  formatNumber(st.relRmse),
                  formatNumber(st.mseStderr),
                  formatNumber(m.genSeconds),
                  formatNumber(m.setupSeconds)};
    return result;
  }

 private:
  const IntegrateOptions &o_;
  const IntegrateHooks &hooks_;
  IntegrateSummary &summary_;
  long done_ = 0, total_ = 0;
};

// Refuses options the study cannot run with, naming the option.
void validateOptions(const IntegrateOptions &o) {
  if (o.instances < 2)
    throw std::invalid_argument("--instances " + std::to_string(o.instances) +
                                ": expected at least 2 (the standard deviation needs two)");
  if (o.optimizedInstances < 2)
    throw std::invalid_argument("--optimized-instances " + std::to_string(o.optimizedInstances) +
                                ": expected at least 2 (the standard deviation needs two)");
  if (o.ns.empty()) throw std::invalid_argument("--n: expected at least one N");
  for (std::size_t n : o.ns)
    if (n == 0) throw std::invalid_argument("--n: N must be at least 1");
  if (o.optEpochs < 0) throw std::invalid_argument("--opt-epochs: expected a positive count");
  if (o.outDir.empty()) throw std::invalid_argument("-o: an output directory is required");
}

// The rows to make, in order: integrand, sampler, N. Tabulated samplers only
// where the integrand has a lobe; optimized and blue-noise sets up to
// optimizedMaxN; a neural model where it has a gamma for the integrand, at
// every N (graph) or at its own (the supplement's network).
std::vector<Task> planTasks(const IntegrateOptions &o, const std::vector<Integrand> &integrands,
                            const std::vector<SamplerChoice> &samplers,
                            const std::map<std::string, NeuralModel> &models,
                            const FileBanks &fileBanks) {
  std::vector<Task> tasks;
  for (const auto &in : integrands)
    for (const auto &s : samplers) {
      if (s.tabulated && !in.lobeContribution) continue;
      if (s.kind == SamplerChoice::Kind::Bank) {  // at the N of the banks that serve it
        for (const auto &[n, bank] : fileBanksFor(fileBanks.at(s.name), in, s))
          tasks.push_back({&in, &s, n, bank});
        continue;
      }
      if (s.kind == SamplerChoice::Kind::Neural) {
        const NeuralModel &m = models.at(s.name);
        // A graph model makes sets of every N asked for; the supplement's its own N.
        if (m.gammaFor.count(in.name)) {
          if (m.generator->anySize())
            for (std::size_t n : o.ns) tasks.push_back({&in, &s, n});
          else
            tasks.push_back({&in, &s, m.generator->settings().n});
        }
        continue;
      }
      for (std::size_t n : o.ns)
        if ((s.kind != SamplerChoice::Kind::Optimized &&
             s.kind != SamplerChoice::Kind::BlueNoise) ||
            n <= o.optimizedMaxN)
          tasks.push_back({&in, &s, n});
    }
  return tasks;
}

}  // namespace

std::string rowOptions(const IntegrateOptions &o) {
  return "instances=" + std::to_string(o.instances) + " seed=" + std::to_string(o.seed) +
         " optimized-instances=" + std::to_string(o.optimizedInstances) +
         " opt-epochs=" + std::to_string(o.optEpochs) +
         " opt-objective=" + (o.optObjective ? toString(*o.optObjective) : "preset") +
         " opt-union-weight=" + formatNumber(o.optUnionWeight) +
         " lobe-choice=" + toString(o.lobeChoice);
}

IntegrateSummary runIntegrateStudy(const IntegrateOptions &o, const IntegrateHooks &hooks) {
  validateOptions(o);
  IntegrateSummary summary;
  StudyRunner runner(o, hooks, summary);
  std::vector<SamplerChoice> samplers;
  std::vector<std::string> notes;
  const auto integrands = selectIntegrands(o, notes);
  for (const auto &n : notes) runner.note(n);
  std::map<std::string, NeuralModel> models;
  FileBanks fileBanks;
  for (SamplerChoice s : parseSamplers(o.samplers, o.neuralModels)) {
    if (s.kind == SamplerChoice::Kind::Neural) {
      NeuralModel model = loadModel(s, integrands);
      // `neural` means what it means in renders: a lobe family's sets
      // shifted, as renders deal them; the row's name says so.
      if (modelDealing(*model.generator) == Dealing::Shifted && !s.shifted) {
        runner.note(s.name +
                    ": a lobe family's sets are dealt shifted in their table's "
                    "primary space, as renders deal them (rows " +
                    s.name + "+shift)");
        s.shifted = true;
        s.name += "+shift";
        model.name = s.name;
      }
      if (models.contains(s.name)) continue;  // named twice, once with +shift
      models.emplace(s.name, std::move(model));
    }
    if (s.kind == SamplerChoice::Kind::Bank) fileBanks.emplace(s.name, loadSetBanks(s.paths));
    samplers.push_back(std::move(s));
  }

  const std::vector<Task> tasks = planTasks(o, integrands, samplers, models, fileBanks);
  for (const auto &s : samplers)
    if (s.kind == SamplerChoice::Kind::Bank &&
        std::none_of(tasks.begin(), tasks.end(), [&](const Task &t) { return t.s == &s; }))
      runner.note(s.name + ": no set of '" + s.paths + "' follows an integrand's target" +
                  (s.shifted ? " with a CDF map (image, envmap, disney)" : "") +
                  " or the uniform target; no rows");
  if (Ranks::world().root()) claimOutputFolder(o.outDir, kStudyFolder);
  CsvTable table(integrateCsvPath(o.outDir), integrateColumns());
  table.loadExisting();
  table.requireOptions(rowOptions(o), Ranks::world().root());
  runner.setTotal(long(tasks.size()));
  std::vector<const Task *> pending;
  for (const Task &t : tasks) {
    if (!table.hasRow({t.in->name, toString(t.in->domain()), t.s->name, std::to_string(t.n)})) {
      pending.push_back(&t);
      continue;
    }
    ++summary.rowsSkipped;
    runner.advance();
    runner.progress(t.in->name + " " + t.s->name + " N=" + std::to_string(t.n) +
                    " (already in the CSV)");
  }
  // Every rank has read the CSV before rank 0 first adds to it.
  const Ranks &ranks = Ranks::world();
  ranks.barrier();

  // First the optimized banks the rows need, each made once, on one rank
  // (rank 0 writes them); then the rows, side by side.
  std::vector<const Task *> optimizedRows;
  for (const Task *t : pending)
    if (t->s->kind == SamplerChoice::Kind::Optimized) optimizedRows.push_back(t);
  const auto banks = runner.makeBanks(optimizedRows, ranks);

  runInRounds(
      ranks, pending.size(),
      [&](std::size_t i) { return runner.measureRow(*pending[i], models, banks).bytes(); },
      [&](std::size_t i, const std::string &bytes) {
        const Task &t = *pending[i];
        const RowResult r = RowResult::from(bytes);
        for (const std::string &note : r.notes) runner.note(note);
        summary.setsFromCache += r.setsFromCache;
        table.addRow(r.row);
        ++summary.rowsAdded;
        runner.advance();
        runner.progress(t.in->name + " " + t.s->name + " N=" + std::to_string(t.n));
      });
  return summary;
}

}  // namespace nuld::study
