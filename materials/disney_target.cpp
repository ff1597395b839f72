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
    "sheentint, clearcoat, clearcoatgloss, theta, phi, res, rows, mix, lobes";

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
    } else if (key == "lobes") {
      const auto choice = kLobeChoiceNames.find(value);
      if (!choice)
        parser.fail("lobes = " + value + " (expected " + kLobeChoiceNames.expected() + ")");
      out.lobeChoice = *choice;
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
  if (!rowsGiven) out.thetaRows = out.defaultRows();
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
  if (s.thetaRows != s.defaultRows()) add("rows", std::to_string(s.thetaRows));
  if (s.samplingMix != d.samplingMix) add("mix", formatRoundTrip(s.samplingMix));
  if (s.lobeChoice != d.lobeChoice) add("lobes", toString(s.lobeChoice));
  return args.empty() ? "disney" : "disney:" + args;
}

namespace {

void checkTableArgs(int cols, int rows, Vec3 wo, const std::string &name) {
  if (!(cols >= 1 && rows >= 1 && cols <= kMaxCells && rows <= kMaxCells))
    throw std::invalid_argument("target '" + name + "': expected 1 to " +
                                std::to_string(kMaxCells) + " cells per axis, got " +
                                std::to_string(cols) + " x " + std::to_string(rows));
  if (!isFinite(wo) || !(wo.z > 0))
    throw std::invalid_argument("target '" + name + "': wo must point above the surface");
}

// f(wo, .) cos tabulated on the layout described in the header; `name` is
// the spec the target reports.
std::unique_ptr<GridTarget> tabulate(const DisneyBrdf &brdf, Vec3 wo, int phiCells, int thetaRows,
                                     double samplingMix, const std::string &name) {
  checkTableArgs(phiCells, thetaRows, wo, name);
  wo = normalize(wo);

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
  return tabulate(DisneyBrdf(params, spec.lobeChoice), wo, phiCells, thetaRows, spec.samplingMix,
                  toSpec(spec));
}

std::unique_ptr<GridTarget> makeDisneyTarget(const DisneyTargetSpec &spec) {
  return tabulate(DisneyBrdf(spec.params, spec.lobeChoice), spec.wo(), spec.phiCells,
                  spec.thetaRows, spec.samplingMix, toSpec(spec));
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
  Domain domain() const override { return base_.domain(); }
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

namespace {

// The part after PREFIX (and its colon) of a spec that starts with PREFIX.
std::optional<std::string> argsAfter(const std::string &spec, const std::string &prefix) {
  if (spec == prefix) return std::string();
  if (spec.rfind(prefix + ":", 0) != 0) return std::nullopt;
  return spec.substr(prefix.size() + 1);
}

}  // namespace

std::optional<std::vector<double>> disneyFamilyGamma(const std::string &familySpec,
                                                     const std::string &targetSpec) {
  const auto targetArgs = argsAfter(targetSpec, "disney");
  if (!targetArgs) return std::nullopt;
  try {
    const DisneyTargetSpec t = parseDisneyTargetArgs(*targetArgs);
    const auto sameLayout = [&](const DisneyTargetSpec &base) {
      return t.phiCells == base.phiCells && t.thetaRows == base.thetaRows &&
             t.samplingMix == base.samplingMix;
    };
    if (const auto familyArgs = argsAfter(familySpec, "family:disney-material")) {
      const DisneyTargetSpec base = parseDisneyTargetArgs(*familyArgs);
      if (!sameLayout(base)) return std::nullopt;
      return invertDisneyMaterialGamma(t);
    }
    const auto familyArgs = argsAfter(familySpec, "family:disney");
    if (!familyArgs) return std::nullopt;
    const DisneyTargetSpec base = parseDisneyTargetArgs(*familyArgs);
    if (!(t.params == base.params) || !sameLayout(base)) return std::nullopt;
    const auto view = invertDisneyFamilyView({t.thetaDegrees, t.phiDegrees});
    if (!view) return std::nullopt;
    return std::vector<double>{(*view)[0], (*view)[1]};
  } catch (const std::invalid_argument &) {
    return std::nullopt;  // not a spec this family could have made
  }
}

// ---------------------------------------------------- family:disney-material

namespace {

// How gamma entry k maps to a parameter in [0, 1]: linear, or with a flat
// stretch at 0 (and at 1) of width `flat` that puts that much of the
// uniformly drawn gammas on the value (scenes leave a clear coat, sheen,
// subsurface, anisotropy and the tints at 0 and make materials metallic 0 or
// 1 far more often than anything between).
struct GammaAxis {
  double DisneyParams::*field = nullptr;  // null: a base colour channel
  int channel = 0;
  double flatLow = 0, flatHigh = 0;

  double value(double g) const {
    return std::clamp((g - flatLow) / (1 - flatLow - flatHigh), 0.0, 1.0);
  }
  // The gamma of a value: the middle of a flat stretch for its end values.
  double gamma(double v) const {
    if (v <= 0 && flatLow > 0) return flatLow / 2;
    if (v >= 1 && flatHigh > 0) return 1 - flatHigh / 2;
    return flatLow + v * (1 - flatLow - flatHigh);
  }
};

// gamma = (theta / 89 degrees, phi / 360 degrees, then these).
const std::array<GammaAxis, 13> kMaterialAxes{{
    {nullptr, 0},
    {nullptr, 1},
    {nullptr, 2},
    {&DisneyParams::metallic, 0, 0.25, 0.25},
    {&DisneyParams::subsurface, 0, 0.5},
    {&DisneyParams::specular},
    {&DisneyParams::roughness},
    {&DisneyParams::specularTint, 0, 0.5},
    {&DisneyParams::anisotropic, 0, 0.5},
    {&DisneyParams::sheen, 0, 0.5},
    {&DisneyParams::sheenTint, 0, 0.5},
    {&DisneyParams::clearcoat, 0, 0.5},
    {&DisneyParams::clearcoatGloss},
}};

double &channel(Rgb &c, int k) { return k == 0 ? c.r : k == 1 ? c.g : c.b; }

// gamma = the view and every material parameter (kMaterialAxes); ARGS give
// the table's layout only (res, rows, mix, lobes).
class DisneyMaterialFamily final : public TargetFamily {
 public:
  explicit DisneyMaterialFamily(const std::string &args) : base_(parseDisneyTargetArgs(args)) {
    DisneyTargetSpec layout;
    layout.phiCells = base_.phiCells;
    layout.thetaRows = base_.thetaRows;
    layout.samplingMix = base_.samplingMix;
    layout.lobeChoice = base_.lobeChoice;
    if (toSpec(layout) != toSpec(base_))
      throw std::invalid_argument("target family 'family:disney-material:" + args +
                                  "': the view and the material are its gamma; its keys are the "
                                  "table's layout only (res, rows, mix, lobes)");
  }
  std::string spec() const override {
    const std::string s = toSpec(base_);  // "disney" or "disney:ARGS"
    return "family:disney-material" + s.substr(std::string("disney").size());
  }
  std::size_t gammaDimension() const override { return 2 + kMaterialAxes.size(); }
  Domain domain() const override { return base_.domain(); }
  std::shared_ptr<const Target> target(std::span<const double> gamma) const override {
    checkGamma(*this, gamma);
    return makeDisneyTarget(disneyMaterialSpec(base_, gamma));
  }

 private:
  DisneyTargetSpec base_;
};

}  // namespace

DisneyTargetSpec disneyMaterialSpec(const DisneyTargetSpec &layout, std::span<const double> gamma) {
  if (gamma.size() != kDisneyMaterialGammaDimension)
    throw std::invalid_argument("family:disney-material: gamma needs " +
                                std::to_string(kDisneyMaterialGammaDimension) + " entries");
  DisneyTargetSpec s = layout;
  const DisneyView view = disneyFamilyView({gamma[0], gamma[1]});
  s.thetaDegrees = view.thetaDegrees;
  s.phiDegrees = view.phiDegrees;
  for (std::size_t k = 0; k < kMaterialAxes.size(); ++k) {
    const GammaAxis &a = kMaterialAxes[k];
    const double v = a.value(gamma[2 + k]);
    if (a.field)
      s.params.*(a.field) = v;
    else
      channel(s.params.baseColor, a.channel) = v;
  }
  return s;
}

std::optional<std::vector<double>> invertDisneyMaterialGamma(const DisneyTargetSpec &spec) {
  const auto view = invertDisneyFamilyView({spec.thetaDegrees, spec.phiDegrees});
  if (!view) return std::nullopt;
  std::vector<double> g{(*view)[0], (*view)[1]};
  Rgb colour = spec.params.baseColor;
  for (const GammaAxis &a : kMaterialAxes)
    g.push_back(a.gamma(a.field ? spec.params.*(a.field) : channel(colour, a.channel)));
  return g;
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
          " (mix: the share of the material's own sampling pdf; lobes: the material's lobe "
          "choice); "
          "plain `disney` is the supplement's instance at theta 45");
  registerTargetFamily(
      "disney",
      [](const std::string &args) -> std::unique_ptr<TargetFamily> {
        return std::make_unique<DisneyFamily>(args);
      },
      "family:disney[:KEY=VALUE,...]",
      "gamma = (theta / 89 degrees, phi / 360 degrees) of the view; the other keys as disney");
  registerTargetFamily(
      "disney-material",
      [](const std::string &args) -> std::unique_ptr<TargetFamily> {
        return std::make_unique<DisneyMaterialFamily>(args);
      },
      "family:disney-material[:res=..,rows=..,mix=..,lobes=..]",
      "gamma = the view (as family:disney), then base colour r, g, b, metallic, subsurface, "
      "specular, roughness, speculartint, anisotropic, sheen, sheentint, clearcoat, "
      "clearcoatgloss; metallic is 0 or 1, and subsurface, the tints, anisotropic, sheen and "
      "clearcoat 0, over flat stretches of gamma (materials/disney_target.h)");
}

}  // namespace nuld
