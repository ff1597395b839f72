#include "tools/study/reference_render.h"

#include <chrono>
#include <fstream>
#include <map>
#include <sstream>
#include <stdexcept>

#include "renderer/backend_registry.h"
#include "renderer/image_metrics.h"
#include "renderer/sampler_backend.h"
#include "sampler/io/atomic_file.h"
#include "sampler/io/image_io.h"
#include "tools/study/ranks.h"

namespace nuld::study {

namespace fs = std::filesystem;

std::string ReferenceSettings::describe(const std::string &sceneName) const {
  std::ostringstream s;
  s << "scene=" << sceneName << " backend=" << backend << " spp=" << totalSpp()
    << " pass_spp=" << samplesPerPass() << " seed=" << seed << " res=" << render.width << "x"
    << render.height << " integrator=" << toString(render.integrator)
    << " max_depth=" << render.maxDepth << " renderer=" << kRendererRevision;
  return s.str();
}

namespace {

struct State {
  std::string description;
  std::size_t passesDone = 0;
  double seconds = 0;  // render time of all passes, over every run
};

std::map<std::string, std::string> readKeyValues(const fs::path &path) {
  std::ifstream in(path);
  if (!in) throw std::runtime_error(path.string() + ": cannot read the reference state");
  std::map<std::string, std::string> kv;
  std::string line;
  while (std::getline(in, line)) {
    const auto eq = line.find('=');
    if (eq != std::string::npos) kv[line.substr(0, eq)] = line.substr(eq + 1);
  }
  return kv;
}

State readState(const fs::path &path) {
  auto kv = readKeyValues(path);
  State s;
  s.description = kv["description"];
  try {
    s.passesDone = std::stoul(kv.at("passes_done"));
  } catch (...) {
    throw std::runtime_error(path.string() +
                             ": field 'passes_done' missing or not a count (expected an integer)");
  }
  try {
    s.seconds = kv.count("seconds") ? std::stod(kv["seconds"]) : 0.0;
  } catch (...) {
    throw std::runtime_error(path.string() + ": field 'seconds' is not a number");
  }
  return s;
}

void writeState(const fs::path &path, const State &s) {
  writeFileAtomically(path, "description=" + s.description +
                                "\npasses_done=" + std::to_string(s.passesDone) +
                                "\nseconds=" + std::to_string(s.seconds) + "\n");
}

void checkDescription(const fs::path &stateFile, const State &s, const std::string &expected) {
  if (s.description != expected)
    throw std::runtime_error(stateFile.string() + ": made with '" + s.description +
                             "', but this study asks for '" + expected +
                             "' (use another output directory, or delete the reference)");
}

}  // namespace

ReferenceResult renderReference(const Scene &scene, const std::string &sceneName,
                                const ReferenceSettings &settings, const fs::path &dir,
                                const std::function<void(const ReferenceProgress &)> &progress,
                                std::size_t stopAfterPasses) {
  if (settings.passSpp == 0 || settings.spp == 0)
    throw std::invalid_argument("reference: spp and pass spp must be positive");
  const Ranks &ranks = Ranks::world();
  const fs::path finalPath = dir / "reference.exr", partialPath = dir / "reference.partial.exr",
                 statePath = dir / "reference.state";
  const std::string description = settings.describe(sceneName);
  const std::size_t passes = settings.passes();
  RenderSettings rs = settings.render;
  rs.spp = settings.samplesPerPass();

  // Rank 0 alone reads and writes the files; the others learn how far the
  // reference is and, at the end, receive the image.
  State state{description, 0};
  ReferenceResult result;
  Image sum;
  bool alreadyComplete = false;
  if (ranks.root()) {
    fs::create_directories(dir);
    if (fs::exists(statePath)) {
      state = readState(statePath);
      checkDescription(statePath, state, description);
    }
    alreadyComplete = state.passesDone >= passes && fs::exists(finalPath);
    if (alreadyComplete) {
      result.image = readImage(finalPath.string());
    } else if (state.passesDone > 0) {
      sum = readImage(partialPath.string());
      if (sum.width != rs.width || sum.height != rs.height || sum.channels != 3)
        throw std::runtime_error(partialPath.string() + ": size differs from the state's");
    } else {
      sum = Image{rs.width, rs.height, 3,
                  std::vector<float>(std::size_t(rs.width) * rs.height * 3, 0.0f)};
    }
  }
  {
    const std::string bytes = ranks.broadcast(
        ByteWriter().put(state.passesDone).put(state.seconds).put(alreadyComplete).take());
    ByteReader r(bytes);
    r.get(state.passesDone);
    r.get(state.seconds);
    r.get(alreadyComplete);
  }

  if (!alreadyComplete) {
    // Rounds of one pass per rank; rank 0 adds the passes in their order, so
    // the sum is the one a single process makes.
    const std::size_t K = std::size_t(ranks.size());
    const std::size_t first = state.passesDone;
    const std::size_t last = stopAfterPasses ? std::min(passes, first + stopAfterPasses) : passes;
    const auto start = std::chrono::steady_clock::now();
    runInRounds(
        ranks, last - first,
        [&](std::size_t i) {
          const std::size_t pass = first + i;
          const std::size_t roundFirst = first + i / K * K;
          const std::size_t roundSize = std::min(last, roundFirst + K) - roundFirst;
          const auto passStart = std::chrono::steady_clock::now();
          const auto backend = makeBackend(settings.backend, settings.seed + pass);
          const Image image =
              render(scene, rs, *backend, nullptr, [&](std::size_t d, std::size_t n) {
                if (progress && ranks.root())
                  progress(
                      {roundFirst, passes,
                       (double(roundFirst) + double(roundSize) * double(d) / double(n)) / passes});
              });
          const double seconds =
              std::chrono::duration<double>(std::chrono::steady_clock::now() - passStart).count();
          return ByteWriter().put(seconds).put(image).take();
        },
        [&](std::size_t, const std::string &bytes) {
          ByteReader r(bytes);
          state.seconds += r.get<double>();
          const Image image = r.get<Image>();
          for (std::size_t i = 0; i < sum.pixels.size(); ++i) sum.pixels[i] += image.pixels[i];
        },
        [&](std::size_t collected) {
          state.passesDone = first + collected;
          // The image first: a state that counts a pass always has its sum on disk.
          writeImage(partialPath.string(), sum);
          writeState(statePath, state);
          if (progress) progress({state.passesDone, passes, double(state.passesDone) / passes});
        });
    // The other ranks learn the count here; rank 0 has it from the rounds.
    state.passesDone = last;
    result.passesRun = last - first;
    result.seconds =
        std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  }

  result.complete = state.passesDone >= passes;
  state.seconds = fromBytes<double>(ranks.broadcast(ByteWriter().put(state.seconds).take()));
  result.totalSeconds = state.seconds;
  if (ranks.root() && !alreadyComplete) {
    const float scale = 1.0f / float(state.passesDone);
    result.image = sum;
    for (float &v : result.image.pixels) v *= scale;
    if (result.complete) {
      RenderSettings whole = rs;
      whole.spp = settings.totalSpp();
      RenderStats stats;
      stats.seconds = state.seconds;
      ImageAttributes attributes =
          renderAttributes(sceneName, scene.lobeChoice, whole, settings.backend, settings.seed, stats);
      attributes.emplace_back("nuld:reference", description);
      writeRender(finalPath.string(), result.image, attributes);
      fs::remove(partialPath);
    }
  }
  // Every rank scores its renders against the same image.
  if (ranks.distributed())
    result.image = fromBytes<Image>(
        ranks.broadcast(ranks.root() ? ByteWriter().put(result.image).take() : std::string()));
  return result;
}

}  // namespace nuld::study
