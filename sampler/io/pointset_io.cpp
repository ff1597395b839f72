#include "sampler/io/pointset_io.h"

#include <bit>
#include <charconv>
#include <cmath>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <stdexcept>

#include "sampler/io/atomic_file.h"
#include "sampler/io/content_hash.h"
#include "sampler/io/input_file.h"
#include "sampler/io/pointset_metadata.h"
#include "sampler/io/round_trip.h"

namespace nuld {
namespace {

// Version 2 ends in a checksum of every byte before it; version 1 files
// (written before 2026-12) have none and are still read.
constexpr char kMagic[8] = {'N', 'U', 'L', 'D', 'P', 'T', 'S', '2'};
constexpr char kMagicV1[8] = {'N', 'U', 'L', 'D', 'P', 'T', 'S', '1'};
constexpr std::size_t kChecksumBytes = sizeof(std::uint64_t);

bool endsWith(const std::string &s, const std::string &suffix) {
  return s.size() >= suffix.size() &&
         s.compare(s.size() - suffix.size(), suffix.size(), suffix) == 0;
}

std::string trim(const std::string &s) {
  const auto b = s.find_first_not_of(" \t\r");
  if (b == std::string::npos) return "";
  const auto e = s.find_last_not_of(" \t\r");
  return s.substr(b, e - b + 1);
}

[[noreturn]] void fail(const std::string &path, std::size_t line, const std::string &what) {
  throw std::runtime_error(path + (line ? ":" + std::to_string(line) : std::string()) + ": " +
                           what);
}

void finishSets(PointSet &set, const std::vector<std::vector<Point2>> &sets,
                const std::string &path) {
  std::size_t n = 0;
  for (const auto &s : sets) {
    if (s.empty()) continue;
    if (n == 0) n = s.size();
    if (s.size() != n)
      fail(path, 0,
           "sets have different sizes (" + std::to_string(n) + " and " + std::to_string(s.size()) +
               " points); expected equal sizes");
    set.points.insert(set.points.end(), s.begin(), s.end());
  }
  if (n == 0) fail(path, 0, "no points found; expected lines of 2 numbers");
  set.n = n;
}

PointSet readText(const std::string &path, std::istream &in) {
  PointSet set;
  std::vector<std::vector<Point2>> sets(1);
  std::string line;
  std::size_t lineNo = 0;
  while (std::getline(in, line)) {
    ++lineNo;
    const std::string t = trim(line);
    if (t.empty()) continue;
    if (t[0] == '#') {
      const std::string body = trim(t.substr(1));
      if (body.empty() || body == "set" || body.rfind("set ", 0) == 0) {
        if (!sets.back().empty()) sets.emplace_back();
        continue;
      }
      const auto colon = body.find(':');
      if (colon != std::string::npos && colon > 0 && body.find(' ') > colon)
        set.metadata[body.substr(0, colon)] = trim(body.substr(colon + 1));
      continue;
    }
    double v[3];
    int count = 0;
    const char *p = t.data(), *end = t.data() + t.size();
    while (p < end) {
      while (p < end && (*p == ' ' || *p == '\t' || *p == ',')) ++p;
      if (p >= end) break;
      if (count == 3) break;
      const auto [next, ec] = std::from_chars(p, end, v[count]);
      if (ec != std::errc() || (next < end && *next != ' ' && *next != '\t' && *next != ','))
        fail(path, lineNo, quotedInput(t) + " is not a list of numbers");
      ++count;
      p = next;
    }
    if (count != 2)
      fail(path, lineNo,
           "expected 2 coordinates per point, found " +
               std::string(count == 3 ? "more than 2" : std::to_string(count)));
    if (const std::string why = pointProblem({v[0], v[1]}); !why.empty()) fail(path, lineNo, why);
    sets.back().push_back({v[0], v[1]});
  }
  finishSets(set, sets, path);
  // Written by writePointSetText as a header, derived from the data: a header
  // that disagrees with the data is refused, then dropped.
  for (const auto &[key, actual] :
       {std::pair{meta::kN, set.n}, {meta::kInstances, set.instances()}})
    if (const auto it = set.metadata.find(std::string(key)); it != set.metadata.end())
      if (it->second != std::to_string(actual))
        fail(path, 0,
             "the header says " + std::string(key) + ": " + it->second + " but the data hold " +
                 std::to_string(actual) + (key == meta::kN ? " points per set" : " sets") +
                 "; expected the header to match the data");
  for (const std::string_view key : {meta::kFormat, meta::kN, meta::kInstances})
    set.metadata.erase(std::string(key));
  return set;
}

template <typename T>
void readRaw(std::istream &in, T &value, const std::string &path, const char *field) {
  in.read(reinterpret_cast<char *>(&value), sizeof(T));
  if (!in) fail(path, 0, std::string("truncated binary file while reading ") + field);
}

PointSet readBinary(const std::string &path, std::istream &in, std::uintmax_t fileSize,
                    bool checksummed) {
  in.seekg(sizeof(kMagic));
  std::uint32_t dim = 0, metaBytes = 0;
  std::uint64_t n = 0, instances = 0;
  readRaw(in, dim, path, "dimension");
  readRaw(in, n, path, "point count");
  readRaw(in, instances, path, "instance count");
  readRaw(in, metaBytes, path, "metadata size");
  if (dim != 2) fail(path, 0, "dimension " + std::to_string(dim) + "; expected 2");
  if (n == 0 || instances == 0) fail(path, 0, "no points; expected N > 0 and instances > 0");
  const std::uintmax_t header = sizeof(kMagic) + 4 + 8 + 8 + 4;
  if (n > (std::uint64_t(1) << 40) / instances ||
      fileSize != header + metaBytes + n * instances * 2 * sizeof(double) +
                      (checksummed ? kChecksumBytes : 0))
    fail(path, 0,
         "file size does not match its header (N = " + std::to_string(n) +
             ", instances = " + std::to_string(instances) + ")");
  std::string meta(metaBytes, '\0');
  in.read(meta.data(), metaBytes);
  PointSet set;
  std::istringstream ms(meta);
  for (std::string line; std::getline(ms, line);) {
    const auto eq = line.find('=');
    if (eq != std::string::npos) set.metadata[line.substr(0, eq)] = line.substr(eq + 1);
  }
  set.n = n;
  set.points.resize(n * instances);
  in.read(reinterpret_cast<char *>(set.points.data()),
          std::streamsize(n * instances * sizeof(Point2)));
  if (!in) fail(path, 0, "truncated binary file while reading points");
  if (checksummed) {
    // The hash of the bytes just read, header included: a flipped bit, an
    // edited setting or a file cut and padded back is refused here.
    // FNV-1a runs byte by byte, so the parts hash as the whole file would.
    std::uint64_t recorded = 0;
    readRaw(in, recorded, path, "checksum");
    const auto bytesOf = [](const auto &value) {
      return std::string_view(reinterpret_cast<const char *>(&value), sizeof value);
    };
    const std::uint64_t actual =
        ContentHash()
            .add(std::string_view(kMagic, sizeof kMagic))
            .add(bytesOf(dim))
            .add(bytesOf(n))
            .add(bytesOf(instances))
            .add(bytesOf(metaBytes))
            .add(meta)
            .add(std::string_view(reinterpret_cast<const char *>(set.points.data()),
                                  set.points.size() * sizeof(Point2)))
            .value();
    if (actual != recorded)
      fail(path, 0, "checksum mismatch: the file was changed or damaged after it was written");
  }
  for (std::size_t i = 0; i < set.points.size(); ++i)
    if (const std::string why = pointProblem(set.points[i]); !why.empty())
      fail(path, 0, "point " + std::to_string(i) + ": " + why);
  return set;
}

}  // namespace

// Point sets live in the unit square (their domain's parameterization);
// a coordinate outside it (inUnitSquare) is a foreign or corrupted file.
std::string pointProblem(Point2 p) {
  if (!isFinite(p)) return "coordinate is not finite";
  if (inUnitSquare(p)) return "";
  return "point (" + formatRoundTrip(p.x) + ", " + formatRoundTrip(p.y) +
         ") lies outside the unit square; expected coordinates in [0, 1]";
}

PointSet readPointSet(const std::string &path) {
  requireInputFile(path, "point-set file");
  std::ifstream in(path, std::ios::binary);
  if (!in) fail(path, 0, "cannot open point-set file");
  char magic[sizeof(kMagic)] = {};
  in.read(magic, sizeof(magic));
  const bool whole = in.gcount() == sizeof(magic);
  const bool v2 = whole && std::memcmp(magic, kMagic, sizeof(kMagic)) == 0;
  const bool v1 = whole && std::memcmp(magic, kMagicV1, sizeof(kMagicV1)) == 0;
  in.clear();
  if (v1 || v2) {
    in.seekg(0, std::ios::end);
    const auto size = static_cast<std::uintmax_t>(in.tellg());
    return readBinary(path, in, size, v2);
  }
  in.seekg(0);
  return readText(path, in);
}

void writePointSetText(std::ostream &out, const PointSet &set) {
  out << "# " << meta::kFormat << ": 1\n";
  out << "# " << meta::kN << ": " << set.n << "\n# " << meta::kInstances << ": " << set.instances()
      << "\n";
  for (const auto &[k, v] : set.metadata) out << "# " << k << ": " << v << "\n";
  char buf[64];
  for (std::size_t k = 0; k < set.instances(); ++k) {
    out << "# set " << k << "\n";
    for (const Point2 &p : set.instance(k)) {
      char *end = formatRoundTrip(buf, buf + sizeof(buf), p.x);
      *end++ = ' ';
      end = formatRoundTrip(end, buf + sizeof(buf), p.y);
      *end++ = '\n';
      out.write(buf, end - buf);
    }
  }
}

void writePointSet(const std::string &path, const PointSet &set) {
  if (set.n == 0 || set.points.size() % set.n != 0)
    throw std::invalid_argument(path + ": refusing to write a malformed point set");
  std::ostringstream out;
  if (endsWith(path, ".ptsb")) {
    std::string meta;
    for (const auto &[k, v] : set.metadata) meta += k + "=" + v + "\n";
    const std::uint32_t dim = 2, metaBytes = std::uint32_t(meta.size());
    const std::uint64_t n = set.n, instances = set.instances();
    out.write(kMagic, sizeof(kMagic));
    out.write(reinterpret_cast<const char *>(&dim), 4);
    out.write(reinterpret_cast<const char *>(&n), 8);
    out.write(reinterpret_cast<const char *>(&instances), 8);
    out.write(reinterpret_cast<const char *>(&metaBytes), 4);
    out.write(meta.data(), std::streamsize(meta.size()));
    out.write(reinterpret_cast<const char *>(set.points.data()),
              std::streamsize(set.points.size() * sizeof(Point2)));
    const std::uint64_t checksum = ContentHash().add(out.view()).value();
    out.write(reinterpret_cast<const char *>(&checksum), kChecksumBytes);
  } else {
    writePointSetText(out, set);
  }
  writeFileAtomically(path, out.str());
}

void exportPointSet(const std::string &path, const PointSet &set) {
  const std::string ext = std::filesystem::path(path).extension().string();
  std::ostringstream out;
  if (ext == ".npy") {
    // NPY 1.0: magic, version, header length, a Python dict literal padded
    // with spaces to a multiple of 64 bytes and ending in a newline.
    std::string header = "{'descr': '<f8', 'fortran_order': False, 'shape': (" +
                         std::to_string(set.instances()) + ", " + std::to_string(set.n) + ", 2), }";
    const std::size_t unpadded = 10 + header.size() + 1;
    header += std::string((64 - unpadded % 64) % 64, ' ') + "\n";
    out << "\x93NUMPY" << char(1) << char(0) << char(header.size() & 0xff)
        << char(header.size() >> 8) << header;
    static_assert(std::endian::native == std::endian::little, "NPY data is written little-endian");
    out.write(reinterpret_cast<const char *>(set.points.data()),
              std::streamsize(set.points.size() * sizeof(Point2)));
  } else if (ext == ".csv") {
    out << "instance,x,y\n";
    for (std::size_t k = 0; k < set.instances(); ++k)
      for (const Point2 &p : set.instance(k))
        out << k << "," << formatRoundTrip(p.x) << "," << formatRoundTrip(p.y) << "\n";
  } else if (ext == ".dat") {
    // UTK's text format: one point per line, a line "#" between sets.
    for (std::size_t k = 0; k < set.instances(); ++k) {
      if (k > 0) out << "#\n";
      for (const Point2 &p : set.instance(k))
        out << formatRoundTrip(p.x) << " " << formatRoundTrip(p.y) << "\n";
    }
  } else {
    throw std::invalid_argument(path + ": cannot export to '" + ext +
                                "' (expected a name ending in .npy, .csv or .dat)");
  }
  writeFileAtomically(path, out.str());
}

}  // namespace nuld
