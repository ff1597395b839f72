#include "backends/reference_render.h"

#include <chrono>
#include <fstream>
#include <iostream>
#include <map>
#include <sstream>
#include <stdexcept>

#include "backends/backend_registry.h"
#include "backends/ranks.h"
#include "backends/ready_backend.h"
#include "renderer/image_metrics.h"
#include "renderer/sampler_backend.h"
#include "sampler/io/atomic_file.h"
#include "sampler/io/content_hash.h"
#include "sampler/io/image_io.h"
#include "sampler/io/round_trip.h"

namespace nuld {

namespace fs = std::filesystem;

std::string ReferenceSettings::describe(const Scene &scene) const {
  std::ostringstream s;
  s << "content=" << sceneContentKey(scene) << " backend=" << backend << " spp=" << totalSpp()
    << " pass_spp=" << samplesPerPass() << " seed=" << seed << " res=" << render.width << "x"
    << render.height << " integrator=" << toString(render.integrator)
    << " max_depth=" << render.maxDepth << " roulette_depth=" << render.rouletteDepth;
  // Lobe tables change a render only through a backend that samples lobes.
  if (parseBackendWord(backend).samplesLobes()) {
    const LobeTableSettings &t = render.lobeTables;
    s << " lobe_tables=" << t.thetaBins << "x" << t.phiBins << "/" << t.phiCells << ","
      << (t.samplingMix ? formatNumber(*t.samplingMix) : "auto") << "," << toString(t.routing)
      << "," << formatNumber(t.defensive) << "," << t.bounces;
  }
  s << " renderer=" << kRendererRevision << " halves=2";
  return s.str();
}

std::string referenceProgressText(const ReferenceProgress &p) {
  if (p.waiting) return "waiting for another process making this reference";
  return "pass " + std::to_string(p.passesDone) + "/" + std::to_string(p.passes);
}

ReferenceNoise referenceNoise(const Image &half0, const Image &half1) {
  if (half0.width != half1.width || half0.height != half1.height ||
      half0.channels != half1.channels || half0.pixels.size() != half1.pixels.size())
    throw std::invalid_argument("referenceNoise: the halves differ in size");
  // relMSE's weight, as compareImages has it.
  double sum = 0, relSum = 0;
  for (std::size_t i = 0; i < half0.pixels.size(); ++i) {
    const double a = half0.pixels[i], b = half1.pixels[i], r = 0.5 * (a + b);
    const double v = 0.25 * (a - b) * (a - b);
    sum += v;
    relSum += v / (r * r + kRelMseEpsilon);
  }
  const double n = double(std::max<std::size_t>(1, half0.pixels.size()));
  return {sum / n, relSum / n};
}

namespace {

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

}  // namespace

ReferenceState readReferenceState(const fs::path &path) {
  auto kv = readKeyValues(path);
  ReferenceState s;
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

namespace {

void writeState(const fs::path &path, const ReferenceState &s) {
  writeFileAtomically(path, "description=" + s.description +
                                "\npasses_done=" + std::to_string(s.passesDone) +
                                "\nseconds=" + std::to_string(s.seconds) + "\n");
}

void checkDescription(const fs::path &stateFile, const ReferenceState &s,
                      const std::string &expected) {
  // Without halves its noise cannot be measured, and rows scored against it
  // would stand beside rows flagged by that noise: refused, not reused.
  if (s.description.find(" halves=") == std::string::npos)
    throw std::runtime_error(
        stateFile.string() +
        ": this reference was rendered by an older nuld without two independent halves, so "
        "its own noise cannot be estimated; use a new output directory (the rows beside it "
        "were scored against it), or delete " +
        (stateFile.parent_path() / "reference.*").string() + " to render it again");
  if (s.description != expected)
    throw std::runtime_error(stateFile.string() + ": made with '" + s.description +
                             "', but this study asks for '" + expected +
                             "' (use another output directory, or delete the reference)");
}

// The sums of both halves in one six-channel image that also records the
// passes and seconds it holds: one atomic write, so that a job killed
// between two writes never leaves a sum and its count apart (the image is
// what a resume believes; the state file may lag it by a round).
struct PartialSums {
  Image sum[2];
  std::size_t passesDone = 0;
  double seconds = 0;
};

// What proves a reference's image (its sums, halves and mean): the hash of
// its floats, recorded beside its description. An image edited, swapped
// for another valid image or damaged is never read as the reference.
constexpr const char *kPixelsHash = "nuld:pixels_hash";

std::string pixelsHash(const Image &image) {
  return ContentHash()
      .add(std::string_view(reinterpret_cast<const char *>(image.pixels.data()),
                            image.pixels.size() * sizeof(float)))
      .hex();
}

// A damaged entry: the reference starts again (renderReference).
struct DamagedReference : std::runtime_error {
  using std::runtime_error::runtime_error;
};

// `path` read and proved: it decodes, was made for `description`, and its
// floats hash to the recorded hash; else DamagedReference saying why.
Image readProved(const fs::path &path, const std::string &description) {
  Image image;
  std::map<std::string, std::string> kv;
  try {
    image = readImage(path.string());
    for (const auto &[name, value] : readImageAttributes(path.string())) kv[name] = value;
  } catch (const std::exception &e) {
    throw DamagedReference(e.what());
  }
  if (kv["nuld:reference"] != description)
    throw DamagedReference(path.string() + ": made for another reference");
  if (kv[kPixelsHash] != pixelsHash(image))
    throw DamagedReference(path.string() + ": its pixels do not match the hash recorded with them");
  return image;
}

ImageAttributes proved(ImageAttributes attributes, const Image &image) {
  attributes.emplace_back(kPixelsHash, pixelsHash(image));
  return attributes;
}

void writePartial(const fs::path &path, const PartialSums &p, const std::string &description) {
  const Image &a = p.sum[0], &b = p.sum[1];
  Image both{a.width, a.height, 6, std::vector<float>(a.pixels.size() * 2)};
  for (std::size_t i = 0; i < a.pixels.size() / 3; ++i)
    for (int c = 0; c < 3; ++c) {
      both.pixels[6 * i + c] = a.pixels[3 * i + c];
      both.pixels[6 * i + 3 + c] = b.pixels[3 * i + c];
    }
  writeImage(path.string(), both,
             proved({{"nuld:reference", description},
                     {"nuld:passes_done", std::to_string(p.passesDone)},
                     {"nuld:seconds", std::to_string(p.seconds)}},
                    both));
}

PartialSums readPartial(const fs::path &path, int width, int height,
                        const std::string &description) {
  const Image both = readProved(path, description);
  if (both.width != width || both.height != height || both.channels != 6)
    throw DamagedReference(path.string() + ": size differs from the state's");
  PartialSums p;
  for (Image &sum : p.sum)
    sum = Image{width, height, 3, std::vector<float>(std::size_t(width) * height * 3)};
  for (std::size_t i = 0; i < p.sum[0].pixels.size() / 3; ++i)
    for (int c = 0; c < 3; ++c) {
      p.sum[0].pixels[3 * i + c] = both.pixels[6 * i + c];
      p.sum[1].pixels[3 * i + c] = both.pixels[6 * i + 3 + c];
    }
  std::map<std::string, std::string> kv;
  for (const auto &[name, value] : readImageAttributes(path.string())) kv[name] = value;
  try {
    p.passesDone = std::stoul(kv.at("nuld:passes_done"));
    p.seconds = std::stod(kv.at("nuld:seconds"));
  } catch (...) {
    throw DamagedReference(path.string() +
                           ": attributes nuld:passes_done and nuld:seconds missing or not numbers");
  }
  return p;
}

}  // namespace

std::string referenceProblem(const fs::path &dir) {
  try {
    // No state yet: made before its first pass ended, nothing counted.
    if (std::error_code ec;
        !fs::exists(dir / "reference.state", ec) && !fs::exists(dir / "reference.exr", ec))
      return "";
    const ReferenceState state = readReferenceState(dir / "reference.state");
    if (std::error_code ec; fs::exists(dir / "reference.exr", ec)) {
      for (const char *name : {"reference.exr", "reference.half0.exr", "reference.half1.exr"})
        readProved(dir / name, state.description);
    } else if (state.passesDone > 0) {
      readProved(dir / "reference.partial.exr", state.description);
    }
    return "";
  } catch (const std::exception &e) {
    return e.what();
  }
}

ReferenceResult renderReference(const Scene &scene, const std::string &sceneName,
                                const ReferenceSettings &settings, const fs::path &dir,
                                const std::function<void(const ReferenceProgress &)> &progress,
                                std::size_t stopAfterPasses, const std::string &described) {
  if (settings.passSpp == 0 || settings.spp == 0)
    throw std::invalid_argument("reference: spp and pass spp must be positive");
  const Ranks &ranks = Ranks::world();
  const fs::path finalPath = dir / "reference.exr", statePath = dir / "reference.state";
  // Half h holds the passes p with p % 2 == h: their sum while in progress,
  // their mean when complete.
  const fs::path halfPath[2] = {dir / "reference.half0.exr", dir / "reference.half1.exr"};
  const fs::path partialPath = dir / "reference.partial.exr";
  const std::string description = described.empty() ? settings.describe(scene) : described;
  const std::size_t passes = settings.passes();
  RenderSettings rs = settings.render;
  rs.spp = settings.samplesPerPass();

  // Rank 0 alone reads and writes the files; the others learn how far the
  // reference is and, at the end, receive the image.
  ReferenceState state{description, 0};
  ReferenceResult result;
  PartialSums partial;
  Image(&sum)[2] = partial.sum;
  bool alreadyComplete = false;
  if (ranks.root()) {
    fs::create_directories(dir);
    if (fs::exists(statePath)) {
      state = readReferenceState(statePath);
      checkDescription(statePath, state, description);
    }
    alreadyComplete = state.passesDone >= passes && fs::exists(finalPath);
    // What the entry holds is proved before it is used; a damaged entry
    // (an image that does not decode, was swapped or edited) is rendered
    // again from its first pass, said on stderr, and never served.
    try {
      if (alreadyComplete) {
        result.image = readProved(finalPath, description);
        result.noise = referenceNoise(readProved(halfPath[0], description),
                                      readProved(halfPath[1], description));
        if (result.image.width != rs.width || result.image.height != rs.height)
          throw DamagedReference(finalPath.string() + ": size differs from the state's");
      } else if (state.passesDone > 0) {
        partial = readPartial(partialPath, rs.width, rs.height, description);
        state.passesDone = partial.passesDone;
        state.seconds = partial.seconds;
      }
    } catch (const DamagedReference &e) {
      std::cerr << "\nnuld: note: the reference in " << dir.string() << " is damaged (" << e.what()
                << "); rendering it again\n";
      for (const fs::path &file : {finalPath, fs::path(finalPath).replace_extension(".png"),
                                   halfPath[0], halfPath[1], partialPath})
        fs::remove(file);
      state = ReferenceState{description, 0};
      writeState(statePath, state);
      alreadyComplete = false;
    }
    if (state.passesDone == 0)
      for (Image &half : sum)
        half = Image{rs.width, rs.height, 3,
                     std::vector<float>(std::size_t(rs.width) * rs.height * 3, 0.0f)};
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
    // the sums are the ones a single process makes.
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
        [&](std::size_t i, const std::string &bytes) {
          ByteReader r(bytes);
          state.seconds += r.get<double>();
          const Image image = r.get<Image>();
          Image &half = sum[(first + i) % 2];
          for (std::size_t k = 0; k < half.pixels.size(); ++k) half.pixels[k] += image.pixels[k];
        },
        [&](std::size_t collected) {
          state.passesDone = first + collected;
          // The sums first: a state that counts a pass always has its sum on disk.
          partial.passesDone = state.passesDone;
          partial.seconds = state.seconds;
          writePartial(partialPath, partial, description);
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
    // The mean of all passes so far, and of each half's (even: the extra one).
    const std::size_t done = state.passesDone;
    const std::size_t count[2] = {(done + 1) / 2, done / 2};
    result.image = sum[0];
    for (std::size_t k = 0; k < result.image.pixels.size(); ++k)
      result.image.pixels[k] = (sum[0].pixels[k] + sum[1].pixels[k]) / float(done);
    if (result.complete) {
      Image mean[2] = {sum[0], sum[1]};
      for (int h = 0; h < 2; ++h)
        for (float &v : mean[h].pixels) v /= float(count[h]);
      result.noise = referenceNoise(mean[0], mean[1]);
      RenderSettings whole = rs;
      whole.spp = settings.totalSpp();
      RenderStats stats;
      stats.seconds = state.seconds;
      ImageAttributes attributes =
          renderAttributes(sceneName, scene, whole, settings.backend, settings.seed, stats);
      attributes.emplace_back("nuld:reference", description);
      // The halves before the reference: a reference on disk has its halves.
      for (int h = 0; h < 2; ++h)
        writeImage(halfPath[h].string(), mean[h], proved(attributes, mean[h]));
      writeRender(finalPath.string(), result.image, proved(attributes, result.image));
      fs::remove(partialPath);
    }
  }
  // Every rank scores its renders against the same image.
  if (ranks.distributed()) {
    const std::string bytes = ranks.broadcast(ranks.root() ? ByteWriter()
                                                                 .put(result.image)
                                                                 .put(result.noise.variance)
                                                                 .put(result.noise.relVariance)
                                                                 .take()
                                                           : std::string());
    ByteReader r(bytes);
    r.get(result.image);
    r.get(result.noise.variance);
    r.get(result.noise.relVariance);
  }
  return result;
}

}  // namespace nuld
