#pragma once
// The render study's cells (render_study.cpp): one backend at one spp,
// rendered repeat by repeat against the reference; each repeat's
// measurements as SCENE/repeats.csv keeps them, and a row of render.csv made
// from all of them, so that later rounds and reruns add repeats to a row.

#include <filesystem>
#include <functional>
#include <string>
#include <vector>

#include "backends/ranks.h"
#include "renderer/render.h"
#include "renderer/sampler_backend.h"
#include "tools/study/csv_table.h"
#include "tools/study/render_study.h"

namespace nuld::study {

namespace fs = std::filesystem;

// Where a cell's first render and its error map go.
struct CellFiles {
  fs::path image, errorMap, flipMap, spectrum;
  CellFiles(const fs::path &dir, const std::string &backend, std::size_t spp) {
    // A labelled row's files are named for its label (rowLabel).
    const std::string stem = slug(rowLabel(backend)) + "_spp" + std::to_string(spp);
    image = dir / (stem + ".exr");
    errorMap = dir / (stem + "_error.png");
    flipMap = dir / (stem + "_flip.png");
    spectrum = dir / (stem + "_spectrum.csv");
  }
};

// The repeats' mean radially averaged power spectrum of the error
// (errorPowerSpectrum) as CSV: radius, frequency in cycles per pixel, power.
void writeSpectrum(const fs::path &file, const std::vector<double> &power);

// One cell of the table: the renders of one backend at one spp,
// scored against the reference.
struct Cell {
  const Scene &scene;
  RenderSettings settings;  // spp set
  std::string sceneSlug, backend;
  BackendSpec spec;
  double setupSeconds = 0;
  const Image &reference;
  fs::path dir;

  CellFiles files() const { return {dir, backend, settings.spp}; }
};

// One repeat's measurements, as SCENE/repeats.csv keeps them: a row is
// made from all of its repeats, and a later round or run adds to them.
struct RepeatRecord {
  double mse = 0, relmse = 0, screen = 0, winsorized = 0, topShare = 0;
  // Its wall time, the part of it spent making sets (setup, not render
  // time) and, on the cell's repeat 0, the cell's setup before any repeat
  // (its sets optimized, its lobe tables).
  double seconds = 0, madeSeconds = 0, setupSeconds = 0, raysPerSecond = 0;
  std::uint64_t nonFinite = 0, rejected = 0;
  // HDR-FLIP's mean against the reference (renderer/flip.h); NaN where the
  // image has non-finite pixels, or in a record from before FLIP.
  double flip = NAN;
};

// repeats.csv's columns: backend, spp, repeat, seed, then a record's fields.
const std::vector<std::string> &repeatColumns();
// Those a repeats.csv written before them lacks (read as empty).
const std::vector<std::string> &repeatDerivedColumns();

// The records of one cell (backend, spp) in repeat order.
std::vector<RepeatRecord> cellRecords(const CsvTable &repeats, const std::string &backend,
                                      std::size_t spp);

// What a repeat of a cell sends to rank 0: its record, or why it has none
// (the backend's refusal, or the scene's lack of what the backend needs),
// the error's spectrum when asked, and, from repeat 0, the render (written
// beside the reference with its error map) and its FLIP map.
struct CellOutcome {
  std::vector<RepeatRecord> records;  // empty when refused
  std::string refusal;
  std::string note;              // what the backend decided that a user should hear (its note())
  std::vector<double> spectrum;  // errorPowerSpectrum, when asked
  Image image;                   // repeat 0's
  Image flipMap;                 // repeat 0's FLIP map; empty where it has non-finite pixels
  ImageAttributes attributes;

  // A cell the scene cannot serve (no map, no Disney material): no row.
  static CellOutcome skipped(const std::string &why) {
    CellOutcome c;
    c.refusal = why;
    return c;
  }
  std::string bytes() const {
    ByteWriter w;
    w.put(std::uint64_t(records.size()));
    for (const RepeatRecord &r : records) w.put(r);
    return w.put(refusal).put(note).put(spectrum).put(image).put(flipMap).put(attributes).take();
  }
  static CellOutcome from(std::string_view bytes) {
    ByteReader r(bytes);
    CellOutcome c;
    c.records.resize(r.get<std::uint64_t>());
    for (RepeatRecord &record : c.records) r.get(record);
    r.get(c.refusal);
    r.get(c.note);
    r.get(c.spectrum);
    r.get(c.image);
    r.get(c.flipMap);
    r.get(c.attributes);
    return c;
  }
};

// Repeat r of the cell (seed s.seed + r), and the error's spectrum when
// asked; a refusal (BackendRefusal) is an outcome, any other error
// propagates. `progress(d, n)` follows the render.
CellOutcome renderRepeat(const Cell &c, const RenderStudySettings &s, std::size_t r,
                         bool withSpectrum,
                         const std::function<void(std::size_t d, std::size_t n)> &progress);

// A cell's row from all of its repeats' records.
std::vector<std::string> composeRow(const std::string &sceneSlug, const std::string &backend,
                                    std::size_t spp, const std::vector<RepeatRecord> &records,
                                    const CellFiles &files, const fs::path &out);

}  // namespace nuld::study
