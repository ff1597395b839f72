#include "sampler/targets/target_spec.h"

#include <algorithm>
#include <charconv>
#include <cmath>
#include <filesystem>
#include <map>
#include <mutex>
#include <optional>
#include <sstream>
#include <stdexcept>

#include "sampler/enum_names.h"
#include "sampler/io/pointset_metadata.h"
#include "sampler/targets/basic_targets.h"
#include "sampler/targets/image_targets.h"

namespace nuld {
namespace {

struct Registered {
  TargetFactory factory;
  TargetDescription description;
};
std::map<std::string, Registered> &registry() {
  static std::map<std::string, Registered> r;
  return r;
}
std::mutex &registryMutex() {
  static std::mutex m;
  return m;
}

// The targets read from an image file (`NAME:PATH`), one table for
// makeTarget (which loads them) and sameTarget (which compares their files):
// an image on the square, or an environment map with its pixel weight.
struct ImageKind {
  std::string name;
  std::optional<PixelWeight> envmapWeight;
};

const std::vector<ImageKind> &imageKinds() {
  static const std::vector<ImageKind> kinds{
      {"image", std::nullopt},
      {envmapFamily(PixelWeight::Luminance), PixelWeight::Luminance},
      {envmapFamily(PixelWeight::ChannelMean), PixelWeight::ChannelMean},
      {envmapFamily(PixelWeight::LuminanceCompensated), PixelWeight::LuminanceCompensated},
      {envmapFamily(PixelWeight::ChannelMeanCompensated), PixelWeight::ChannelMeanCompensated}};
  return kinds;
}

const ImageKind *findImageKind(const std::string &name) {
  for (const ImageKind &kind : imageKinds())
    if (kind.name == name) return &kind;
  return nullptr;
}

// Every family a spec may start with: the word of each grammar.
std::vector<std::string> targetFamilies() {
  std::vector<std::string> families;
  for (const TargetDescription &d : targetDescriptions())
    families.push_back(d.grammar.substr(0, d.grammar.find_first_of(":[ ")));
  return families;
}

// Every family's grammar, the closest to `family` first.
std::invalid_argument unknownTarget(const std::string &spec, const std::string &family) {
  std::string known;
  for (const TargetDescription &d : targetDescriptions())
    known += (known.empty() ? "" : ", ") + d.grammar;
  return std::invalid_argument("unknown target '" + spec + "'" +
                               didYouMean(family, targetFamilies()) +
                               " (expected one of: " + known + "; nuld help targets)");
}

}  // namespace

void registerTargetKind(const std::string &name, TargetFactory factory, const std::string &grammar,
                        const std::string &description) {
  std::lock_guard lock(registryMutex());
  registry()[name] = {std::move(factory),
                      {grammar.empty() ? name + ":ARGS" : grammar, description}};
}

std::vector<TargetDescription> targetDescriptions() {
  std::vector<TargetDescription> out{
      {"uniform", "the unit square"},
      {"bilinear:w00,w10,w01,w11", "bilinear in the four corner weights (>= 0, not all 0)"},
      {"gaussian:mx,my,sigma", "a normal density truncated to the square"},
      {"quarterdisc", "uniform on the quarter disc x^2 + y^2 < 1"},
      {"step:x0[,left,right]", "density `left` below x0 and `right` above (default 0,1)"},
      {"image:PATH", "the luminance of any image OpenImageIO reads, upright"},
      {std::string(envmapFamily(PixelWeight::Luminance)) + ":PATH",
       "a lat-long environment map on the sphere (phi = 2 pi u, cos theta = 1 - 2v), texels "
       "weighted by luminance"},
      {std::string(envmapFamily(PixelWeight::ChannelMean)) + ":PATH",
       "the same with texels weighted by the mean of their channels"},
      {std::string(envmapFamily(PixelWeight::LuminanceCompensated)) + ":PATH",
       "envmap: less its mean over the sphere, clamped at 0 (MIS compensation)"},
      {std::string(envmapFamily(PixelWeight::ChannelMeanCompensated)) + ":PATH",
       "envmap-mean: less its mean over the sphere, clamped at 0"},
  };
  std::lock_guard lock(registryMutex());
  for (const auto &[name, r] : registry()) out.push_back(r.description);
  return out;
}

std::vector<double> parseNumberList(const std::string &spec, const std::string &args,
                                    std::size_t minCount, std::size_t maxCount,
                                    const std::string &expected) {
  std::vector<double> values;
  std::size_t pos = 0;
  while (!args.empty() && pos <= args.size()) {
    const std::size_t comma = std::min(args.find(',', pos), args.size());
    const std::string item = args.substr(pos, comma - pos);
    double v = 0;
    const auto [end, ec] = std::from_chars(item.data(), item.data() + item.size(), v);
    if (item.empty() || ec != std::errc() || end != item.data() + item.size() || !std::isfinite(v))
      throw std::invalid_argument("target '" + spec + "': '" + item +
                                  "' is not a number (expected " + expected + ")");
    values.push_back(v);
    pos = comma + 1;
  }
  if (values.size() < minCount || values.size() > maxCount)
    throw std::invalid_argument("target '" + spec + "': got " + std::to_string(values.size()) +
                                " numbers, expected " + expected);
  return values;
}

std::unique_ptr<Target> makeTarget(const std::string &spec) {
  const std::size_t colon = spec.find(':');
  const std::string family = spec.substr(0, colon);
  const std::string args = colon == std::string::npos ? "" : spec.substr(colon + 1);
  auto noArgs = [&] {
    if (!args.empty())
      throw std::invalid_argument("target '" + spec + "': '" + family + "' takes no parameters");
  };
  if (family == "uniform") {
    noArgs();
    return std::make_unique<UniformTarget>();
  }
  if (family == "quarterdisc") {
    noArgs();
    return std::make_unique<QuarterDiscTarget>();
  }
  try {
    if (family == "bilinear") {
      const auto w = parseNumberList(spec, args, 4, 4, "4 weights w00,w10,w01,w11");
      return std::make_unique<BilinearTarget>(w[0], w[1], w[2], w[3]);
    }
    if (family == "gaussian") {
      const auto g = parseNumberList(spec, args, 3, 3, "3 numbers mx,my,sigma");
      return std::make_unique<GaussianTarget>(g[0], g[1], g[2]);
    }
    if (family == "step") {
      const auto s = parseNumberList(spec, args, 1, 3, "x0 or x0,left,right");
      return std::make_unique<StepTarget>(s[0], s.size() > 1 ? s[1] : 0.0,
                                          s.size() > 2 ? s[2] : 1.0);
    }
  } catch (const std::invalid_argument &e) {
    const std::string what = e.what();
    if (what.rfind("target '", 0) == 0) throw;
    throw std::invalid_argument("target '" + spec + "': " + what);
  }
  if (const ImageKind *image = findImageKind(family)) {
    if (args.empty())
      throw std::invalid_argument("target '" + spec + "': expected a file path after '" + family +
                                  ":'");
    if (!image->envmapWeight) return loadImageTarget(args);
    return loadEnvmapTarget(args, *image->envmapWeight);
  }
  TargetFactory factory;
  {
    std::lock_guard lock(registryMutex());
    auto it = registry().find(family);
    if (it != registry().end()) factory = it->second.factory;
  }
  if (factory) return factory(args);
  throw unknownTarget(spec, family);
}

void checkTargetFamily(const std::string &spec) {
  const std::string family = spec.substr(0, spec.find(':'));
  const std::vector<std::string> known = targetFamilies();
  if (std::find(known.begin(), known.end(), family) == known.end())
    throw unknownTarget(spec, family);
}

std::vector<std::size_t> parseSizeList(const std::string &what, const std::string &text) {
  const auto bad = [&](const std::string &why) {
    return std::invalid_argument(what + " '" + text + "': " + why +
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

bool sameTarget(const std::string &a, const std::string &b) {
  if (a == b) return true;
  const auto colonA = a.find(':'), colonB = b.find(':');
  if (colonA == std::string::npos || colonB == std::string::npos) return false;
  const std::string familyA = a.substr(0, colonA), familyB = b.substr(0, colonB);
  if (familyA != familyB || !findImageKind(familyA)) return false;
  std::error_code ec;
  const std::filesystem::path pa = a.substr(colonA + 1), pb = b.substr(colonB + 1);
  return std::filesystem::equivalent(pa, pb, ec) && !ec;
}

void recordTarget(PointSet &set, const Target &target) {
  setMeta(set, meta::kTarget, target.spec());
  setMeta(set, meta::kTargetHash, target.contentHash());
  setMeta(set, meta::kDomain, toString(target.domain()));
}

bool followsTarget(const PointSet &set, const std::string &spec, const std::string &contentHash) {
  const std::string recorded = metaOr(set, meta::kTarget, "uniform");
  if (sameTarget(recorded, spec)) return true;
  const std::string *hash = findMeta(set, meta::kTargetHash);
  return hash && !contentHash.empty() && *hash == contentHash;
}

}  // namespace nuld
