#include "tools/study/integration_study.h"

#include <algorithm>
#include <cctype>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <map>
#include <memory>
#include <set>
#include <sstream>
#include <stdexcept>

#include "renderer/pointset_backend.h"
#include "sampler/io/pointset_io.h"
#include "sampler/neural/neural_generator.h"
#include "sampler/optimize/optimizer.h"
#include "sampler/sequences/rng.h"
#include "sampler/sequences/sequence.h"
#include "scenes/default_scene.h"
#include "tools/study/optimized_sets.h"
#include "tools/study/report_script.h"
#include "tools/study/stopwatch.h"

namespace nuld::study {
namespace fs = std::filesystem;

namespace {

std::uint64_t hashString(const std::string &s) {
  std::uint64_t h = 1469598103934665603ull;  // FNV-1a
  for (unsigned char c : s) h = (h ^ c) * 1099511628211ull;
  return h;
}

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

// A loaded neural model and the integrands it serves (with their gamma).
struct NeuralModel {
  std::string path, name;
  std::shared_ptr<const NeuralGenerator> generator;
  std::map<std::string, std::vector<double>> gammaFor;  // integrand name -> gamma
};

// envmap:/long/path/grace_latlong.exr -> envmap:grace_latlong, for names.
std::string shortSpec(const std::string &spec) {
  const auto colon = spec.find(':');
  if (colon == std::string::npos || (spec.rfind("envmap:", 0) != 0 && spec.rfind("image:", 0) != 0))
    return spec;
  return spec.substr(0, colon + 1) + fs::path(spec.substr(colon + 1)).stem().string();
}

// The cache file of the optimized sets for a target, N and settings: the
// name shows the target and N, the hash covers the full spec and settings.
fs::path cachePath(const fs::path &dir, const Target &target, const OptimizerSettings &s) {
  const std::string spec = target.spec();
  std::string slug = shortSpec(spec);
  for (char &c : slug)
    if (!std::isalnum(static_cast<unsigned char>(c)) && c != '.' && c != '-') c = '_';
  if (slug.size() > 48) slug.resize(48);
  char hash[17];
  std::snprintf(hash, sizeof hash, "%016llx",
                static_cast<unsigned long long>(hashString(spec + "|" + s.describe())));
  return dir / ("optimized_" + slug + "_n" + std::to_string(s.n) + "_" + hash + ".ptsb");
}

// A built-in map name (no file): the default sky with a 1e6 sun.
constexpr const char *kSunMap = "sun";

std::optional<std::string> findEnvmap(const std::string &root, const std::string &name) {
  std::vector<fs::path> candidates;
  const fs::path dir = fs::path(root) / "envmaps";
  if (fs::path(name).has_extension() || name.find('/') != std::string::npos)
    candidates = {fs::path(name), dir / name, fs::path(root) / name};
  else
    for (const char *suffix : {"_latlong.exr", "_latlong.hdr", ".exr", ".hdr"})
      candidates.push_back(dir / (name + suffix));
  for (const auto &c : candidates)
    if (fs::is_regular_file(c)) return c.string();
  return std::nullopt;
}

std::string envmapShortName(const std::string &name) {
  if (!fs::path(name).has_extension() && name.find('/') == std::string::npos) return name;
  std::string stem = fs::path(name).stem().string();
  if (stem.size() > 8 && stem.ends_with("_latlong")) stem.resize(stem.size() - 8);
  return stem;
}

}  // namespace

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
                                                "gen_seconds_per_set",
                                                "setup_seconds_per_set"};
  return columns;
}

fs::path integrateCsvPath(const fs::path &outDir) { return outDir / "integrate.csv"; }

std::vector<std::string> splitList(const std::string &text) {
  std::vector<std::string> out;
  std::stringstream in(text);
  std::string item;
  while (std::getline(in, item, ',')) {
    const auto b = item.find_first_not_of(" \t"), e = item.find_last_not_of(" \t");
    if (b != std::string::npos) out.push_back(item.substr(b, e - b + 1));
  }
  return out;
}

std::vector<std::size_t> parseNList(const std::string &text) {
  const auto bad = [&](const std::string &why) {
    return std::invalid_argument("--n '" + text + "': " + why +
                                 " (expected positive integers separated by commas, e.g. "
                                 "16,32,64)");
  };
  std::vector<std::size_t> out;
  std::stringstream in(text);
  std::string item;
  while (std::getline(in, item, ',')) {
    const auto b = item.find_first_not_of(" \t"), e = item.find_last_not_of(" \t");
    if (b == std::string::npos) throw bad("empty item");
    item = item.substr(b, e - b + 1);
    if (item.find_first_not_of("0123456789") != std::string::npos)
      throw bad("'" + item + "' is not a positive integer");
    if (item.size() > 9) throw bad("'" + item + "' is too large");
    const std::size_t n = std::stoul(item);
    if (n == 0) throw bad("N must be at least 1");
    if (std::find(out.begin(), out.end(), n) == out.end()) out.push_back(n);
  }
  if (out.empty() || (!text.empty() && text.back() == ',')) throw bad("empty item");
  return out;
}

std::vector<SamplerChoice> parseSamplers(const std::vector<std::string> &tokens,
                                         const std::vector<std::string> &models) {
  using K = SamplerChoice::Kind;
  const std::vector<std::string> defaults{"independent", "sobol", "halton", "optimized"};
  std::vector<SamplerChoice> out;
  const auto add = [&](SamplerChoice c) {
    for (const auto &o : out) {
      if (o.name != c.name) continue;
      if (o.model != c.model)
        throw std::invalid_argument("--neural: models '" + o.model + "' and '" + c.model +
                                    "' would both be named '" + c.name + "' (rename one file)");
      return;
    }
    out.push_back(std::move(c));
  };
  const auto classic = [&](const std::string &base, K kind,
                           int which) {  // 1 plain, 2 lobes, 3 both
    if (which & 1) add({base, kind, false, {}});
    if (which & 2) add({base + "-lobes", kind, true, {}});
  };
  std::vector<std::string> modelList;
  for (const std::string &t : tokens.empty() ? defaults : tokens) {
    std::string base = t;
    int which = 3;
    if (base.ends_with("-lobes")) {
      base.resize(base.size() - 6);
      which = 2;
    }
    if (base == "independent" || base == "random")
      classic("independent", K::Independent, which);
    else if (base == "sobol")
      classic("sobol", K::Sobol, which);
    else if (base == "halton")
      classic("halton", K::Halton, which);
    else if (t == "optimized")
      add({"optimized", K::Optimized, false, {}});
    else if (t.rfind("neural:", 0) == 0 && t.size() > 7)
      modelList.push_back(t.substr(7));
    else
      throw std::invalid_argument(
          "--samplers: unknown sampler '" + t +
          "' (expected independent, sobol, halton, their -lobes variants such as sobol-lobes, "
          "optimized, or neural:MODEL)");
  }
  modelList.insert(modelList.end(), models.begin(), models.end());
  for (const auto &m : modelList) {
    if (m.empty()) throw std::invalid_argument("--neural: empty model path");
    add({"neural:" + fs::path(m).stem().string(), K::Neural, false, m});
  }
  return out;
}

double importanceEstimate(const Integrand &in, std::span<const Point2> points,
                          std::size_t &zeroPdf) {
  double sum = 0;
  for (const Point2 &x : points) {
    const double p = isFinite(x) ? in.target->pdf(x) : 0.0;
    const double v = p > 0 ? in.f(x) / p : 0.0;
    if (!(p > 0) || !std::isfinite(v)) {
      ++zeroPdf;
      continue;
    }
    sum += v;
  }
  return points.empty() ? 0.0 : sum / double(points.size());
}

EstimateStats summarize(std::span<const double> e, double reference) {
  const double K = double(e.size());
  if (e.size() < 2) throw std::invalid_argument("summarize: need at least 2 estimates");
  EstimateStats s;
  for (double v : e) s.mean += v / K;
  double var = 0, mse = 0;
  for (double v : e) {
    var += (v - s.mean) * (v - s.mean);
    mse += (v - reference) * (v - reference);
  }
  s.std = std::sqrt(var / (K - 1));
  s.bias = s.mean - reference;
  s.biasStderr = s.std / std::sqrt(K);
  s.rmse = std::sqrt(mse / K);
  s.relRmse = reference != 0 ? s.rmse / std::abs(reference) : NAN;
  return s;
}

std::vector<Integrand> selectIntegrands(const IntegrateOptions &o,
                                        std::vector<std::string> &notes) {
  const auto &kinds = integrandKinds();
  const auto wants = [&](const std::string &kind, const std::string &fullName) {
    if (o.integrands.empty()) return true;
    for (const auto &t : o.integrands)
      if (t == "all" || t == kind || t == fullName) return true;
    return false;
  };
  // Every token must name a kind or an integrand the maps make.
  std::vector<std::string> known = kinds;
  for (const auto &m : o.envmaps) {
    known.push_back("envmap:" + envmapShortName(m) + "*cos");
    known.push_back("disney*envmap:" + envmapShortName(m));
    known.push_back("disney-grazing*envmap:" + envmapShortName(m));
  }
  for (const auto &t : o.integrands)
    if (t != "all" && std::find(known.begin(), known.end(), t) == known.end())
      throw std::invalid_argument("--integrands: unknown integrand '" + t + "' (expected " +
                                  joinNames(known) + ")");

  std::vector<Integrand> out;
  if (wants(kinds[0], kinds[0])) out.push_back(makeGaussianStep());
  if (wants(kinds[1], kinds[1])) out.push_back(makeQuarterDiscBilinear());
  for (const auto &m : o.envmaps) {
    const std::string name = envmapShortName(m);
    const bool cosine = wants(kinds[2], "envmap:" + name + "*cos");
    const bool disney = wants(kinds[3], "disney*envmap:" + name);
    const bool grazing = wants(kinds[4], "disney-grazing*envmap:" + name);
    if (!cosine && !disney && !grazing) continue;
    std::shared_ptr<const StudyEnvmap> map;
    if (m == kSunMap) {
      // The stability case: the default scene's sky with a sun 1e6 times
      // brighter than its sky, built in so it needs no file.
      map = makeStudyEnvmap(proceduralSky(512, 256, 1e6), m, "procedural-sun-1e6");
    } else if (const auto path = findEnvmap(o.assetRoot, m)) {
      map = loadStudyEnvmap(*path, name);
    } else {
      notes.push_back("skipping the integrands of environment map '" + m + "': no file " + m +
                      "_latlong.exr/.hdr or " + m + ".exr/.hdr in " +
                      (fs::path(o.assetRoot) / "envmaps").string() + " (check --assets)");
      continue;
    }
    if (cosine) out.push_back(makeEnvmapCos(map));
    if (disney) out.push_back(makeDisneyEnvmap(map));
    if (grazing) {
      Integrand in = makeDisneyEnvmap(map, supplementDisneyParams(), grazingWo());
      in.name = "disney-grazing*envmap:" + name;
      out.push_back(std::move(in));
    }
  }
  for (const auto &in : out) {
    notes.push_back(in.name + ": reference " + formatPrecise(in.reference) + " (" +
                    in.referenceMethod + "; estimated error " +
                    formatNumber(in.referenceError / std::abs(in.reference)) + " relative)");
    if (in.referenceError > 1e-7 * std::abs(in.reference))
      notes.push_back("warning: the reference of " + in.name + " has converged only to " +
                      formatNumber(in.referenceError / std::abs(in.reference)) + " relative");
  }
  return out;
}

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

// One (integrand, sampler, N) measurement: K estimates and the time per set.
struct Measurement {
  std::vector<double> estimates;
  double genSeconds = 0, setupSeconds = 0;  // per set
  std::size_t zeroPdf = 0;
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

  Measurement classic(const Integrand &in, const SamplerChoice &s, std::size_t n) const {
    const SequenceKind kind = s.kind == SamplerChoice::Kind::Independent ? SequenceKind::Random
                              : s.kind == SamplerChoice::Kind::Halton    ? SequenceKind::Halton
                                                                         : SequenceKind::Sobol;
    const SequenceOptions so{kind, Scramble::Owen, seedFor(in, s, n)};
    Measurement m;
    std::vector<Point2> u(n), x(n);
    for (std::size_t k = 0; k < o_.instances; ++k) {
      const auto start = Clock::now();
      generateSet(so, std::uint32_t(k), u);
      if (s.lobes) {
        // sample() makes the direction, f and the pdf in one call, so the
        // time of a -lobes set covers its whole evaluation.
        double sum = 0;
        for (const Point2 &ui : u) {
          const double v = in.lobeContribution(ui);
          if (std::isfinite(v))
            sum += v;
          else
            ++m.zeroPdf;
        }
        m.genSeconds += secondsSince(start);
        m.estimates.push_back(sum / double(n));
        continue;
      }
      for (std::size_t i = 0; i < n; ++i) x[i] = in.target->invert(u[i]).x;
      m.genSeconds += secondsSince(start);
      m.estimates.push_back(importanceEstimate(in, x, m.zeroPdf));
    }
    m.genSeconds /= double(o_.instances);
    return m;
  }

  Measurement optimized(const Integrand &in, std::size_t n) {
    double setupPerSet = 0;
    const PointSet bank = bankFor(*in.target, n, setupPerSet);
    Measurement m;
    m.setupSeconds = setupPerSet;
    std::vector<Point2> x(n);
    for (std::size_t k = 0; k < o_.optimizedInstances; ++k) {
      const auto start = Clock::now();
      const auto set = bank.instance(k);
      std::copy(set.begin(), set.end(), x.begin());
      m.genSeconds += secondsSince(start);
      m.estimates.push_back(importanceEstimate(in, x, m.zeroPdf));
    }
    m.genSeconds /= double(o_.optimizedInstances);
    return m;
  }

  Measurement neural(const Integrand &in, const SamplerChoice &s, const NeuralModel &model) const {
    const std::size_t K = o_.optimizedInstances;
    const auto start = Clock::now();
    const PointSet sets = model.generator->generateSets(
        K, seedFor(in, s, model.generator->settings().n), model.gammaFor.at(in.name));
    Measurement m;
    m.genSeconds = secondsSince(start) / double(K);
    for (std::size_t k = 0; k < K; ++k)
      m.estimates.push_back(importanceEstimate(in, sets.instance(k), m.zeroPdf));
    return m;
  }

 private:
  std::uint64_t seedFor(const Integrand &in, const SamplerChoice &s, std::size_t n) const {
    return hash3(o_.seed, hashString(in.name + "|" + s.name), n);
  }

  // K optimized sets of N points for the target, from the cache or made now
  // (optimized_sets.h: checkpointed, so an interrupted study resumes it).
  PointSet bankFor(const Target &target, std::size_t n, double &secondsPerSet) {
    OptimizedSetsRequest request;
    request.n = n;
    request.instances = o_.optimizedInstances;
    request.epochs = o_.optEpochs;
    request.seed = o_.seed;
    OptimizerSettings settings = presetSettings(defaultPreset(target), n);
    settings.instances = request.instances;
    settings.seed = request.seed;
    if (request.epochs > 0) settings.epochs = request.epochs;
    const fs::path file = cachePath(o_.outDir / "cache", target, settings);
    const std::string what = "optimizing " + shortSpec(target.spec()) + " N=" + std::to_string(n) +
                             " (" + std::to_string(request.instances) + " sets)";
    int lastShown = -1;
    const OptimizedSets made =
        study::optimizedSets(target, request, file, [&](int epoch, int epochs, double) {
          const int percent = int(100.0 * epoch / epochs);
          if (percent == lastShown) return;
          lastShown = percent;
          progress(what + " epoch " + std::to_string(epoch) + "/" + std::to_string(epochs));
        });
    (made.cached ? summary_.setsFromCache : summary_.setsOptimized) += request.instances;
    secondsPerSet = made.seconds / double(request.instances);
    PointSet set = readPointSet(made.file.string());
    if (set.n != n || set.instances() < request.instances)
      throw std::runtime_error(made.file.string() + ": expected " +
                               std::to_string(request.instances) + " sets of " + std::to_string(n) +
                               " points");
    return set;
  }

  const IntegrateOptions &o_;
  const IntegrateHooks &hooks_;
  IntegrateSummary &summary_;
  long done_ = 0, total_ = 0;
};

}  // namespace

IntegrateSummary runIntegrateStudy(const IntegrateOptions &o, const IntegrateHooks &hooks) {
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

  IntegrateSummary summary;
  StudyRunner runner(o, hooks, summary);
  const auto samplers = parseSamplers(o.samplers, o.neuralModels);
  std::vector<std::string> notes;
  const auto integrands = selectIntegrands(o, notes);
  for (const auto &n : notes) runner.note(n);
  std::map<std::string, NeuralModel> models;
  for (const auto &s : samplers)
    if (s.kind == SamplerChoice::Kind::Neural) models.emplace(s.name, loadModel(s, integrands));

  // The rows to make, in order: integrand, sampler, N.
  struct Task {
    const Integrand *in;
    const SamplerChoice *s;
    std::size_t n;
  };
  std::vector<Task> tasks;
  for (const auto &in : integrands)
    for (const auto &s : samplers) {
      if (s.lobes && !in.lobeContribution) continue;
      if (s.kind == SamplerChoice::Kind::Neural) {
        const NeuralModel &m = models.at(s.name);
        if (m.gammaFor.count(in.name)) tasks.push_back({&in, &s, m.generator->settings().n});
        continue;
      }
      for (std::size_t n : o.ns)
        if (s.kind != SamplerChoice::Kind::Optimized || n <= o.optimizedMaxN)
          tasks.push_back({&in, &s, n});
    }

  CsvTable table(integrateCsvPath(o.outDir), integrateColumns());
  table.loadExisting();
  runner.setTotal(long(tasks.size()));
  for (const Task &t : tasks) {
    const std::string domain = toString(t.in->domain()), n = std::to_string(t.n);
    const std::string row = t.in->name + " " + t.s->name + " N=" + n;
    if (table.hasRow({t.in->name, domain, t.s->name, n})) {
      ++summary.rowsSkipped;
      runner.advance();
      runner.progress(row + " (already in the CSV)");
      continue;
    }
    runner.progress(row);
    Measurement m;
    std::size_t K = o.instances;
    switch (t.s->kind) {
      case SamplerChoice::Kind::Optimized:
        m = runner.optimized(*t.in, t.n);
        K = o.optimizedInstances;
        break;
      case SamplerChoice::Kind::Neural:
        m = runner.neural(*t.in, *t.s, models.at(t.s->name));
        K = o.optimizedInstances;
        break;
      default: m = runner.classic(*t.in, *t.s, t.n);
    }
    const EstimateStats st = summarize(m.estimates, t.in->reference);
    const std::vector<double> values{t.in->reference, st.mean,      st.bias,
                                     st.biasStderr,   st.std,       st.rmse,
                                     st.relRmse,      m.genSeconds, m.setupSeconds};
    for (double v : values)
      if (!std::isfinite(v))
        throw std::runtime_error("study integrate: " + row + " gave a value that is not finite");
    if (m.zeroPdf > 0)
      runner.note("note: " + row + ": " + std::to_string(m.zeroPdf) + " of " +
                  std::to_string(K * t.n) +
                  " points had zero density (or a non-finite weight) and counted as 0; this "
                  "shows as bias");
    table.addRow({t.in->name, domain, t.s->name, n, std::to_string(K),
                  formatPrecise(t.in->reference), formatPrecise(st.mean), formatNumber(st.bias),
                  formatNumber(st.biasStderr), formatNumber(st.std), formatNumber(st.rmse),
                  formatNumber(st.relRmse), formatNumber(m.genSeconds),
                  formatNumber(m.setupSeconds)});
    ++summary.rowsAdded;
    runner.advance();
    runner.progress(row);
  }
  return summary;
}

std::optional<std::string> runIntegratePlots(const fs::path &outDir) {
  std::string why;
  // report.py draws plot_integrate.py's plots and the HTML page with them.
  const int status = runStudyScript("report.py", outDir, &why);
  if (status == 0) return std::nullopt;
  if (status < 0) return why + "; no plots made (the CSV is complete)";
  return "report.py exited with status " + std::to_string(status) +
         " (is python3-matplotlib installed?); the CSV is complete";
}

std::string rmseTable(const CsvTable &table) {
  const auto col = [&](const std::string &name) { return table.column(name); };
  const std::size_t ci = col("integrand"), cs = col("sampler"), cn = col("n"), cr = col("rmse"),
                    cref = col("reference");
  std::vector<std::string> integrands;
  for (const auto &r : table.rows())
    if (std::find(integrands.begin(), integrands.end(), r[ci]) == integrands.end())
      integrands.push_back(r[ci]);
  std::ostringstream out;
  for (const auto &name : integrands) {
    std::vector<std::string> samplers;
    std::set<std::size_t> ns;
    std::map<std::pair<std::string, std::size_t>, std::string> cell;
    std::string reference;
    for (const auto &r : table.rows()) {
      if (r[ci] != name) continue;
      if (std::find(samplers.begin(), samplers.end(), r[cs]) == samplers.end())
        samplers.push_back(r[cs]);
      const std::size_t n = std::stoul(r[cn]);
      ns.insert(n);
      char buf[32];
      std::snprintf(buf, sizeof buf, "%.3g", std::stod(r[cr]));
      cell[{r[cs], n}] = buf;
      reference = r[cref];
    }
    std::size_t width = 8;
    for (const auto &s : samplers) width = std::max(width, s.size() + 1);
    out << name << "  (RMSE; reference " << reference << ")\n";
    char buf[64];
    std::snprintf(buf, sizeof buf, "%-*s", int(width), "sampler");
    out << buf;
    for (std::size_t n : ns) {
      std::snprintf(buf, sizeof buf, " %9s", ("N=" + std::to_string(n)).c_str());
      out << buf;
    }
    out << "\n";
    for (const auto &s : samplers) {
      std::snprintf(buf, sizeof buf, "%-*s", int(width), s.c_str());
      out << buf;
      for (std::size_t n : ns) {
        const auto it = cell.find({s, n});
        std::snprintf(buf, sizeof buf, " %9s", it == cell.end() ? "-" : it->second.c_str());
        out << buf;
      }
      out << "\n";
    }
    out << "\n";
  }
  return out.str();
}

}  // namespace nuld::study
