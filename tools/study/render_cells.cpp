#include "tools/study/render_cells.h"

#include <algorithm>

#include "backends/stopwatch.h"
#include "renderer/flip.h"
#include "renderer/image_metrics.h"
#include "sampler/io/atomic_file.h"
#include "sampler/io/image_io.h"
#include "sampler/io/round_trip.h"
#include "tools/study/baselines.h"
#include "tools/study/equal_time.h"
#include "tools/study/statistics.h"

namespace nuld::study {

void writeSpectrum(const fs::path &file, const std::vector<double> &power) {
  std::string text = "radius,cycles_per_pixel,power\n";
  const double side = 2.0 * double(power.size() - 1);
  for (std::size_t r = 0; r < power.size(); ++r)
    text += std::to_string(r) + "," + formatNumber(double(r) / side) + "," +
            formatNumber(power[r]) + "\n";
  writeFileAtomically(file, text);
}

const std::vector<std::string> &repeatColumns() {
  static const std::vector<std::string> columns{"backend",
                                                "spp",
                                                "repeat",
                                                "seed",
                                                "mse",
                                                "relmse",
                                                "screen_mse",
                                                "mse_winsorized",
                                                "top_share",
                                                "seconds",
                                                "made_seconds",
                                                "setup_seconds",
                                                "rays_per_second",
                                                "nonfinite_pixels",
                                                "rejected_samples",
                                                "flip"};
  return columns;
}

const std::vector<std::string> &repeatDerivedColumns() {
  // Missing from a file written before FLIP; read as NaN.
  static const std::vector<std::string> columns{"flip"};
  return columns;
}

// The records of one cell (backend, spp) in repeat order.
std::vector<RepeatRecord> cellRecords(const CsvTable &repeats, const std::string &backend,
                                      std::size_t spp) {
  const auto col = [&](const char *name) { return repeats.column(name); };
  std::vector<std::pair<std::size_t, RepeatRecord>> found;
  for (const auto &row : repeats.rows()) {
    if (row[col("backend")] != backend || row[col("spp")] != std::to_string(spp)) continue;
    const auto num = [&](const char *name) { return parseNumber(row[col(name)]); };
    RepeatRecord r;
    r.mse = num("mse"), r.relmse = num("relmse"), r.screen = num("screen_mse");
    r.winsorized = num("mse_winsorized"), r.topShare = num("top_share");
    r.seconds = num("seconds"), r.madeSeconds = num("made_seconds");
    r.setupSeconds = num("setup_seconds"), r.raysPerSecond = num("rays_per_second");
    r.nonFinite = std::uint64_t(num("nonfinite_pixels"));
    r.rejected = std::uint64_t(num("rejected_samples"));
    r.flip = num("flip");
    found.emplace_back(std::size_t(num("repeat")), r);
  }
  std::sort(found.begin(), found.end(),
            [](const auto &a, const auto &b) { return a.first < b.first; });
  std::vector<RepeatRecord> out;
  for (const auto &[repeat, r] : found) out.push_back(r);
  return out;
}

CellOutcome renderRepeat(const Cell &c, const RenderStudySettings &s, std::size_t r,
                         bool withSpectrum,
                         const std::function<void(std::size_t d, std::size_t n)> &progress) {
  CellOutcome out;
  const auto start = Clock::now();
  const auto b = makeBackend(c.spec, s.seed + r);
  RenderStats stats;
  Image img;
  try {
    img = render(c.scene, c.settings, *b, &stats, progress);
  } catch (const BackendRefusal &e) {
    return CellOutcome::skipped(e.what());
  }
  RepeatRecord record;
  if (r == 0) record.setupSeconds = c.setupSeconds;  // the cell's, once
  record.seconds = secondsSince(start);
  record.madeSeconds = stats.setsMadeSeconds;
  record.raysPerSecond = stats.raysPerSecond();
  const ImageError e = compareImages(img, c.reference);
  record.mse = e.mse;
  record.relmse = e.relmse;
  record.screen = e.screen;
  record.winsorized = e.winsorized;
  record.topShare = e.topShare;
  record.nonFinite = e.nonFinitePixels;
  record.rejected = stats.rejectedSamples;
  if (e.nonFinitePixels == 0) {
    FlipResult flip = hdrFlip(img, c.reference);
    record.flip = flip.mean;
    if (r == 0) out.flipMap = flipMapImage(flip);  // the one the report shows
  }
  out.records.push_back(record);
  if (withSpectrum) out.spectrum = errorPowerSpectrum(img, c.reference);
  if (r == 0) {
    out.attributes = renderAttributes(c.sceneSlug, c.scene, c.settings, b->name(), s.seed, stats);
    out.image = std::move(img);
    out.note = b->report().note;
  }
  return out;
}

// A cell's row from all of its repeats' records.
std::vector<std::string> composeRow(const std::string &sceneSlug, const std::string &backend,
                                    std::size_t spp, const std::vector<RepeatRecord> &records,
                                    const CellFiles &files, const fs::path &out) {
  std::vector<double> mse, relmse, screen, winsorized, topShare, whole, made, raysPerSecond, flip;
  std::uint64_t nonFinite = 0, rejected = 0;
  double setupSeconds = 0;
  for (const RepeatRecord &r : records) {
    setupSeconds += r.setupSeconds;
    mse.push_back(r.mse);
    relmse.push_back(r.relmse);
    screen.push_back(r.screen);
    winsorized.push_back(r.winsorized);
    topShare.push_back(r.topShare);
    whole.push_back(r.seconds);
    made.push_back(r.madeSeconds);
    raysPerSecond.push_back(r.raysPerSecond);
    flip.push_back(r.flip);
    nonFinite += r.nonFinite;
    rejected += r.rejected;
  }
  // Banks a backend made in its first repeat (neural) are setup, not render
  // time (splitRepeatSeconds).
  const RepeatSeconds split = splitRepeatSeconds(whole, made);
  const MeanAndError m = meanAndError(mse), rm = meanAndError(relmse),
                     rps = meanAndError(raysPerSecond);
  const MedianAndSpread t = medianAndSpread(split.render);
  std::vector<std::string> row = {sceneSlug,
                                  backend,
                                  std::to_string(spp),
                                  std::to_string(records.size()),
                                  formatNumber(m.mean),
                                  formatNumber(m.stderr_),
                                  formatNumber(rm.mean),
                                  formatNumber(rm.stderr_),
                                  formatNumber(t.median),
                                  formatNumber(setupSeconds + split.setup),
                                  "",  // total_seconds .. amortize: fillEqualTime
                                  "",
                                  "",
                                  "",
                                  formatNumber(rps.mean),
                                  std::to_string(nonFinite),
                                  std::to_string(rejected),
                                  fs::relative(files.image, out).string(),
                                  fs::relative(files.errorMap, out).string()};
  row.resize(renderStudyColumns().size());  // baselineColumns: fillBaselineColumns
  const auto at = [](const std::string &name) {
    const auto &c = renderStudyColumns();
    return std::size_t(std::find(c.begin(), c.end(), name) - c.begin());
  };
  const MeanAndError sm = meanAndError(screen), wm = meanAndError(winsorized),
                     share = meanAndError(topShare);
  row[at(screenColumns()[0])] = formatNumber(sm.mean);
  row[at(screenColumns()[1])] = formatNumber(sm.stderr_);
  row[at("mse_winsorized")] = formatNumber(wm.mean);
  row[at("mse_winsorized_stderr")] = formatNumber(wm.stderr_);
  row[at("top_share")] = formatNumber(share.mean);
  const MeanAndError fm = meanAndError(flip);
  row[at(flipColumns()[0])] = formatNumber(fm.mean);
  row[at(flipColumns()[1])] = formatNumber(fm.stderr_);
  row[at(timeSpreadColumns()[0])] = formatNumber(t.mad);
  row[at(timeSpreadColumns()[1])] = formatNumber(t.stderr_);
  row[at("label")] = rowLabel(backend);
  return row;
}

}  // namespace nuld::study
