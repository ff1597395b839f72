// The graph generator's per-point and per-edge inputs (TorchNet::graphInputs).

#include <algorithm>
#include <cmath>
#include <numbers>

#include "sampler/neural/network.h"

namespace nuld {

std::int64_t graphNodeFeatures(const NeuralSettings &s, std::size_t gammaDim) {
  const std::int64_t harmonics =
      ((2 * s.positionHarmonics + 1) * (2 * s.positionHarmonics + 1) - 1);
  return harmonics + 2 + 3 + 1 + std::int64_t(gammaDim) + (gammaDim > 0 ? s.encodingDims : 0) +
         (s.discrepancyGradient ? 3 : 0);
}

namespace {

// The descent direction at each point: dL2^2/du (pulled back through the
// map's Jacobians and balanced per coordinate as the trainer does) into
// `gradient`; returns its root mean square.
double descentDirection(const NonuniformL2asd &objective, std::span<const Point2> x,
                        std::span<const Jacobian2> jacobian, std::span<Point2> gradient) {
  const std::size_t n = x.size();
  objective.squared(x, gradient);
  double scale = 0;
  for (std::size_t i = 0; i < n; ++i) {
    gradient[i] = balancedPullback(jacobian[i].transposeTimes(gradient[i]), jacobian[i]);
    scale += (gradient[i].x * gradient[i].x + gradient[i].y * gradient[i].y) / double(n);
  }
  return std::sqrt(scale);
}

// How the map stretches around u: the log lengths of J's columns and the
// cosine between them (a zero or non-finite column reads as the floor).
double *writeStretch(double *f, const Jacobian2 &j) {
  const double c0 = std::hypot(j.m[0][0], j.m[1][0]), c1 = std::hypot(j.m[0][1], j.m[1][1]);
  auto logLength = [](double c) {
    return c > 0 && std::isfinite(c) ? std::clamp(std::log(c), -8.0, 8.0) / 4 : -2.0;
  };
  *f++ = logLength(c0);
  *f++ = logLength(c1);
  const double dot = j.m[0][0] * j.m[0][1] + j.m[1][0] * j.m[1][1];
  *f++ = c0 > 0 && c1 > 0 && std::isfinite(dot / (c0 * c1)) ? dot / (c0 * c1) : 0.0;
  return f;
}

// Edges of one set: each neighbour's offset on the torus of u (for the base
// set the same for every z) and in x, both in units of the spacing; x's is
// clamped, as a neighbour across the square's seam or a stretched region is
// simply far.
void writeEdges(Point2 *pe, std::span<const Point2> u, std::span<const Point2> x,
                const std::vector<std::int64_t> &nb, std::size_t k, bool sphere) {
  const std::size_t n = u.size();
  const double rootN = std::sqrt(double(n));
  auto clampSpacing = [&](double d) { return std::clamp(d * rootN, -4.0, 4.0); };
  for (std::size_t i = 0; i < n; ++i)
    for (std::size_t e = 0; e < k; ++e) {
      const std::size_t j = std::size_t(nb[i * k + e]);
      const Point2 du = torusDifference(u[i], u[j]);
      Point2 dx = x[j] - x[i];
      if (sphere) dx.x -= std::floor(dx.x + 0.5);  // longitude is periodic
      Point2 *edge = pe + 2 * (i * k + e);
      edge[0] = rootN * du;
      edge[1] = {clampSpacing(dx.x), clampSpacing(dx.y)};
    }
}

}  // namespace

std::pair<torch::Tensor, torch::Tensor> TorchNet::graphInputs(
    const NeuralGenerator &gen, std::span<const double> gamma, const torch::Tensor &points,
    const std::vector<TorusGraph> &graphs, std::span<const Target *const> members,
    std::span<const NonuniformL2asd *const> objectives) const {
  const NeuralSettings &s = gen.settings();
  const std::size_t K = std::size_t(points.size(0)), n = std::size_t(points.size(1)),
                    g = gen.gammaDimension();
  // One graph per set, one shared by all (a rotated base at another N), or `torus`.
  auto graphOf = [&](std::size_t set) -> const TorusGraph & {
    return graphs.empty() ? torus : graphs[graphs.size() == K ? set : 0];
  };
  const std::size_t k = graphOf(0).k;
  const std::int64_t F = graphNodeFeatures(s, g);
  const torch::Tensor harmonics = zHarmonicFrequencies(s.positionHarmonics, 2).to(torch::kFloat64);
  const std::int64_t H = harmonics.size(0);
  const double logN = std::log2(double(n)) / 10;
  const bool sphere = gen.domain() != Domain::Square;

  torch::Tensor nodes = torch::empty({std::int64_t(K), std::int64_t(n), F}, torch::kFloat64);
  torch::Tensor edges =
      torch::empty({std::int64_t(K), std::int64_t(n), std::int64_t(k), 4}, torch::kFloat64);
  const auto *pb = reinterpret_cast<const Point2 *>(points.data_ptr<double>());
  double *pn = nodes.data_ptr<double>();
  auto *pe = reinterpret_cast<Point2 *>(edges.data_ptr<double>());
  const auto hf = harmonics.accessor<double, 2>();
  std::vector<Point2> x(n), u(n), gradient(s.discrepancyGradient ? n : 0);
  std::vector<Jacobian2> jacobian(n);
  for (std::size_t set = 0; set < K; ++set) {
    const std::vector<std::int64_t> &nb = graphOf(set).neighbours;
    const std::span<const double> gs = gamma.subspan(set * g, g);
    const Target *target = members[set];
    std::vector<double> gammaCode;
    if (g > 0) {
      const torch::Tensor v =
          torch::from_blob(const_cast<double *>(gs.data()), {1, std::int64_t(g)}, torch::kFloat64);
      const torch::Tensor code = fourierFeatures(v, graph->B.to(torch::kFloat64)).contiguous();
      gammaCode.assign(code.data_ptr<double>(), code.data_ptr<double>() + code.numel());
    }
    for (std::size_t i = 0; i < n; ++i) {
      const Point2 raw = pb[set * n + i];
      u[i] = {wrapUnit(raw.x), wrapUnit(raw.y)};
      x[i] = gen.place(raw, *target, &jacobian[i]);
    }
    double gradientScale = 0;
    if (s.discrepancyGradient)
      gradientScale = descentDirection(*objectives[set], x, jacobian, gradient);
    for (std::size_t i = 0; i < n; ++i) {
      double *f = pn + (set * n + i) * std::size_t(F);
      for (std::int64_t h = 0; h < H; ++h) {
        const double angle = 2 * std::numbers::pi * (hf[h][0] * u[i].x + hf[h][1] * u[i].y);
        *f++ = std::cos(angle);
        *f++ = std::sin(angle);
      }
      *f++ = 2 * x[i].x - 1;
      *f++ = 2 * x[i].y - 1;
      f = writeStretch(f, jacobian[i]);
      *f++ = logN;
      for (std::size_t q = 0; q < g; ++q) *f++ = 2 * gs[q] - 1;
      for (const double c : gammaCode) *f++ = c;
      if (s.discrepancyGradient) {
        const bool usable = gradientScale > 0 && std::isfinite(gradientScale);
        *f++ = usable ? gradient[i].x / gradientScale : 0.0;
        *f++ = usable ? gradient[i].y / gradientScale : 0.0;
        *f++ = usable
                   ? std::clamp(std::log(gradientScale * double(n) * double(n)), -20.0, 20.0) / 10
                   : -2.0;
      }
    }
    writeEdges(pe + 2 * set * n * k, u, x, nb, k, sphere);
  }
  const auto dtype = graph->embed->weight.scalar_type();
  return {nodes.to(dtype), edges.to(dtype)};
}

}  // namespace nuld
