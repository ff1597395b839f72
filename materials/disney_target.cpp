#include "materials/disney_target.h"

#include <tbb/parallel_for.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <numbers>
#include <stdexcept>
#include <vector>

#include "materials/sampling.h"
#include "materials/sphere_map.h"
#include "sampler/io/round_trip.h"
#include "sampler/targets/target_family.h"
#include "sampler/targets/target_spec.h"

namespace nuld {
namespace {

constexpr double kDegrees = 180 / std::numbers::pi;
constexpr int kSubSamples = 4;  // per cell side
constexpr int kMaxCells = 8192;

// One parameter key of the spec and where it lives in DisneyParams.
struct ParamKey {
  const char *name;
  double DisneyParams::*field;
};
constexpr std::array<ParamKey, 10> kParamKeys{{
    {"metallic", &DisneyParams::metallic},
    {"subsurface", &DisneyParams::subsurface},
    {"specular", &DisneyParams::specular},
    {"roughness", &DisneyParams::roughness},
    {"speculartint", &DisneyParams::specularTint},
    {"anisotropic", &DisneyParams::anisotropic},
    {"sheen", &DisneyParams::sheen},
    {"sheentint", &DisneyParams::sheenTint},
    {"clearcoat", &DisneyParams::clearcoat},
    {"clearcoatgloss", &DisneyParams::clearcoatGloss},
}};
constexpr const char *kKnownKeys =
    "basecolor, metallic, subsurface, specular, roughness, speculartint, anisotropic, sheen, "
    "sheentint, clearcoat, clearcoatgloss, theta, phi, res, rows, mix";

class ArgsParser {
 public:
  explicit ArgsParser(const std::string &args)
      : spec_(args.empty() ? "disney" : "disney:" + args) {}

  [[noreturn]] void fail(const std::string &what) const {
    throw std::invalid_argument("target '" + spec_ + "': " + what);
  }

  // One finite number; the sampler's list parser words the error.
  double number(const std::string &key, const std::string &text) const {
    if (text.empty()) fail("key '" + key + "' has no value (expected " + key + "=NUMBER)");
    return parseNumberList(spec_, text, 1, 1, "one number for key '" + key + "'")[0];
  }
  double inRange(const std::string &key, const std::string &text, double lo, double hi, bool hiOpen,
                 const std::string &expected) const {
    const double v = number(key, text);
    if (!(v >= lo && (hiOpen ? v < hi : v <= hi)))
      fail(key + " = " + text + " is out of range (expected " + expected + ")");
    return v;
  }
  int cells(const std::string &key, const std::string &text, int lo) const {
    const std::string expected =
        "an integer in [" + std::to_string(lo) + ", " + std::to_string(kMaxCells) + "]";
    const double v = inRange(key, text, lo, kMaxCells, false, expected);
    if (v != std::floor(v))
      fail(key + " = " + text + " is not an integer (expected " + expected + ")");
    return int(v);
  }
  Rgb color(const std::string &key, const std::string &text) const {
    std::vector<double> c;
    std::size_t pos = 0;
    while (pos <= text.size()) {
      const std::size_t slash = std::min(text.find('/', pos), text.size());
      c.push_back(inRange(key, text.substr(pos, slash - pos), 0, 1, false,
                          "a grey value or r/g/b, each in [0, 1]"));
      pos = slash + 1;
    }
    if (c.size() == 1) return Rgb::grey(c[0]);
    if (c.size() != 3) fail(key + " = " + text + " (expected a grey value or r/g/b)");
    return {c[0], c[1], c[2]};
  }

 private:
  std::string spec_;
};

}  // namespace

DisneyParams supplementDisneyParams() {
  DisneyParams p;
  p.baseColor = Rgb::grey(1);
  p.roughness = 0.58;
  p.metallic = 0.2;
  p.subsurface = 0.5;
  p.anisotropic = 0.15;
  // "Other parameters are all zero", literally: specular and clearcoat gloss too.
  p.specular = 0;
  p.specularTint = p.sheen = p.sheenTint = p.clearcoat = p.clearcoatGloss = 0;
  return p;
}

Vec3 supplementWo() { return {std::numbers::sqrt2 / 2, 0, std::numbers::sqrt2 / 2}; }

Vec3 DisneyTargetSpec::wo() const {
  const double theta = thetaDegrees / kDegrees, phi = phiDegrees / kDegrees;
  return sphericalDirection(std::sin(theta), std::cos(theta), phi);
}

DisneyTargetSpec parseDisneyTargetArgs(const std::string &args) {
  const ArgsParser parser(args);
  DisneyTargetSpec out;
  bool rowsGiven = false;
  std::vector<std::string> seen;
  std::size_t pos = 0;
  while (!args.empty() && pos <= args.size()) {
    const std::size_t comma = std::min(args.find(',', pos), args.size());
    const std::string item = args.substr(pos, comma - pos);
    pos = comma + 1;
    const std::size_t eq = item.find('=');
    if (eq == std::string::npos)
      parser.fail("'" + item + "' is not key=value (keys: " + kKnownKeys + ")");
    const std::string key = item.substr(0, eq), value = item.substr(eq + 1);
    if (std::find(seen.begin(), seen.end(), key) != seen.end())
      parser.fail("key '" + key + "' is given twice");
    seen.push_back(key);

    if (key == "basecolor") {
      out.params.baseColor = parser.color(key, value);
    } else if (key == "theta") {
      out.thetaDegrees = parser.inRange(key, value, 0, 90, true, "degrees in [0, 90)");
    } else if (key == "phi") {
      out.phiDegrees = parser.number(key, value);
    } else if (key == "res") {
      out.phiCells = parser.cells(key, value, 2);
    } else if (key == "mix") {
      out.samplingMix = parser.inRange(key, value, 0, 1, false, "a number in [0, 1]");
    } else if (key == "rows") {
      out.thetaRows = parser.cells(key, value, 1);
      rowsGiven = true;
    } else {
      const auto it = std::find_if(kParamKeys.begin(), kParamKeys.end(),
                                   [&](const ParamKey &k) { return key == k.name; });
      if (it == kParamKeys.end())
        parser.fail("unknown key '" + key + "' (expected one of: " + kKnownKeys + ")");
      out.params.*(it->field) = parser.inRange(key, value, 0, 1, false, "a number in [0, 1]");
    }
  }
  if (!rowsGiven) out.thetaRows = std::max(1, out.phiCells / 2);
  return out;
}

std::string toSpec(const DisneyTargetSpec &s) {
  const DisneyTargetSpec d;
  std::string args;
  auto add = [&](const std::string &key, const std::string &value) {
    args += (args.empty() ? "" : ",") + key + "=" + value;
  };
  const Rgb c = s.params.baseColor;
  if (!(c == d.params.baseColor))
    add("basecolor", c.r == c.g && c.g == c.b ? formatRoundTrip(c.r)
                                              : formatRoundTrip(c.r) + "/" + formatRoundTrip(c.g) +
                                                    "/" + formatRoundTrip(c.b));
  for (const ParamKey &k : kParamKeys)
    if (s.params.*(k.field) != d.params.*(k.field))
      add(k.name, formatRoundTrip(s.params.*(k.field)));
  if (s.thetaDegrees != d.thetaDegrees) add("theta", formatRoundTrip(s.thetaDegrees));
  if (s.phiDegrees != d.phiDegrees) add("phi", formatRoundTrip(s.phiDegrees));
  if (s.phiCells != d.phiCells) add("res", std::to_string(s.phiCells));
  if (s.thetaRows != std::max(1, s.phiCells / 2)) add("rows", std::to_string(s.thetaRows));
  if (s.samplingMix != d.samplingMix) add("mix", formatRoundTrip(s.samplingMix));
  return args.empty() ? "disney" : "disney:" + args;
}

namespace {

// f(wo, .) cos tabulated on the layout described in the header; `name` is
// the spec the target reports.
std::unique_ptr<GridTarget> tabulate(const DisneyParams &params, Vec3 wo, int phiCells,
                                     int thetaRows, double samplingMix, const std::string &name) {
  if (!(phiCells >= 1 && thetaRows >= 1 && phiCells <= kMaxCells && thetaRows <= kMaxCells))
    throw std::invalid_argument("target '" + name + "': expected 1 to " +
                                std::to_string(kMaxCells) + " cells per axis, got " +
                                std::to_string(phiCells) + " x " + std::to_string(thetaRows));
  if (!isFinite(wo) || !(wo.z > 0))
    throw std::invalid_argument("target '" + name + "': wo must point above the surface");
  wo = normalize(wo);
  const DisneyBrdf brdf(params);

  std::vector<double> yEdges(thetaRows + 2);
  for (int j = 0; j <= thetaRows; ++j) yEdges[j] = 0.5 * j / thetaRows;
  yEdges[thetaRows + 1] = 1.0;
  std::vector<double> xEdges = GridTarget::uniformEdges(phiCells);

  // The last row (the lower hemisphere) stays zero. f cos and the sampling
  // pdf are tabulated apart, then each normalized to mass one and mixed.
  const std::size_t cells = std::size_t(phiCells) * (thetaRows + 1);
  std::vector<double> density(cells, 0.0), sampling(samplingMix > 0 ? cells : 0, 0.0);
  tbb::parallel_for(0, thetaRows, [&](int j) {
    for (int i = 0; i < phiCells; ++i) {
      double sum = 0, pdfSum = 0;
      for (int sj = 0; sj < kSubSamples; ++sj)
        for (int si = 0; si < kSubSamples; ++si) {
          const Point2 uv{xEdges[i] + (si + 0.5) / kSubSamples * (xEdges[i + 1] - xEdges[i]),
                          yEdges[j] + (sj + 0.5) / kSubSamples * (yEdges[j + 1] - yEdges[j])};
          const Vec3 wi = sphereDirection(uv);
          if (samplingMix < 1) sum += brdf.eval(wo, wi).luminance() * std::max(0.0, wi.z);
          if (samplingMix > 0 && wi.z > 0) pdfSum += brdf.pdf(wo, wi);
        }
      density[std::size_t(j) * phiCells + i] = sum / (kSubSamples * kSubSamples);
      if (samplingMix > 0) sampling[std::size_t(j) * phiCells + i] = pdfSum;
    }
  });
  if (samplingMix > 0) {
    // Sums in a fixed order: tables stay bit-identical across thread counts.
    double productTotal = 0, samplingTotal = 0;
    for (std::size_t c = 0; c < cells; ++c)
      productTotal += density[c], samplingTotal += sampling[c];
    for (std::size_t c = 0; c < cells; ++c)
      density[c] = (productTotal > 0 ? (1 - samplingMix) * density[c] / productTotal : 0) +
                   samplingMix * sampling[c] / samplingTotal;
  }
  return std::make_unique<GridTarget>(std::move(xEdges), std::move(yEdges), density, name,
                                      Domain::Hemisphere, "target '" + name + "'");
}

}  // namespace

std::unique_ptr<GridTarget> makeDisneyTarget(const DisneyParams &params, Vec3 wo, int phiCells,
                                             int thetaRows) {
  DisneyTargetSpec spec;
  spec.params = params;
  spec.thetaDegrees = std::atan2(std::hypot(wo.x, wo.y), wo.z) * kDegrees;
  spec.phiDegrees = std::atan2(wo.y, wo.x) * kDegrees;
  spec.phiCells = phiCells;
  spec.thetaRows = thetaRows;
  return tabulate(params, wo, phiCells, thetaRows, spec.samplingMix, toSpec(spec));
}

std::unique_ptr<GridTarget> makeDisneyTarget(const DisneyTargetSpec &spec) {
  return tabulate(spec.params, spec.wo(), spec.phiCells, spec.thetaRows, spec.samplingMix,
                  toSpec(spec));
}

DisneyView disneyFamilyView(std::array<double, 2> gamma) {
  return {kDisneyFamilyMaxThetaDegrees * gamma[0], 360 * gamma[1]};
}

std::optional<std::array<double, 2>> invertDisneyFamilyView(DisneyView view) {
  if (!(view.thetaDegrees >= 0 && view.thetaDegrees <= kDisneyFamilyMaxThetaDegrees))
    return std::nullopt;
  const double phi = view.phiDegrees / 360;
  return std::array<double, 2>{view.thetaDegrees / kDisneyFamilyMaxThetaDegrees,
                               phi - std::floor(phi)};
}

namespace {

// gamma = the view of wo (disneyFamilyView); the other parameters come from
// the family's ARGS (a `disney:` spec without theta and phi).
class DisneyFamily final : public TargetFamily {
 public:
  explicit DisneyFamily(const std::string &args) : base_(parseDisneyTargetArgs(args)) {
    if (args.find("theta") != std::string::npos || args.find("phi") != std::string::npos)
      throw std::invalid_argument("target family 'family:disney:" + args +
                                  "': theta and phi are the family's gamma, not parameters");
  }
  std::string spec() const override {
    const std::string s = toSpec(base_);  // "disney" or "disney:ARGS"
    return "family:" + s;
  }
  std::size_t gammaDimension() const override { return 2; }
  Domain domain() const override { return Domain::Hemisphere; }
  std::shared_ptr<const Target> target(std::span<const double> gamma) const override {
    checkGamma(*this, gamma);
    DisneyTargetSpec s = base_;
    const DisneyView view = disneyFamilyView({gamma[0], gamma[1]});
    s.thetaDegrees = view.thetaDegrees;
    s.phiDegrees = view.phiDegrees;
    return makeDisneyTarget(s);
  }

 private:
  DisneyTargetSpec base_;
};

}  // namespace

std::optional<std::array<double, 2>> disneyFamilyGamma(const std::string &familySpec,
                                                       const std::string &targetSpec) {
  // The part after `disney` (with its colon) of a spec that starts with PREFIX.
  const auto argsAfter = [](const std::string &spec,
                            const std::string &prefix) -> std::optional<std::string> {
    if (spec == prefix) return std::string();
    if (spec.rfind(prefix + ":", 0) != 0) return std::nullopt;
    return spec.substr(prefix.size() + 1);
  };
  const auto familyArgs = argsAfter(familySpec, "family:disney");
  const auto targetArgs = argsAfter(targetSpec, "disney");
  if (!familyArgs || !targetArgs) return std::nullopt;
  try {
    const DisneyTargetSpec base = parseDisneyTargetArgs(*familyArgs);
    const DisneyTargetSpec t = parseDisneyTargetArgs(*targetArgs);
    if (!(t.params == base.params) || t.phiCells != base.phiCells ||
        t.thetaRows != base.thetaRows || t.samplingMix != base.samplingMix)
      return std::nullopt;
    return invertDisneyFamilyView({t.thetaDegrees, t.phiDegrees});
  } catch (const std::invalid_argument &) {
    return std::nullopt;  // not a spec this family could have made
  }
}

void registerMaterialTargets() {
  registerTargetKind(
      "disney",
      [](const std::string &args) -> std::unique_ptr<Target> {
        return makeDisneyTarget(parseDisneyTargetArgs(args));
      },
      "disney[:KEY=VALUE,...]",
      std::string("a Disney BRDF lobe f cos on the hemisphere at the view (theta, phi) in "
                  "degrees, tabulated; keys: ") +
          kKnownKeys +
          " (mix: the share of the material's own sampling pdf); plain `disney` "
          "is the supplement's instance at theta 45");
  registerTargetFamily(
      "disney",
      [](const std::string &args) -> std::unique_ptr<TargetFamily> {
        return std::make_unique<DisneyFamily>(args);
      },
      "family:disney[:KEY=VALUE,...]",
      "gamma = (theta / 89 degrees, phi / 360 degrees) of the view; the other keys as disney");
}

}  // namespace nuld
