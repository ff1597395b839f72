#include "renderer/flip.h"

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <cmath>
#include <numbers>
#include <stdexcept>
#include <string>

namespace nuld {
namespace flip {
namespace {

// The papers' constants (see flip.h for where each comes from).
constexpr double kQc = 0.7, kPc = 0.4, kPt = 0.95, kQf = 0.5;
constexpr double kFeatureWidthDegrees = 0.082;  // w: the edge detector's peak-to-trough width
constexpr double kExposureTarget = 0.85;        // t: tone-mapped value of the exposure ends

// A CSF is a sum of Gaussians a sqrt(pi / b) exp(-pi^2 x^2 / b), x in
// degrees: per channel (achromatic, red-green, blue-yellow) two terms {a, b},
// a = 0 for none. The widest term (largest b) sets one radius for all three.
constexpr double kCsf[3][2][2] = {
    {{1.0, 0.0047}, {0, 0}}, {{1.0, 0.0053}, {0, 0}}, {{34.1, 0.04}, {13.5, 0.025}}};
constexpr double kCsfLargestB = 0.04;

// Narkowicz's ACES fit (2.51x^2 + 0.03x) / (2.43x^2 + 0.59x + 0.14) of 0.6 x.
constexpr double kAces[6] = {0.6 * 0.6 * 2.51, 0.6 * 0.03, 0.0, 0.6 * 0.6 * 2.43, 0.6 * 0.59, 0.14};

using Matrix3 = std::array<Color, 3>;
// Linear sRGB -> XYZ, exact fractions (the sRGB primaries and D65).
constexpr Matrix3 kRgbToXyz = {
    {{10135552.0 / 24577794.0, 8788810.0 / 24577794.0, 4435075.0 / 24577794.0},
     {2613072.0 / 12288897.0, 8788810.0 / 12288897.0, 887015.0 / 12288897.0},
     {1425312.0 / 73733382.0, 8788810.0 / 73733382.0, 70074185.0 / 73733382.0}}};

// The inverse by cofactors: exact to rounding, not a table of rounded values.
constexpr Matrix3 invert(const Matrix3 &a) {
  Matrix3 r{};
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j)
      r[i][j] = a[(j + 1) % 3][(i + 1) % 3] * a[(j + 2) % 3][(i + 2) % 3] -
                a[(j + 1) % 3][(i + 2) % 3] * a[(j + 2) % 3][(i + 1) % 3];
  const double det = a[0][0] * r[0][0] + a[0][1] * r[1][0] + a[0][2] * r[2][0];
  for (Color &row : r)
    for (double &v : row) v /= det;
  return r;
}
constexpr Matrix3 kXyzToRgb = invert(kRgbToXyz);

constexpr Color multiply(const Matrix3 &m, const Color &v) {
  Color r{};
  for (int i = 0; i < 3; ++i) r[i] = m[i][0] * v[0] + m[i][1] * v[1] + m[i][2] * v[2];
  return r;
}
constexpr Color kWhite = multiply(kRgbToXyz, {1, 1, 1});

double clamp01(double v) { return std::clamp(v, 0.0, 1.0); }

// Runs body(begin, end) over [0, n) in bands of rows, through TBB as the
// renderer's tiles are (its thread limit applies). Rows are independent, so
// the result is the same for any split.
template <typename Body>
void parallelRows(int n, const Body &body) {
  tbb::parallel_for(tbb::blocked_range<int>(0, n, 8),
                    [&](const tbb::blocked_range<int> &r) { body(r.begin(), r.end()); });
}
// The same over the pixels of rows [0, h) of width w.
template <typename Body>
void parallelPixels(int w, int h, const Body &body) {
  parallelRows(h, [&](int y0, int y1) {
    for (std::size_t i = std::size_t(y0) * w; i < std::size_t(y1) * w; ++i) body(i);
  });
}

// Planes hold float, as NVIDIA's code does: half the memory traffic and twice
// the vector width of double, and far more precision than the eye needs.
using Real = float;
using Plane = std::vector<Real>;  // width x height, row-major

// The convolutions work on blocks of kBlock neighbouring outputs held in a
// small array, which compilers keep in vector registers (the block size
// is measured in tools/experiments/README.md, "FLIP"), and fold
// each kernel's mirrored taps together: every kernel here is even
// (w[-j] = w[j]) or odd (w[-j] = -w[j]).
constexpr int kBlock = 32;

// acc[u] += sum_j k[j] at(u, j) over the 2r + 1 taps j of output u.
template <typename At>
void foldedTaps(const std::vector<Real> &k, const At &at, Real (&acc)[kBlock]) {
  const int r = int(k.size() / 2);
  const Real mirror = k[0] == -k.back() && k[0] != 0 ? -1 : 1;  // odd or even
  for (int u = 0; u < kBlock; ++u) acc[u] += k[r] * at(u, r);
  for (int j = 0; j < r; ++j)
    for (int u = 0; u < kBlock; ++u) acc[u] += k[j] * (at(u, j) + mirror * at(u, 2 * r - j));
}

// Correlation along rows with a 1D kernel, the border clamped to the edge.
Plane horizontal(const Plane &in, int w, int h, const std::vector<double> &weights) {
  const std::vector<Real> k(weights.begin(), weights.end());
  const int r = int(k.size() / 2);
  Plane out(in.size());
  parallelRows(h, [&](int y0, int y1) {
    std::vector<Real> padded(std::size_t(w) + 2 * r + kBlock);
    for (int y = y0; y < y1; ++y) {
      const Real *row = &in[std::size_t(y) * w];
      for (std::size_t i = 0; i < padded.size(); ++i)
        padded[i] = row[std::clamp(int(i) - r, 0, w - 1)];
      for (int x0 = 0; x0 < w; x0 += kBlock) {
        Real acc[kBlock] = {};
        foldedTaps(
            k, [&](int u, int j) { return padded[x0 + u + j]; }, acc);
        std::copy_n(acc, std::min(kBlock, w - x0), &out[std::size_t(y) * w + x0]);
      }
    }
  });
  return out;
}

// The same along columns, added into `out` (a kernel may be a sum of terms).
void vertical(const Plane &in, int w, int h, const std::vector<double> &weights, Plane &out) {
  const std::vector<Real> k(weights.begin(), weights.end());
  const int r = int(k.size() / 2);
  parallelRows(h, [&](int y0, int y1) {
    std::vector<const Real *> rows(k.size());
    for (int y = y0; y < y1; ++y) {
      for (int j = 0; j <= 2 * r; ++j)
        rows[j] = &in[std::size_t(std::clamp(y + j - r, 0, h - 1)) * w];
      for (int x0 = 0; x0 < w; x0 += kBlock) {
        Real acc[kBlock] = {};
        const int n = std::min(kBlock, w - x0);
        if (n == kBlock)
          foldedTaps(
              k, [&](int u, int j) { return rows[j][x0 + u]; }, acc);
        else  // the last, partial block repeats its last column
          foldedTaps(
              k, [&](int u, int j) { return rows[j][std::min(x0 + u, w - 1)]; }, acc);
        for (int u = 0; u < n; ++u) out[std::size_t(y) * w + x0 + u] += acc[u];
      }
    }
  });
}

Plane filtered(const Plane &in, int w, int h, const SeparableKernel &k) {
  Plane out(in.size(), Real(0));
  for (const std::vector<double> &f : k.factors) vertical(horizontal(in, w, h, f), w, h, f, out);
  return out;
}

struct Filters {
  SeparableKernel achromatic, redGreen, blueYellow;
  FeatureKernels features;
};

struct Rgb {
  int width = 0, height = 0;
  std::array<Plane, 3> c;  // linear RGB in [0, 1]
};

// What LDR-FLIP needs of one image: its CSF-filtered colours as
// Hunt-adjusted L*a*b*, and the edge and point strengths of its luminance.
struct Analysis {
  std::array<Plane, 3> lab;
  Plane edge, point;
};

Analysis analyze(const Rgb &img, const Filters &f) {
  const int w = img.width, h = img.height;
  const std::size_t n = std::size_t(w) * h;
  std::array<Plane, 3> opponent{Plane(n), Plane(n), Plane(n)};
  Plane luminance(n);  // Y / Y_white in [0, 1], the feature detector's input
  parallelPixels(w, h, [&](std::size_t i) {
    const Color xyz = linearRgbToXyz({img.c[0][i], img.c[1][i], img.c[2][i]});
    const Color o = xyzToYcxcz(xyz);
    for (int c = 0; c < 3; ++c) opponent[c][i] = Real(o[c]);
    luminance[i] = Real(xyz[1] / kWhite[1]);
  });
  Analysis a;
  a.lab = {filtered(opponent[0], w, h, f.achromatic), filtered(opponent[1], w, h, f.redGreen),
           filtered(opponent[2], w, h, f.blueYellow)};
  // The filtered opponent colours may leave the RGB cube; FLIP clamps them
  // back before measuring colour differences.
  parallelPixels(w, h, [&](std::size_t i) {
    Color rgb = xyzToLinearRgb(ycxczToXyz({a.lab[0][i], a.lab[1][i], a.lab[2][i]}));
    for (double &v : rgb) v = clamp01(v);
    const Color lab = huntAdjust(xyzToLab(linearRgbToXyz(rgb)));
    for (int c = 0; c < 3; ++c) a.lab[c][i] = Real(lab[c]);
  });
  // Gaussian derivatives along x (smoothed along y) and along y (smoothed
  // along x): products of 1D factors.
  const FeatureKernels &k = f.features;
  const Plane smooth = horizontal(luminance, w, h, k.gaussian);
  const auto along = [&](const Plane &alongX, const std::vector<double> &alongY) {
    Plane out(n, Real(0));
    vertical(alongX, w, h, alongY, out);
    return out;
  };
  const Plane ex = along(horizontal(luminance, w, h, k.edge), k.gaussian);
  const Plane px = along(horizontal(luminance, w, h, k.point), k.gaussian);
  const Plane ey = along(smooth, k.edge), py = along(smooth, k.point);
  a.edge.resize(n);
  a.point.resize(n);
  parallelPixels(w, h, [&](std::size_t i) {
    a.edge[i] = std::sqrt(ex[i] * ex[i] + ey[i] * ey[i]);
    a.point[i] = std::sqrt(px[i] * px[i] + py[i] * py[i]);
  });
  return a;
}

Stages compare(const Rgb &test, const Rgb &reference, const Filters &f) {
  const Analysis t = analyze(test, f), r = analyze(reference, f);
  const std::size_t n = std::size_t(test.width) * test.height;
  Stages s{test.width, test.height, std::vector<float>(n), std::vector<float>(n),
           std::vector<float>(n)};
  parallelPixels(test.width, test.height, [&](std::size_t i) {
    const double d =
        hyab({t.lab[0][i], t.lab[1][i], t.lab[2][i]}, {r.lab[0][i], r.lab[1][i], r.lab[2][i]});
    // cmax bounds hyab^qc on the RGB cube; the clamp only guards rounding.
    // Powers in float (faster; the planes hold float precision anyway).
    const double color = std::min(1.0, compressColorDifference(std::pow(float(d), float(kQc))));
    // Each strength is at most sqrt 2 (kernels of unit positive and negative
    // mass on values in [0, 1]), so the difference / sqrt 2 is in [0, 1].
    const double edge = std::abs(t.edge[i] - r.edge[i]), point = std::abs(t.point[i] - r.point[i]);
    const double feature = std::min(1.0, std::max(edge, point) / std::numbers::sqrt2);
    const double powered = kQf == 0.5 ? std::sqrt(feature) : std::pow(feature, kQf);
    s.color[i] = float(color);
    s.feature[i] = float(powered);
    // 0^0 would be 1: no colour difference is no error, whatever the features.
    s.flip[i] = color == 0 ? 0.0f : std::pow(float(color), float(1 - powered));
  });
  return s;
}

Filters makeFilters(double ppd) {
  return {csfKernel(CsfChannel::Achromatic, ppd), csfKernel(CsfChannel::RedGreen, ppd),
          csfKernel(CsfChannel::BlueYellow, ppd), featureKernels(ppd)};
}

std::string size(const Image &img) {
  return std::to_string(img.width) + "x" + std::to_string(img.height);
}

void checkImage(const Image &img, const std::string &name) {
  if (img.channels < 3)
    throw std::invalid_argument("FLIP needs 3 (RGB) or more channels: the " + name + " image (" +
                                size(img) + ") has " + std::to_string(img.channels));
  if (img.width <= 0 || img.height <= 0 ||
      img.pixels.size() != std::size_t(img.width) * img.height * img.channels)
    throw std::invalid_argument("FLIP: the " + name + " image (" + size(img) + ", " +
                                std::to_string(img.channels) + " channels) holds " +
                                std::to_string(img.pixels.size()) + " values");
  for (int y = 0; y < img.height; ++y)
    for (int x = 0; x < img.width; ++x)
      for (int c = 0; c < 3; ++c)  // a 4th channel (alpha) plays no part
        if (!std::isfinite(img.at(x, y, c)))
          throw std::invalid_argument("FLIP: " + name + " image: pixel (" + std::to_string(x) +
                                      ", " + std::to_string(y) + ") channel " + std::to_string(c) +
                                      " is not a finite number");
}

void checkPair(const Image &test, const Image &reference) {
  if (test.width != reference.width || test.height != reference.height)
    throw std::invalid_argument("FLIP: the test image is " + size(test) + " but the reference is " +
                                size(reference));
  checkImage(test, "test");
  checkImage(reference, "reference");
}

// The first three channels through `f`, as planes.
template <typename F>
Rgb toRgb(const Image &img, const F &f) {
  Rgb out{img.width, img.height, {}};
  for (Plane &p : out.c) p.resize(std::size_t(img.width) * img.height);
  parallelPixels(img.width, img.height, [&](std::size_t i) {
    for (int c = 0; c < 3; ++c) out.c[c][i] = Real(f(double(img.pixels[i * img.channels + c])));
  });
  return out;
}

FlipResult toResult(std::vector<float> map, int w, int h) {
  double sum = 0;
  for (const float v : map) sum += v;
  return {std::move(map), w, h, sum / double(std::size_t(w) * h)};
}

}  // namespace

Color linearRgbToXyz(const Color &rgb) { return multiply(kRgbToXyz, rgb); }
Color xyzToLinearRgb(const Color &xyz) { return multiply(kXyzToRgb, xyz); }
Color referenceWhite() { return kWhite; }

// CIELAB's L*, a*, b* without the cube root: linear in XYZ, so filtering in
// it is filtering of light (the YyCxCz space FLIP filters in).
Color xyzToYcxcz(const Color &xyz) {
  const double x = xyz[0] / kWhite[0], y = xyz[1] / kWhite[1], z = xyz[2] / kWhite[2];
  return {116 * y - 16, 500 * (x - y), 200 * (y - z)};
}
Color ycxczToXyz(const Color &o) {
  const double y = (o[0] + 16) / 116;
  return {(y + o[1] / 500) * kWhite[0], y * kWhite[1], (y - o[2] / 200) * kWhite[2]};
}

Color xyzToLab(const Color &xyz) {
  constexpr double delta = 6.0 / 29.0;
  const auto f = [](double t) {
    return t > delta * delta * delta ? std::cbrt(t) : t / (3 * delta * delta) + 4.0 / 29.0;
  };
  const double fx = f(xyz[0] / kWhite[0]), fy = f(xyz[1] / kWhite[1]), fz = f(xyz[2] / kWhite[2]);
  return {116 * fy - 16, 500 * (fx - fy), 200 * (fy - fz)};
}

double maxColorDifference() {
  static const double cmax = std::pow(hyab(huntAdjust(xyzToLab(linearRgbToXyz({0, 1, 0}))),
                                           huntAdjust(xyzToLab(linearRgbToXyz({0, 0, 1})))),
                                      kQc);
  return cmax;
}

double compressColorDifference(double e) {
  const double cmax = maxColorDifference(), knee = kPc * cmax;
  return e < knee ? e * (kPt / knee) : kPt + (e - knee) / (cmax - knee) * (1 - kPt);
}

double toneMapAces(double x) {
  const double *k = kAces;
  // Divided through by x^2 above 1, so that no square overflows.
  const double y = x <= 1 ? (k[0] * x * x + k[1] * x + k[2]) / (k[3] * x * x + k[4] * x + k[5])
                          : (k[0] + k[1] / x + k[2] / (x * x)) / (k[3] + k[4] / x + k[5] / (x * x));
  return clamp01(y);
}

double acesInverse(double t) {
  // (k0 - t k3) x^2 + (k1 - t k4) x + (k2 - t k5) = 0, whose positive root
  // is taken in the cancellation-free form.
  const double *k = kAces;
  const double a = k[0] - t * k[3], b = k[1] - t * k[4], c = k[2] - t * k[5];
  const double q = -0.5 * (b + std::copysign(std::sqrt(b * b - 4 * a * c), b));
  return std::max(q / a, c / q);
}

SeparableKernel csfKernel(CsfChannel channel, double ppd) {
  constexpr double pi = std::numbers::pi;
  SeparableKernel k;
  k.radius = int(std::ceil(3 * std::sqrt(kCsfLargestB / (2 * pi * pi)) * ppd));
  // a sqrt(pi/b) exp(-pi^2 (x^2 + y^2) / b) is the outer product of
  // sqrt(a sqrt(pi/b)) exp(-pi^2 x^2 / b) with itself. Dividing every factor
  // by the root of the sum of the squared factor sums makes the 2D sum 1.
  double squaredSums = 0;
  for (const auto &[a, b] : kCsf[int(channel)]) {
    if (a == 0) continue;
    std::vector<double> f(2 * k.radius + 1);
    double sum = 0;
    for (int i = -k.radius; i <= k.radius; ++i) {
      const double x = i / ppd;  // degrees
      sum += f[i + k.radius] = std::sqrt(a * std::sqrt(pi / b)) * std::exp(-pi * pi * x * x / b);
    }
    squaredSums += sum * sum;
    k.factors.push_back(std::move(f));
  }
  for (std::vector<double> &f : k.factors)
    for (double &v : f) v /= std::sqrt(squaredSums);
  return k;
}

FeatureKernels featureKernels(double ppd) {
  const double sigma = 0.5 * kFeatureWidthDegrees * ppd;  // in pixels
  FeatureKernels k;
  k.radius = int(std::ceil(3 * sigma));
  for (int i = -k.radius; i <= k.radius; ++i) {
    const double g = std::exp(-(i * i) / (2 * sigma * sigma));
    k.gaussian.push_back(g);
    k.edge.push_back(-i * g);
    k.point.push_back((i * i / (sigma * sigma) - 1) * g);
  }
  // The Gaussian to unit sum; each derivative's positive and negative lobes
  // to +1 and -1 (a lobe that underflowed at a tiny ppd stays 0).
  for (std::vector<double> *f : {&k.gaussian, &k.edge, &k.point}) {
    const bool bySign = f != &k.gaussian;
    double positive = 0, negative = 0;
    for (const double v : *f) (v > 0 || !bySign ? positive : negative) += std::abs(v);
    for (double &v : *f)
      if (const double mass = v > 0 || !bySign ? positive : negative; mass > 0) v /= mass;
  }
  return k;
}

Stages ldrFlipLinear(const Image &testLinear, const Image &referenceLinear, double ppd) {
  checkPair(testLinear, referenceLinear);
  if (!(ppd > 0) || !std::isfinite(ppd))
    throw std::invalid_argument("FLIP: pixels per degree must be a positive finite number");
  return compare(toRgb(testLinear, clamp01), toRgb(referenceLinear, clamp01), makeFilters(ppd));
}

}  // namespace flip

double FlipViewing::pixelsPerDegree() const {
  const std::pair<const char *, double> values[] = {
      {"monitorDistanceMeters", monitorDistanceMeters},
      {"monitorWidthMeters", monitorWidthMeters},
      {"monitorWidthPixels", monitorWidthPixels}};
  for (const auto &[name, v] : values)
    if (!(v > 0) || !std::isfinite(v))
      throw std::invalid_argument(std::string("FLIP: the viewing condition ") + name + " is " +
                                  std::to_string(v) + "; it must be a positive finite number");
  return monitorDistanceMeters * (monitorWidthPixels / monitorWidthMeters) * std::numbers::pi / 180;
}

FlipResult ldrFlip(const Image &test, const Image &reference, const FlipViewing &v) {
  const double ppd = v.pixelsPerDegree();
  flip::checkPair(test, reference);
  const auto decode = [](double s) { return flip::srgbToLinear(flip::clamp01(s)); };
  flip::Stages s = flip::compare(flip::toRgb(test, decode), flip::toRgb(reference, decode),
                                 flip::makeFilters(ppd));
  return flip::toResult(std::move(s.flip), test.width, test.height);
}

FlipExposures hdrFlipExposures(const Image &reference, const HdrFlipOptions &o) {
  flip::checkImage(reference, "reference");
  double start = 0, stop = 0;  // an all-black reference stays at exposure 0
  if (!o.startExposure || !o.stopExposure) {
    std::vector<double> y;
    for (std::size_t i = 0; i < reference.pixels.size(); i += reference.channels)
      y.push_back(rec709Luminance(std::max(0.0f, reference.pixels[i]),
                                  std::max(0.0f, reference.pixels[i + 1]),
                                  std::max(0.0f, reference.pixels[i + 2])));
    std::sort(y.begin(), y.end());
    if (y.back() > 0) {
      double median = y[y.size() / 2];
      if (median <= 0) {  // most of it black: the median of what is lit
        const auto lit = std::upper_bound(y.begin(), y.end(), 0.0);
        median = lit[(y.end() - lit) / 2];
      }
      const double x85 = flip::acesInverse(flip::kExposureTarget);
      start = std::log2(x85 / y.back());
      stop = std::log2(x85 / median);
    }
  }
  for (const auto &e : {o.startExposure, o.stopExposure})
    if (e && !std::isfinite(*e))
      throw std::invalid_argument("HDR-FLIP: an exposure option is not a finite number");
  start = o.startExposure.value_or(start);
  stop = o.stopExposure.value_or(stop);
  if (start > stop)
    throw std::invalid_argument("HDR-FLIP: the start exposure " + std::to_string(start) +
                                " is above the stop exposure " + std::to_string(stop));
  if (o.exposures && *o.exposures < 1)
    throw std::invalid_argument("HDR-FLIP: " + std::to_string(*o.exposures) +
                                " exposures; it needs 1 or more");
  constexpr double kMaxStops = 1000;  // far past any image's range
  if (!o.exposures && stop - start > kMaxStops)
    throw std::invalid_argument("HDR-FLIP: exposures from " + std::to_string(start) + " to " +
                                std::to_string(stop) + " span too many stops to evaluate");
  return {start, stop, o.exposures.value_or(std::max(2, int(std::ceil(stop - start - 1e-9))))};
}

FlipResult hdrFlip(const Image &test, const Image &reference, const FlipViewing &v,
                   const HdrFlipOptions &o) {
  const double ppd = v.pixelsPerDegree();
  flip::checkPair(test, reference);
  const FlipExposures e = hdrFlipExposures(reference, o);
  const flip::Filters filters = flip::makeFilters(ppd);
  std::vector<float> map(std::size_t(test.width) * test.height, 0.0f);
  const double step = e.count > 1 ? (e.stop - e.start) / (e.count - 1) : 0.0;
  // With step 0 every exposure is the first.
  for (int i = 0; i < (step > 0 ? e.count : 1); ++i) {
    const double scale = std::exp2(e.start + i * step);
    // A black pixel stays black even where 2^e overflows (0 x inf).
    const auto expose = [scale](double x) { return x > 0 ? flip::toneMapAces(x * scale) : 0.0; };
    const flip::Stages s =
        flip::compare(flip::toRgb(test, expose), flip::toRgb(reference, expose), filters);
    for (std::size_t p = 0; p < map.size(); ++p) map[p] = std::max(map[p], s.flip[p]);
  }
  return flip::toResult(std::move(map), test.width, test.height);
}

Image flipMapImage(const FlipResult &r) {
  // matplotlib's magma at entries 0, 16, ..., 240 and 255 (sRGB values).
  static constexpr float kKnots[17 * 3] = {
      0.001462f, 0.000466f, 0.013866f, 0.039608f, 0.031090f, 0.133515f, 0.113094f, 0.065492f,
      0.276784f, 0.211718f, 0.061992f, 0.418647f, 0.316654f, 0.071690f, 0.485380f, 0.414709f,
      0.110431f, 0.504662f, 0.512831f, 0.148179f, 0.507648f, 0.613617f, 0.181811f, 0.498536f,
      0.716387f, 0.214982f, 0.475290f, 0.816914f, 0.255895f, 0.436461f, 0.904281f, 0.319610f,
      0.388137f, 0.960949f, 0.418323f, 0.359630f, 0.986700f, 0.535582f, 0.382210f, 0.996096f,
      0.653659f, 0.446213f, 0.996898f, 0.769591f, 0.534892f, 0.992440f, 0.884330f, 0.640099f,
      0.987053f, 0.991438f, 0.749504f};
  Image out{r.width, r.height, 3, std::vector<float>(r.map.size() * 3)};
  for (std::size_t i = 0; i < r.map.size(); ++i) {
    const float v = std::isfinite(r.map[i]) ? std::clamp(r.map[i], 0.0f, 1.0f) : 0.0f;
    const float entry = v * 255;  // the knots sit at entries 16 k, the last at 255
    const int k = std::min(int(entry / 16), 15);
    const float lo = 16.0f * k, hi = k == 15 ? 255.0f : lo + 16, t = (entry - lo) / (hi - lo);
    for (int c = 0; c < 3; ++c)
      out.pixels[i * 3 + c] = kKnots[3 * k + c] + t * (kKnots[3 * k + 3 + c] - kKnots[3 * k + c]);
  }
  return out;
}

}  // namespace nuld
