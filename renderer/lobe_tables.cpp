#include "renderer/lobe_tables.h"

#include <algorithm>
#include <cmath>
#include <numbers>
#include <stdexcept>

#include "materials/disney_target.h"
#include "materials/sphere_map.h"

namespace nuld {

namespace {

constexpr double kDegrees = 180 / std::numbers::pi;

int binOf(double value, double range, int bins) {
  return std::clamp(int(value / range * bins), 0, bins - 1);
}
double binCentre(int bin, double range, int bins) { return (bin + 0.5) * range / bins; }

}  // namespace

Vec3 LobeFrame::direction(Point2 x) const {
  const Vec3 d = sphereDirection(x);
  return {flipX * (cosPhi * d.x - sinPhi * d.y), flipY * (sinPhi * d.x + cosPhi * d.y), d.z};
}

double LobeFrame::pdf(Vec3 wi) const {
  if (!(wi.z > 0)) return 0;
  const double x = flipX * wi.x, y = flipY * wi.y;
  const Vec3 local{cosPhi * x + sinPhi * y, -sinPhi * x + cosPhi * y, wi.z};
  return table->pdf(spherePoint(normalize(local))) * kInvFourPi;
}

LobeTables::LobeTables(const std::vector<std::shared_ptr<const Bsdf>> &materials,
                       const LobeTableSettings &settings)
    : settings_(settings) {
  if (settings.thetaBins < 1 || settings.phiBins < 1 || settings.phiCells < 2)
    throw std::invalid_argument(
        "lobe tables: theta and phi bins must be >= 1 and the resolution >= 2");
  if (!settings.samplingMix || !(*settings.samplingMix >= 0 && *settings.samplingMix <= 1))
    throw std::invalid_argument("lobe tables: the sampling mix must be given, in [0, 1]");
  for (const auto &m : materials) {
    const auto *disney = dynamic_cast<const DisneyBrdf *>(m.get());
    if (!disney || std::any_of(entries_.begin(), entries_.end(),
                               [&](const Entry &e) { return e.material == disney; }))
      continue;
    Entry e{disney, disney->params().anisotropic > 0, {}};
    const int phiBins = e.anisotropic ? settings.phiBins : 1;
    for (int t = 0; t < settings.thetaBins; ++t)
      for (int p = 0; p < phiBins; ++p) {
        DisneyTargetSpec spec;
        spec.params = disney->params();
        spec.thetaDegrees = binCentre(t, 90, settings.thetaBins);
        spec.phiDegrees = e.anisotropic ? binCentre(p, 90, phiBins) : 0;
        spec.phiCells = settings.phiCells;
        spec.thetaRows = std::max(1, settings.phiCells / 2);
        spec.samplingMix = *settings.samplingMix;
        e.tables.push_back(makeDisneyTarget(spec));
      }
    entries_.push_back(std::move(e));
  }
}

std::optional<LobeFrame> LobeTables::frame(const Bsdf *material, Vec3 wo) const {
  const auto it = std::find_if(entries_.begin(), entries_.end(),
                               [&](const Entry &e) { return e.material == material; });
  if (it == entries_.end() || !(wo.z > 0)) return std::nullopt;
  const double r = std::hypot(wo.x, wo.y);
  const int t = binOf(std::atan2(r, wo.z) * kDegrees, 90, settings_.thetaBins);
  LobeFrame f;
  if (!it->anisotropic) {
    f.table = it->tables[t].get();
    if (r > 0) f.cosPhi = wo.x / r, f.sinPhi = wo.y / r;
    return f;
  }
  f.flipX = wo.x < 0 ? -1 : 1;
  f.flipY = wo.y < 0 ? -1 : 1;
  const int p = binOf(std::atan2(std::abs(wo.y), std::abs(wo.x)) * kDegrees, 90, settings_.phiBins);
  f.table = it->tables[std::size_t(t) * settings_.phiBins + p].get();
  return f;
}

std::vector<const Target *> LobeTables::targets() const {
  std::vector<const Target *> out;
  for (const Entry &e : entries_)
    for (const auto &t : e.tables) out.push_back(t.get());
  return out;
}

}  // namespace nuld
