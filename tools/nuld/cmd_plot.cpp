#include <algorithm>
#include <cmath>
#include <fstream>
#include <iostream>

#include "sampler/io/atomic_file.h"
#include "sampler/io/image_io.h"
#include "sampler/io/pointset_io.h"
#include "sampler/metrics/spectrum.h"
#include "tools/nuld/cli_util.h"
#include "tools/nuld/commands.h"

namespace nuld::cli {

Runner addPlot(CLI::App &app) {
  struct Options {
    std::string file, target, output;
    int size = 512;
    std::size_t instance = 0;
    double radius = 0;
  };
  auto o = std::make_shared<Options>();
  app.add_option("file", o->file, "point-set file")->required();
  app.add_option("-o,--output", o->output, "PNG to write")->required();
  app.add_option("--target", o->target,
                 targetOptionHelp("draw this target's density underneath (default: the file's)"))
      ->check(targetFamily());
  app.add_option("--size", o->size, "image size in pixels")
      ->check(wholeNumberIn(16, 8192))
      ->capture_default_str();
  app.add_option("--instance", o->instance, "which set of the file")
      ->capture_default_str()
      ->check(wholeNumber());
  app.add_option("--radius", o->radius, "dot radius in pixels (default from N)")
      ->check(numberIn(0.01, 1000));
  return [o] {
    const PointSet set = readPointSet(o->file);
    if (o->instance >= set.instances())
      throw std::invalid_argument(o->file + ": has " + std::to_string(set.instances()) +
                                  " sets; --instance " + std::to_string(o->instance) +
                                  " is out of range");
    const auto target = targetFor(o->target, set, o->file);
    const int S = o->size;
    // Lat-long convention on the sphere: zenith (v = 0) at the top; the square upright (y up).
    const bool vDown = target->domain() != Domain::Square;
    auto toV = [&](double rowCenter) { return vDown ? rowCenter : 1 - rowCenter; };
    Image img{S, S, 3, std::vector<float>(std::size_t(S) * S * 3, 1.0f)};
    // Background: the density in light blue, on a log scale below its maximum.
    if (!target->isUniform()) {
      std::vector<double> d(std::size_t(S) * S);
      for (int y = 0; y < S; ++y)
        for (int x = 0; x < S; ++x)
          d[std::size_t(y) * S + x] = target->pdf({(x + 0.5) / S, toV((y + 0.5) / S)});
      // A log scale over the top four decades below the peak: an HDR map's
      // sun is 1e4-1e6 times its sky, and a linear (or log1p) scale draws
      // everything but the sun white. Zero density stays white.
      const double peak = std::max(*std::max_element(d.begin(), d.end()), 1e-300);
      constexpr double kDecades = 4;
      for (std::size_t i = 0; i < d.size(); ++i) {
        const float t =
            d[i] > 0 ? float(std::clamp(1 + std::log10(d[i] / peak) / kDecades, 0.0, 1.0)) : 0.0f;
        img.pixels[3 * i + 0] = 1 - 0.75f * t;
        img.pixels[3 * i + 1] = 1 - 0.5f * t;
        img.pixels[3 * i + 2] = 1.0f;
      }
    }
    const double r =
        o->radius > 0 ? o->radius : std::clamp(0.35 * S / std::sqrt(double(set.n)), 1.0, 6.0);
    for (const Point2 &p : set.instance(o->instance)) {
      const double cx = p.x * S, cy = (vDown ? p.y : 1 - p.y) * S;
      for (int y = int(cy - r - 1); y <= int(cy + r + 1); ++y)
        for (int x = int(cx - r - 1); x <= int(cx + r + 1); ++x) {
          if (x < 0 || y < 0 || x >= S || y >= S) continue;
          const double dist = std::hypot(x + 0.5 - cx, y + 0.5 - cy);
          const float cover = float(std::clamp(r + 0.5 - dist, 0.0, 1.0));  // anti-aliased edge
          for (int c = 0; c < 3; ++c) img.at(x, y, c) *= 1 - cover;
        }
    }
    writeImage(o->output, img);
    std::cerr << "wrote " << o->output << "\n";
    return 0;
  };
}

Runner addSpectrum(CLI::App &app) {
  struct Options {
    std::string file, output, csv;
    int half = 64;
  };
  auto o = std::make_shared<Options>();
  app.add_option("file", o->file, "point-set file (all instances are averaged)")->required();
  app.add_option("-o,--output", o->output, "spectrum image (PNG or EXR)")->required();
  app.add_option("--csv", o->csv, "radial average as CSV (columns: frequency,power)");
  app.add_option("--half-size", o->half, "frequencies -K..K per axis")
      ->check(wholeNumberIn(1, 1024))
      ->capture_default_str();
  return [o] {
    // Both outputs checked before either is written.
    checkDestination(o->output);
    if (!o->csv.empty()) checkDestination(o->csv);
    const PointSet set = readPointSet(o->file);
    const PowerSpectrum ps = averagePowerSpectrum(set, o->half);
    const int S = 2 * o->half + 1;
    Image img{S, S, 1, std::vector<float>(std::size_t(S) * S)};
    for (int j = 0; j < S; ++j)
      for (int i = 0; i < S; ++i) {
        const bool dc = i == o->half && j == o->half;
        // Tone map: power 1 (white noise) maps to mid grey; DC is not shown.
        const double v = dc ? 0.0 : ps.power[std::size_t(j) * S + i];
        img.at(i, S - 1 - j, 0) = float(std::clamp(0.5 * v, 0.0, 1.0));
      }
    writeImage(o->output, img);
    if (!o->csv.empty()) {
      std::string text = "frequency,power\n";
      for (std::size_t r = 0; r < ps.radial.size(); ++r)
        text += std::to_string(r) + "," + std::to_string(ps.radial[r]) + "\n";
      writeFileAtomically(o->csv, text);
    }
    std::cerr << "wrote " << o->output << (o->csv.empty() ? "" : " and " + o->csv) << "\n";
    return 0;
  };
}

}  // namespace nuld::cli
