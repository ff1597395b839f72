#include "tools/study/integrands.h"

#include <tbb/parallel_for.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <numbers>
#include <stdexcept>

#include "materials/disney_target.h"
#include "materials/sphere_map.h"
#include "sampler/sequences/rng.h"
#include "sampler/targets/basic_targets.h"
#include "sampler/targets/image_targets.h"

namespace nuld::study {
namespace {

constexpr double kPi = std::numbers::pi;
constexpr double kFourPi = 4 * kPi;
constexpr double kDegrees = 180 / kPi;

// Row j of a lat-long map spans cos theta from cos(pi j / H) down to
// cos(pi (j + 1) / H): the target's equal-area rows.
double rowTopZ(int j, int height) { return std::cos(kPi * j / height); }

// Sums a value per map row in parallel, then adds the rows in order, so the
// reference is the same on any number of threads.
template <typename RowSum>
double sumRows(int rows, const RowSum &rowSum) {
  std::vector<double> perRow(rows, 0.0);
  tbb::parallel_for(0, rows, [&](int j) { perRow[j] = rowSum(j); });
  double total = 0;
  for (double v : perRow) total += v;
  return total;
}

// The integral over phi in [phi0, phi1] (phi1 - phi0 <= 2 pi) of
// max(0, a + b cos(phi - phiN)), b >= 0, in closed form: the integrand is
// positive on |psi| < acos(-a / b) (mod 2 pi), psi = phi - phiN.
double clippedCosineIntegral(double a, double b, double phi0, double phi1, double phiN) {
  const auto exact = [&](double lo, double hi) {
    return a * (hi - lo) + b * (std::sin(hi) - std::sin(lo));
  };
  double s0 = phi0 - phiN;
  s0 -= 2 * kPi * std::floor((s0 + kPi) / (2 * kPi));  // [-pi, pi)
  const double s1 = s0 + (phi1 - phi0);
  if (a >= b) return exact(s0, s1);
  if (a <= -b) return 0;
  const double half = std::acos(std::clamp(-a / b, -1.0, 1.0));
  double sum = 0;
  for (int k = 0; k <= 1; ++k) {  // s1 < 3 pi: the windows about 0 and 2 pi
    const double lo = std::max(s0, 2 * kPi * k - half), hi = std::min(s1, 2 * kPi * k + half);
    if (hi > lo) sum += exact(lo, hi);
  }
  return sum;
}

// The quarter-disc*bilinear coefficients.
constexpr double kA = 0.25, kB = 1, kC = 0.5, kD = 2;
constexpr double kStepX0 = 0.6;

}  // namespace

void gaussLegendre(int q, std::vector<double> &nodes, std::vector<double> &weights) {
  // P_q(x) and its derivative by the three-term recurrence.
  const auto legendre = [q](double x, double &derivative) {
    double p0 = 1, p1 = x;
    for (int k = 2; k <= q; ++k) {
      const double p2 = ((2 * k - 1) * x * p1 - (k - 1) * p0) / k;
      p0 = p1;
      p1 = p2;
    }
    derivative = q * (x * p1 - p0) / (x * x - 1);
    return p1;
  };
  nodes.assign(q, 0);
  weights.assign(q, 0);
  for (int i = 0; i < (q + 1) / 2; ++i) {
    double x = std::cos(kPi * (i + 0.75) / (q + 0.5)), dp = 1;
    for (int it = 0; it < 100; ++it) {  // Newton from the classic first guess
      const double dx = legendre(x, dp) / dp;
      x -= dx;
      if (std::abs(dx) < 1e-15) break;
    }
    legendre(x, dp);
    nodes[i] = -x;
    nodes[q - 1 - i] = x;
    weights[i] = weights[q - 1 - i] = 2 / ((1 - x * x) * dp * dp);
  }
}

const std::vector<std::string> &integrandKinds() {
  static const std::vector<std::string> kinds{
      "gaussian*step",         "quarterdisc*bilinear", "envmap*cos",         "disney*envmap",
      "disney-grazing*envmap", "disney*cosines",       "disney-views*envmap"};
  return kinds;
}

Vec3 grazingWo() {
  const double theta = 89 * std::numbers::pi / 180;
  return {std::sin(theta), 0, std::cos(theta)};
}

Integrand makeGaussianStep() {
  auto target = std::make_shared<GaussianTarget>(0.5, 0.5, 0.15);
  Integrand in;
  in.name = "gaussian*step";
  in.target = target;
  in.f = [t = target.get()](Point2 x) { return x.x < kStepX0 ? t->pdf(x) : 0.0; };
  in.reference = target->mass({{0, 0}, {kStepX0, 1}});
  in.referenceMethod = "exact box mass (erf)";
  return in;
}

Integrand makeQuarterDiscBilinear() {
  auto target = std::make_shared<QuarterDiscTarget>();
  Integrand in;
  in.name = "quarterdisc*bilinear";
  in.target = target;
  in.f = [t = target.get()](Point2 x) {
    return t->pdf(x) * (kA + kB * x.x + kC * x.y + kD * x.x * x.y);
  };
  in.reference = kA + 4 / kPi * ((kB + kC) / 3 + kD / 8);
  in.referenceMethod = "closed form (disc moments)";
  return in;
}

double StudyEnvmap::luminanceAt(Point2 x) const {
  const GridTarget::Cell c = target->locate(x);
  return luminance[std::size_t(c.j) * width + c.i];
}

std::shared_ptr<const StudyEnvmap> makeStudyEnvmap(const Image &latlong, std::string name,
                                                   std::string source) {
  auto map = std::make_shared<StudyEnvmap>();
  map->name = std::move(name);
  map->source = std::move(source);
  map->width = latlong.width;
  map->height = latlong.height;
  map->luminance.resize(std::size_t(latlong.width) * latlong.height);
  bool black = true;
  for (int j = 0; j < latlong.height; ++j)
    for (int i = 0; i < latlong.width; ++i) {
      const double l = std::max(0.0, latlong.luminance(i, j));
      map->luminance[std::size_t(j) * latlong.width + i] = l;
      black = black && l == 0;
    }
  if (black || map->luminance.empty())
    throw std::invalid_argument(map->source +
                                ": the environment map is black (nothing to integrate)");
  map->target = makeEnvmapTarget(latlong, map->source);
  return map;
}

std::shared_ptr<const StudyEnvmap> loadStudyEnvmap(const std::string &path, std::string name) {
  return makeStudyEnvmap(readImage(path), std::move(name), path);
}

Vec3 envmapCosNormal() {
  const double theta = 45 / kDegrees, phi = 90 / kDegrees;
  return {std::sin(theta) * std::cos(phi), std::sin(theta) * std::sin(phi), std::cos(theta)};
}

Integrand makeEnvmapCos(std::shared_ptr<const StudyEnvmap> map, Vec3 normal) {
  normal = normalize(normal);
  Integrand in;
  in.name = "envmap:" + map->name + "*cos";
  in.target = map->target;
  in.f = [map, normal](Point2 x) {
    return kFourPi * map->luminanceAt(x) * std::max(0.0, dot(normal, sphereDirection(x)));
  };
  // n . w = nz z + nh sqrt(1 - z^2) cos(phi - phiN): exact in phi per pixel,
  // Gauss-Legendre in z per row.
  const double nh = std::hypot(normal.x, normal.y), phiN = std::atan2(normal.y, normal.x);
  const int W = map->width, H = map->height;
  // Where g(z) = the phi integral has kinks, Gauss-Legendre converges
  // slowly, so each pixel's z range is split there: at z = +-nh (where
  // n.w = 0 touches a parallel) and where n.w = 0 crosses the pixel's edge
  // meridians.
  const auto edgeCrossing = [&](double phi) {
    const double c = std::cos(phi - phiN), d = std::hypot(normal.z, nh * c);
    if (normal.z == 0 || d == 0) return 0.0;
    return -std::copysign(1.0, normal.z) * nh * c / d;
  };
  const auto reference = [&](int q) {
    std::vector<double> xs, ws;
    gaussLegendre(q, xs, ws);
    return sumRows(H, [&](int j) {
      const double zTop = rowTopZ(j, H), zBottom = rowTopZ(j + 1, H);
      double row = 0;
      std::vector<double> cuts;
      for (int i = 0; i < W; ++i) {
        const double l = map->luminance[std::size_t(j) * W + i];
        if (l == 0) continue;
        const double phi0 = 2 * kPi * i / W, phi1 = 2 * kPi * (i + 1) / W;
        cuts = {zBottom, zTop};
        for (double z : {nh, -nh, edgeCrossing(phi0), edgeCrossing(phi1)})
          if (z > zBottom && z < zTop) cuts.push_back(z);
        std::sort(cuts.begin(), cuts.end());
        double cell = 0;
        for (std::size_t c = 0; c + 1 < cuts.size(); ++c) {
          // z = lo + (hi - lo) (3 s^2 - 2 s^3): flat at both ends, so the
          // (z - z*)^(3/2) behaviour where the terminator touches a
          // parallel becomes smooth enough for Gauss-Legendre in s.
          const double lo = cuts[c], span = cuts[c + 1] - cuts[c];
          for (int k = 0; k < q; ++k) {
            const double t = 0.5 * (1 + xs[k]);
            const double z = lo + span * t * t * (3 - 2 * t), dz = span * 6 * t * (1 - t);
            const double r = std::sqrt(std::max(0.0, 1 - z * z));
            cell +=
                0.5 * ws[k] * dz * clippedCosineIntegral(normal.z * z, nh * r, phi0, phi1, phiN);
          }
        }
        row += l * cell;
      }
      return row;
    });
  };
  in.reference = reference(16);
  in.referenceError = std::abs(in.reference - reference(8));
  in.referenceMethod = "per pixel: exact in phi, 16-node Gauss-Legendre in z between kinks";
  return in;
}

namespace {

// The gamma under which a `family:disney` model makes the target `spec`.
std::function<std::optional<std::vector<double>>(const TargetFamily &)> familyGammaOf(
    std::string spec) {
  return [spec](const TargetFamily &family) -> std::optional<std::vector<double>> {
    return disneyFamilyGamma(family.spec(), spec);
  };
}

}  // namespace

Integrand makeDisneyEnvmap(std::shared_ptr<const StudyEnvmap> map, const DisneyParams &params,
                           Vec3 wo, LobeChoice lobes) {
  wo = normalize(wo);
  if (!(wo.z > 0)) throw std::invalid_argument("disney*envmap: wo must point above the surface");
  auto brdf = std::make_shared<DisneyBrdf>(params, lobes);
  // The supplement's instance keeps the canonical spec `disney`, so models
  // and cached sets made for `--target disney` match it.
  DisneyTargetSpec spec;
  spec.params = params;
  if (!(wo == supplementWo())) {
    spec.thetaDegrees = std::atan2(std::hypot(wo.x, wo.y), wo.z) * kDegrees;
    spec.phiDegrees = std::atan2(wo.y, wo.x) * kDegrees;
    if (spec.phiDegrees < 0) spec.phiDegrees += 360;
  }
  std::shared_ptr<const GridTarget> target = makeDisneyTarget(spec);

  Integrand in;
  in.name = "disney*envmap:" + map->name;
  in.target = target;
  const auto g = [brdf, map, wo](Vec3 wi, Point2 x) {
    if (!(wi.z > 0)) return 0.0;
    return brdf->eval(wo, wi).luminance() * wi.z * map->luminanceAt(x);
  };
  in.f = [g](Point2 x) { return kFourPi * g(sphereDirection(x), x); };
  in.lobeContribution = [brdf, map, wo](Point2 u) {
    const auto s = brdf->sampleSquare(wo, u);
    if (!s) return 0.0;
    return s->f.luminance() * s->wi.z * map->luminanceAt(spherePoint(s->wi)) / s->pdf;
  };
  in.familyGamma = familyGammaOf(toSpec(spec));

  // Gauss-Legendre q x q in (phi, z) over each pixel's part above the
  // horizon, on sub-cells at most 2 pi / 128 wide and 1 / 32 of z high (a
  // coarse map's pixels are split; a 1024 x 512 map's are not).
  const int W = map->width, H = map->height;
  const int subPhi = std::max(1, (128 + W - 1) / W), subZ = std::max(1, (64 + H - 1) / H);
  const auto reference = [&](int q) {
    std::vector<double> xs, ws;
    gaussLegendre(q, xs, ws);
    return sumRows(H, [&](int j) {
      const double zTop = rowTopZ(j, H), zBottom = std::max(0.0, rowTopZ(j + 1, H));
      if (!(zTop > zBottom)) return 0.0;
      const double hz = 0.5 * (zTop - zBottom) / subZ, hphi = kPi / (W * subPhi);
      double row = 0;
      for (int i = 0; i < W; ++i) {
        const double l = map->luminance[std::size_t(j) * W + i];
        if (l == 0) continue;
        double cell = 0;
        for (int sz = 0; sz < subZ; ++sz)
          for (int sp = 0; sp < subPhi; ++sp) {
            const double mz = zBottom + (2 * sz + 1) * hz;
            const double mphi = 2 * kPi * (i + (sp + 0.5) / subPhi) / W;
            for (int a = 0; a < q; ++a) {
              const double z = mz + hz * xs[a], r = std::sqrt(std::max(0.0, 1 - z * z));
              for (int b = 0; b < q; ++b) {
                const double phi = mphi + hphi * xs[b];
                const Vec3 wi{r * std::cos(phi), r * std::sin(phi), z};
                cell += ws[a] * ws[b] * brdf->eval(wo, wi).luminance() * z;
              }
            }
          }
        row += l * cell * hz * hphi;
      }
      return row;
    });
  };
  in.reference = reference(8);
  in.referenceError = std::abs(in.reference - reference(4));
  in.referenceMethod = "per pixel: 8x8 Gauss-Legendre in (phi, z) above the horizon";
  return in;
}

std::vector<Vec3> smoothLightNormals() {
  std::vector<Vec3> normals;
  Rng rng(0x636f73696e6573ull);  // fixed: the integrand is part of the study's definition
  for (int k = 0; k < 8; ++k) {
    const double z = 2 * rng.uniform() - 1, phi = 2 * kPi * rng.uniform();
    const double r = std::sqrt(std::max(0.0, 1 - z * z));
    normals.push_back({r * std::cos(phi), r * std::sin(phi), z});
  }
  return normals;
}

Integrand makeDisneyCosines(double thetaDegrees, const DisneyParams &params, LobeChoice lobes) {
  if (!(thetaDegrees >= 0 && thetaDegrees < 90))
    throw std::invalid_argument("disney*cosines: theta must lie in [0, 90) degrees");
  DisneyTargetSpec spec;
  spec.params = params;
  spec.thetaDegrees = thetaDegrees;
  const Vec3 wo = spec.wo();
  auto brdf = std::make_shared<DisneyBrdf>(params, lobes);
  const std::vector<Vec3> normals = smoothLightNormals();
  const auto light = [normals](Vec3 wi) {
    double l = 0;
    for (const Vec3 &n : normals) l += std::max(0.0, dot(n, wi));
    return l / double(normals.size());
  };
  const auto g = [brdf, wo, light](Vec3 wi) {
    if (!(wi.z > 0)) return 0.0;
    return brdf->eval(wo, wi).luminance() * wi.z * light(wi);
  };

  Integrand in;
  in.name = disneyCosinesName(thetaDegrees);
  in.target = makeDisneyTarget(spec);
  in.f = [g](Point2 x) { return kFourPi * g(sphereDirection(x)); };
  in.lobeContribution = [brdf, wo, light](Point2 u) {
    const auto s = brdf->sampleSquare(wo, u);
    if (!s) return 0.0;
    return s->f.luminance() * s->wi.z * light(s->wi) / s->pdf;
  };
  in.familyGamma = familyGammaOf(toSpec(spec));

  // Gauss-Legendre q x q on each of 256 x 128 cells of (phi, z) over the
  // hemisphere (d omega = d phi d z); the light's kinks cost accuracy only
  // in the cells they cross.
  constexpr int kPhiCells = 256, kZCells = 128;
  const auto reference = [&](int q) {
    std::vector<double> xs, ws;
    gaussLegendre(q, xs, ws);
    const double hphi = kPi / kPhiCells, hz = 0.5 / kZCells;
    return sumRows(kZCells, [&](int j) {
      double row = 0;
      for (int i = 0; i < kPhiCells; ++i)
        for (int a = 0; a < q; ++a) {
          const double z = (2 * j + 1) * hz + hz * xs[a], r = std::sqrt(std::max(0.0, 1 - z * z));
          for (int b = 0; b < q; ++b) {
            const double phi = (2 * i + 1) * hphi + hphi * xs[b];
            row += ws[a] * ws[b] * g({r * std::cos(phi), r * std::sin(phi), z});
          }
        }
      return row * hz * hphi;
    });
  };
  in.reference = reference(6);
  in.referenceError = std::abs(in.reference - reference(3));
  in.referenceMethod = "6x6 Gauss-Legendre on 256 x 128 cells of (phi, cos theta)";
  return in;
}

std::vector<double> disneyCosinesThetas() { return {20, 45, 70}; }

std::vector<double> disneyViewThetas() { return {20, 70}; }

std::string disneyViewName(const std::string &map, double thetaDegrees) {
  char theta[32];
  std::snprintf(theta, sizeof theta, "%g", thetaDegrees);
  return "disney*envmap:" + map + ":theta=" + theta;
}

std::string disneyCosinesName(double thetaDegrees) {
  char name[64];
  std::snprintf(name, sizeof name, "disney*cosines:theta=%g", thetaDegrees);
  return name;
}

}  // namespace nuld::study
