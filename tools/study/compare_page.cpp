#include "tools/study/compare_page.h"

#include <algorithm>
#include <cmath>
#include <fstream>
#include <map>
#include <nlohmann/json.hpp>
#include <stdexcept>
#include <string>
#include <vector>

#include "backends/ready_backend.h"
#include "sampler/io/atomic_file.h"
#include "sampler/io/image_io.h"
#include "tools/study/baselines.h"
#include "tools/study/csv_table.h"
#include "tools/study/render_cells.h"
#include "tools/study/render_study.h"

namespace nuld::study {

namespace fs = std::filesystem;

namespace {

std::string base64(std::string_view bytes) {
  static constexpr char digits[] =
      "ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";
  std::string out;
  out.reserve((bytes.size() + 2) / 3 * 4);
  for (std::size_t i = 0; i < bytes.size(); i += 3) {
    const std::size_t n = std::min<std::size_t>(3, bytes.size() - i);
    std::uint32_t v = 0;
    for (std::size_t k = 0; k < 3; ++k) v = v << 8 | (k < n ? std::uint8_t(bytes[i + k]) : 0u);
    for (std::size_t k = 0; k < 4; ++k) out += k <= n ? digits[(v >> (18 - 6 * k)) & 63] : '=';
  }
  return out;
}

std::string fileBytes(const fs::path &file) {
  std::ifstream in(file, std::ios::binary);
  std::string bytes{std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
  if (!in.good() && !in.eof()) throw std::runtime_error(file.string() + ": cannot read the file");
  return bytes;
}

}  // namespace

std::string encodeRgbe(const Image &img) {
  std::string out(4 * std::size_t(img.width) * std::size_t(img.height), '\0');
  for (std::size_t p = 0; p < std::size_t(img.width) * std::size_t(img.height); ++p) {
    float c[3];
    for (int k = 0; k < 3; ++k) {
      const float v =
          img.pixels[p * std::size_t(img.channels) + std::size_t(std::min(k, img.channels - 1))];
      c[k] = std::isnan(v) || v < 0 ? 0.0f : std::min(v, 1e38f);
    }
    const float m = std::max({c[0], c[1], c[2]});
    if (m < 1e-32f) continue;
    int e = 0;
    const float scale = std::frexp(m, &e) * 256.0f / m;
    for (int k = 0; k < 3; ++k)
      out[4 * p + std::size_t(k)] = char(std::min(255, int(c[k] * scale)));
    out[4 * p + 3] = char(e + 128);
  }
  return out;
}

namespace {

// Whether an image's data file is there and no older than its sources.
bool isFresh(const fs::path &file, std::initializer_list<fs::path> sources) {
  std::error_code ec;
  if (!fs::exists(file, ec)) return false;
  const auto made = fs::last_write_time(file, ec);
  if (ec) return false;
  for (const fs::path &source : sources)
    if (!source.empty() && fs::exists(source, ec) && fs::last_write_time(source, ec) > made)
      return false;
  return true;
}

// One image's data file: the render as RGBE, its maps (where they exist) as
// PNG data.
void writeImageData(const fs::path &file, const std::string &key, const Image &img,
                    const fs::path &errorMap, const fs::path &flipMap) {
  nlohmann::json data = {
      {"width", img.width}, {"height", img.height}, {"rgbe", base64(encodeRgbe(img))}};
  std::error_code ec;
  for (const auto &[name, map] : {std::pair{"error", errorMap}, std::pair{"flip", flipMap}})
    if (!map.empty() && fs::exists(map, ec))
      data[name] = "data:image/png;base64," + base64(fileBytes(map));
  if (fs::create_directories(file.parent_path(), ec); ec)
    throw std::runtime_error(file.parent_path().string() + ": cannot make the folder (" +
                             ec.message() + ")");
  writeFileAtomically(
      file, "nuldCompare.image(" + nlohmann::json(key).dump() + ", " + data.dump() + ");\n");
}

}  // namespace

fs::path writeComparisonPage(const fs::path &out, const fs::path &viewerDir) {
  CsvTable table(out / "render.csv", renderStudyColumns(), renderStudyDerivedColumns());
  table.loadExisting();
  if (table.rows().empty()) return {};
  CsvTable refs(out / "references.csv", referenceColumns(), referenceOptionalColumns());
  refs.loadExisting();
  const auto col = [&](const char *name) { return table.column(name); };
  const std::size_t scene = col("scene"), backend = col("backend"), spp = col("spp"),
                    mse = col("mse"), mseErr = col("mse_stderr"),
                    flip = table.column(flipColumns()[0]), flipErr = table.column(flipColumns()[1]);
  const auto number = [](const std::string &v) {
    const double x = parseNumber(v);
    return std::isfinite(x) ? nlohmann::json(x) : nlohmann::json(nullptr);
  };

  // Scenes in the table's order, spp ascending, rows in the table's order.
  std::vector<std::string> scenes;
  std::map<std::string, std::map<std::size_t, nlohmann::json>> rows;
  for (const auto &r : table.rows()) {
    if (std::find(scenes.begin(), scenes.end(), r[scene]) == scenes.end())
      scenes.push_back(r[scene]);
    const std::size_t n = std::size_t(parseNumber(r[spp]));
    const CellFiles files(out / r[scene], r[backend], n);  // the names the study wrote
    if (!fs::exists(files.image)) continue;  // a row whose image an older run did not keep
    const std::string key = "data/" + r[scene] + "/" + files.image.stem().string() + ".js";
    if (const fs::path file = out / "compare" / key;
        !isFresh(file, {files.image, files.errorMap, files.flipMap}))
      writeImageData(file, key, readImage(files.image.string(), false), files.errorMap,
                     files.flipMap);
    rows[r[scene]][n].push_back({{"label", rowLabel(r[backend])},
                                 {"data", key},
                                 {"mse", number(r[mse])},
                                 {"mseStderr", number(r[mseErr])},
                                 {"flip", number(r[flip])},
                                 {"flipStderr", number(r[flipErr])}});
  }

  nlohmann::json manifest = {{"title", "nuld study: " + out.filename().string()},
                             {"scenes", nlohmann::json::array()}};
  for (const std::string &s : scenes) {
    const fs::path reference = out / s / "reference.exr";
    if (!rows.contains(s) || !fs::exists(reference)) continue;
    const std::string key = "data/" + s + "/reference.js";
    const Image header = readImage(reference.string(), false);  // its size is the scene's
    if (const fs::path file = out / "compare" / key; !isFresh(file, {reference}))
      writeImageData(file, key, header, {}, {});
    std::string integrator = "-";
    for (const auto &r : refs.rows())
      if (r[refs.column("scene")] == s) integrator = r[refs.column("integrator")];
    nlohmann::json spps = nlohmann::json::array();
    for (const auto &[n, list] : rows[s]) spps.push_back({{"spp", n}, {"rows", list}});
    manifest["scenes"].push_back({{"scene", s},
                                  {"integrator", integrator},
                                  {"width", header.width},
                                  {"height", header.height},
                                  {"reference", key},
                                  {"spps", spps}});
  }
  if (manifest["scenes"].empty()) return {};
  writeFileAtomically(out / "compare" / "manifest.js",
                      "nuldCompare.load(" + manifest.dump(1) + ");\n");
  for (const char *file : {"viewer.js", "viewer.css"})
    copyFileAtomically(viewerDir / file, out / "compare" / file);
  copyFileAtomically(viewerDir / "compare.html", out / "compare.html");
  return out / "compare.html";
}

}  // namespace nuld::study
