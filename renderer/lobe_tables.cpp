#include "renderer/lobe_tables.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <numbers>
#include <stdexcept>

#include "materials/disney_target.h"
#include "materials/sampling.h"
#include "materials/sphere_map.h"
#include "materials/turns.h"
#include "renderer/padding.h"
#include "renderer/smooth_lights.h"
#include "sampler/sequences/rng.h"
#include "sampler/sequences/sequence.h"

namespace nuld {

namespace {

constexpr double kDegrees = 180 / std::numbers::pi;

double binCentre(int bin, double range, int bins) { return (bin + 0.5) * range / bins; }

// The route measurement (renderer/README.md, "Lobe routes"): the smooth
// lights in the shading frame (smooth_lights.h), against which each route
// estimates the reflected light with kMeasurePoints Owen-Sobol points,
// kMeasureRepeats times, at views spread over the bin.
constexpr int kLights = kSmoothLights;
constexpr std::size_t kMeasurePoints = 16, kMeasureRepeats = 32;

// The light strategy that stands in for the scene's under MIS: uniform
// directions over the hemisphere (a smooth light needs no better), whose
// weights leave to BSDF sampling what is sharper than the light's density.
constexpr double kProxyLightPdf = 0.5 * kInvPi;
Vec3 proxyLightDirection(Point2 u) {
  const double z = u.x, r = std::sqrt(std::max(0.0, 1 - z * z));
  const SinCos phi = sinCosTurns(u.y);
  return {r * phi.cos, r * phi.sin, z};
}

// The relative variances (variance / mean^2, summed over the lights) of the
// classic route (the material's sample()) and of `lobe`'s route, both fed
// the same Owen-Sobol points as the sobol-tabulated backend feeds them;
// `underMis`: each estimate combined with as many proxy light samples by
// the power heuristic, with the material's pdf on the BSDF side as the
// path integrator weighs them (BsdfSample::misPdf).
struct RouteVariances {
  double classic = 0, table = 0;
};
RouteVariances measureAt(const DisneyBrdf &m, Vec3 wo, const LobeFrame &lobe, bool underMis,
                         std::uint64_t seed) {
  std::array<std::array<double, kMeasureRepeats>, kLights> classic{}, table{};
  std::array<Point2, kMeasurePoints> u, ul, choice;
  // A proxy light sample: its direction, f cos / (pdf N) there, and the
  // material's pdf (each route's MIS weight starts from it).
  struct LightSample {
    Vec3 wi;
    double value, materialPdf;
  };
  std::array<LightSample, kMeasurePoints> light;
  for (std::size_t r = 0; r < kMeasureRepeats; ++r) {
    const std::uint64_t key = mix64(seed + r);
    generateSet({SequenceKind::Sobol, Scramble::Owen, key}, 0, u, 0);
    shufflePoints(u, key);
    // The lobe choice's numbers, a 1D set of their own as in a render.
    generateSet({SequenceKind::Sobol, Scramble::Owen, key ^ 0x6c0be}, 0, choice, 0);
    shufflePoints(choice, key ^ 0x6c0be);
    if (underMis) {
      generateSet({SequenceKind::Sobol, Scramble::Owen, mix64(key)}, 0, ul, 0);
      for (std::size_t i = 0; i < kMeasurePoints; ++i) {
        const Vec3 wi = proxyLightDirection(ul[i]);
        const BsdfValue v = m.evalWithPdf(wo, wi);
        light[i] = {wi, v.f.luminance() * wi.z / kProxyLightPdf / double(kMeasurePoints), v.pdf};
      }
    }
    const auto add = [&](const std::optional<BsdfSample> &s, auto &sums) {
      if (!s) return;
      const BsdfSample &b = *s;
      const double w = (underMis ? powerHeuristic(b.misPdf, kProxyLightPdf) : 1.0) *
                       b.f.luminance() * b.wi.z / b.pdf / double(kMeasurePoints);
      for (int k = 0; k < kLights; ++k) sums[k][r] += w * smoothLight(k, b.wi);
    };
    for (std::size_t i = 0; i < kMeasurePoints; ++i) {
      add(sampleRoute(m, wo, LobeFrame{}, {u[i]}, choice[i].x), classic);
      add(sampleRoute(m, wo, lobe, {u[i]}, choice[i].x), table);
    }
    // The proxy light's samples, weighted as the path integrator weighs
    // them: against the material's pdf whichever route draws the BSDF
    // sample (BsdfSample::misPdf), so they add the same to both routes' estimates.
    if (underMis)
      for (const LightSample &l : light) {
        const double w = powerHeuristic(kProxyLightPdf, l.materialPdf) * l.value;
        for (int k = 0; k < kLights; ++k) {
          const double estimate = w * smoothLight(k, l.wi);
          classic[k][r] += estimate;
          table[k][r] += estimate;
        }
      }
  }
  return {summedRelativeVariance(classic), summedRelativeVariance(table)};
}

// The table's sample at the drawn point x (with its cell's density per unit
// area of the square): f and the material's pdf there, and the route's
// mixture density.
std::optional<BsdfSample> tableSample(const Bsdf &bsdf, Vec3 wo, const LobeFrame &lobe,
                                      const GridTarget::Draw &x) {
  BsdfSample s;
  s.wi = lobe.direction(x.x);
  if (!(s.wi.z > 0)) return std::nullopt;
  const BsdfValue v = bsdf.evalWithPdf(wo, s.wi);
  s.f = v.f;
  s.misPdf = v.pdf;
  s.pdf = lobe.mixture(x.density * kInvFourPi, v.pdf);
  return s;
}

// The route's sample before its one validity check (sampleRoute).
std::optional<BsdfSample> drawRoute(const Bsdf &bsdf, Vec3 wo, const LobeFrame &lobe, RoutePoint p,
                                    double uc) {
  if (!lobe.table) return bsdf.sample(wo, uc, p.value);
  const double d = lobe.defensive;
  // A point that follows the table, in a cell the table can draw from, is
  // the table's sample as it is: pulling it back to primary space and
  // mapping it forward again would return the same point.
  if (p.followsTable && d == 0) {
    const GridTarget::Cell c = lobe.table->locate(p.value);
    const double density = lobe.table->cellDensity(c.i, c.j);
    if (density > 0) return tableSample(bsdf, wo, lobe, {p.value, c, density});
  }
  const Point2 u = p.followsTable ? lobe.table->primaryOf(p.value) : p.value;
  // The defensive split, in the table's primary space, where a set that
  // follows the table is uniform: a strip of width d of the conditional
  // coordinate goes to the material's sampler, the rest, stretched back to
  // the whole square, to the table. The points of a set keep their
  // stratification on both sides, which a random choice per sample would
  // not.
  if (u.x < d) {
    auto drawn = bsdf.sample(wo, uc, {u.x / d, u.y});
    if (drawn) drawn->pdf = lobe.pdf(drawn->wi, drawn->misPdf);
    return drawn;
  }
  return tableSample(bsdf, wo, lobe, lobe.table->draw({(u.x - d) / (1 - d), u.y}));
}

}  // namespace

std::optional<BsdfSample> sampleRoute(const Bsdf &bsdf, Vec3 wo, const LobeFrame &lobe,
                                      RoutePoint p, double uc) {
  auto s = drawRoute(bsdf, wo, lobe, p, uc);
  if (!s || !(s->pdf > 0) || !std::isfinite(s->pdf) || !s->f.isFinite()) return std::nullopt;
  return s;
}

Vec3 LobeFrame::direction(Point2 x) const {
  const Vec3 d = sphereDirection(x);
  return {flipX * (cosPhi * d.x - sinPhi * d.y), flipY * (sinPhi * d.x + cosPhi * d.y), d.z};
}

double LobeFrame::tablePdf(Vec3 wi) const {
  if (!(wi.z > 0)) return 0;
  const double x = flipX * wi.x, y = flipY * wi.y;
  const Vec3 local{cosPhi * x + sinPhi * y, -sinPhi * x + cosPhi * y, wi.z};
  return table->pdf(spherePoint(normalize(local))) * kInvFourPi;
}

LobeTablesConfig::LobeTablesConfig(const LobeTableSettings &s, bool mis)
    : settings(s), samplingMix(s.samplingMix.value_or(0)), underMis(mis) {
  // Its range is the tables' to check, for derived mixes too (LobeTables).
  if (!s.samplingMix) throw std::invalid_argument("lobe tables: the sampling mix must be given");
}

LobeTables::LobeTables(const std::vector<std::shared_ptr<const Bsdf>> &materials,
                       const LobeTablesConfig &config)
    : config_(config) {
  const LobeTableSettings &settings = config.settings;
  if (settings.thetaBins < 1 || settings.phiBins < 1 || settings.phiCells < 2)
    throw std::invalid_argument(
        "lobe tables: theta and phi bins must be >= 1 and the resolution >= 2");
  if (!(config.samplingMix >= 0 && config.samplingMix <= 1))
    throw std::invalid_argument("lobe tables: the sampling mix must be in [0, 1]");
  if (!(settings.defensive >= 0 && settings.defensive <= 1))
    throw std::invalid_argument("lobe tables: the defensive share must be in [0, 1]");
  if (settings.bounces < 0)
    throw std::invalid_argument("lobe tables: the bounces must be >= 0 (0: every bounce)");
  for (int t = 1; t < settings.thetaBins; ++t)
    cosThetaEdges_.push_back(std::cos(t * 90.0 / settings.thetaBins / kDegrees));
  for (int p = 1; p < settings.phiBins; ++p)
    tanPhiEdges_.push_back(std::tan(p * 90.0 / settings.phiBins / kDegrees));
  for (const auto &m : materials) {
    const auto *disney = dynamic_cast<const DisneyBrdf *>(m.get());
    // A table covers the hemisphere of reflection; a transmitting material
    // keeps its own sampler (docs/architecture.md, "Materials").
    if (!disney || disney->transmits() ||
        std::any_of(entries_.begin(), entries_.end(),
                    [&](const Entry &e) { return e.material == disney; }))
      continue;
    Entry e{disney, disney->params().anisotropic > 0, {}, routes_.size()};
    const int phiBins = e.anisotropic ? settings.phiBins : 1;
    for (int t = 0; t < settings.thetaBins; ++t)
      for (int p = 0; p < phiBins; ++p) {
        DisneyTargetSpec spec = lobeTableLayout(config);
        spec.params = disney->params();
        spec.thetaDegrees = binCentre(t, 90, settings.thetaBins);
        spec.phiDegrees = e.anisotropic ? binCentre(p, 90, phiBins) : 0;
        spec.lobeChoice = disney->lobeChoice();
        e.tables.push_back(makeDisneyTarget(spec));
      }
    measureRoutes(e, entries_.size());
    entries_.push_back(std::move(e));
  }
}

// Decides each bin's route: the route whose estimates, over views spread
// across the bin, vary less, of the material's own sampler and the table
// (both fed the same kind of points). A bin whose views all lie below the
// table's resolution (a narrow lobe, whose peak moves across the bin with
// the view) keeps the material's sampler.
void LobeTables::measureRoutes(const Entry &e, std::size_t material) {
  const int phiBins = e.anisotropic ? config_.settings.phiBins : 1;
  const LobeRouting routing = config_.settings.routing;
  for (std::size_t b = 0; b < e.tables.size(); ++b) {
    const int t = int(b) / phiBins, p = int(b) % phiBins;
    LobeBinRoute route{material, binCentre(t, 90, config_.settings.thetaBins),
                       e.anisotropic ? binCentre(p, 90, phiBins) : 0};
    if (routing == LobeRouting::Table) {  // nothing to decide
      route.table = true;
      routes_.push_back(route);
      continue;
    }
    int view = 0;
    for (const double ft : {1.0 / 6, 0.5, 5.0 / 6})
      for (const double fp : e.anisotropic ? std::vector{0.25, 0.75} : std::vector{0.4}) {
        const double theta = (t + ft) * 90 / config_.settings.thetaBins / kDegrees;
        // Isotropic: an azimuth away from the table's, so the rotation is
        // part of what is measured. Anisotropic: views in every quadrant,
        // so the folds are.
        const double phi = e.anisotropic ? (p + fp) * 90 / phiBins / kDegrees : fp;
        const double flipX = e.anisotropic && (view & 1) ? -1 : 1;
        const double flipY = e.anisotropic && (view & 2) ? -1 : 1;
        ++view;
        const Vec3 wo{flipX * std::sin(theta) * std::cos(phi),
                      flipY * std::sin(theta) * std::sin(phi), std::cos(theta)};
        const RouteVariances v =
            measureAt(*e.material, wo, frameIn(e, wo, binIndex(e, wo)), config_.underMis,
                      hashCombine(material * 1000 + b, std::uint64_t(ft * 6)));
        route.classicVariance += v.classic;
        route.tableVariance += v.table;
      }
    route.table = route.tableVariance <= route.classicVariance;
    routes_.push_back(route);
  }
}

std::size_t LobeTables::binIndex(const Entry &e, Vec3 wo) const {
  // The bins by comparisons with their edges' cosines and tangents (wo is a
  // unit vector): no atan2 per shading point.
  int t = 0;
  while (t + 1 < config_.settings.thetaBins && wo.z <= cosThetaEdges_[t]) ++t;
  if (!e.anisotropic) return std::size_t(t);
  const double x = std::abs(wo.x), y = std::abs(wo.y);
  int p = 0;
  while (p + 1 < config_.settings.phiBins && y > x * tanPhiEdges_[p]) ++p;
  return std::size_t(t) * config_.settings.phiBins + p;
}

LobeFrame LobeTables::frameIn(const Entry &e, Vec3 wo, std::size_t index) const {
  LobeFrame f;
  f.defensive = config_.settings.defensive;
  if (!e.anisotropic) {
    const double r = std::sqrt(wo.x * wo.x + wo.y * wo.y);
    if (r > 0) f.cosPhi = wo.x / r, f.sinPhi = wo.y / r;
  } else {
    f.flipX = wo.x < 0 ? -1 : 1;
    f.flipY = wo.y < 0 ? -1 : 1;
  }
  f.table = e.tables[index].get();
  return f;
}

std::optional<LobeFrame> LobeTables::frame(const Bsdf *material, Vec3 wo) const {
  const auto it = std::find_if(entries_.begin(), entries_.end(),
                               [&](const Entry &e) { return e.material == material; });
  if (it == entries_.end() || !(wo.z > 0)) return std::nullopt;
  const std::size_t index = binIndex(*it, wo);
  // A bin that keeps the material's sampler needs no frame.
  if (!routes_[it->firstRoute + index].table) return std::nullopt;
  return frameIn(*it, wo, index);
}

std::vector<const Target *> LobeTables::targets() const {
  std::vector<const Target *> out;
  for (const Entry &e : entries_)
    for (std::size_t b = 0; b < e.tables.size(); ++b) {
      const LobeBinRoute &route = routes_[e.firstRoute + b];
      if (route.table) out.push_back(e.tables[b].get());
    }
  return out;
}

DisneyTargetSpec lobeTableLayout(const LobeTablesConfig &config) {
  DisneyTargetSpec spec;
  spec.phiCells = config.settings.phiCells;
  spec.thetaRows = std::max(1, config.settings.phiCells / 2);
  spec.samplingMix = config.samplingMix;
  return spec;
}

std::shared_ptr<const LobeTables> LobeTableCache::get(
    const std::vector<std::shared_ptr<const Bsdf>> &materials, const LobeTablesConfig &config) {
  std::vector<const Bsdf *> key;
  for (const auto &m : materials) key.push_back(m.get());
  const std::lock_guard lock(mutex_);
  for (const Item &item : items_)
    if (item.materials == key && item.config == config) return item.tables;
  auto tables = std::make_shared<const LobeTables>(materials, config);
  items_.push_back({std::move(key), config, tables});
  return tables;
}

}  // namespace nuld
