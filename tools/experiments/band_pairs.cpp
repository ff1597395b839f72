// How many point-box pairs an optimizer run must evaluate at the least: the
// pairs in the soft box loss's band (|alpha d| <= cutoff, where sigma is
// neither 0 nor 1 to double precision), summed over the sphere preset's
// epochs. Independent of the library on purpose: it restates the loss's
// definition (d = the smallest signed distance to a multiple-corner box's
// sides) with its own random boxes, so it checks rather than repeats the
// kernel's culling. Build and run through optimizer_floor.sh.
//
//   band_pairs POINTS.txt [BOXES [EPOCHS [ALPHA_START ALPHA_END RAMP [EVERY]]]]
//
// POINTS.txt is a `nuld` text point file (one "x y" per line, '#' comments).
// BOXES (default 16384) boxes an epoch; 2048 of them are drawn every EVERY-th
// epoch (default 25) and their count scaled up.
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <random>
#include <sstream>
#include <string>
#include <vector>

int main(int argc, char **argv) {
  if (argc < 2) {
    std::fprintf(stderr,
                 "usage: band_pairs POINTS.txt [BOXES [EPOCHS [ALPHA_START ALPHA_END RAMP "
                 "[EVERY]]]]\n");
    return 2;
  }
  std::ifstream in(argv[1]);
  if (!in) {
    std::fprintf(stderr, "band_pairs: cannot read %s\n", argv[1]);
    return 1;
  }
  std::vector<double> xs, ys;
  for (std::string line; std::getline(in, line);) {
    if (line.empty() || line[0] == '#') continue;
    std::istringstream fields(line);
    double x, y;
    if (fields >> x >> y) {
      xs.push_back(x);
      ys.push_back(y);
    }
  }
  const auto arg = [&](int k, double fallback) { return argc > k ? std::atof(argv[k]) : fallback; };
  const double boxes = arg(2, 16384), epochs = arg(3, 5000);
  const double alphaStart = arg(4, 20), alphaEnd = arg(5, 6000), ramp = arg(6, 0.5);
  const int every = std::max(1, int(arg(7, 25)));
  const double cutoff = 36;
  const int drawn = 2048;
  if (xs.empty()) {
    std::fprintf(stderr, "band_pairs: no points in %s\n", argv[1]);
    return 1;
  }

  std::mt19937_64 rng(1);
  std::uniform_real_distribution<double> uniform(0, 1);
  double total = 0;
  std::printf("epoch,alpha,band_pairs_per_box\n");
  for (int epoch = 0; epoch < int(epochs); epoch += every) {
    // The optimizer's schedule: alpha rises linearly over the ramp, then stays.
    const double rampEpochs = ramp * epochs;
    const double t = std::min(1.0, double(epoch) / (rampEpochs - 1));
    const double alpha = alphaStart + (alphaEnd - alphaStart) * t;
    double band = 0;
    for (int m = 0; m < drawn; ++m) {
      // A corner of the square picks which two sides are finite.
      const double cx = uniform(rng), cy = uniform(rng);
      const unsigned corner = unsigned(rng() >> 62);
      const double sx = (corner & 1) ? 1 : -1, sy = (corner & 2) ? 1 : -1;
      for (std::size_t i = 0; i < xs.size(); ++i) {
        const double d = std::min(sx * (xs[i] - cx), sy * (ys[i] - cy));
        band += std::abs(alpha * d) <= cutoff;
      }
    }
    const double perBox = band / drawn;
    if (epoch % 250 == 0) std::printf("%d,%.1f,%.1f\n", epoch, alpha, perBox);
    total += perBox * boxes * std::min(every, int(epochs) - epoch);
  }
  std::printf("# points %zu, boxes %.0f, epochs %.0f: %.4g band pairs in all\n", xs.size(), boxes,
              epochs, total);
  std::printf("total_band_pairs,%.6g\n", total);
}
