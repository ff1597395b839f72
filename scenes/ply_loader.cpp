#include "scenes/ply_loader.h"

#include <algorithm>
#include <array>
#include <bit>
#include <charconv>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <limits>
#include <optional>
#include <stdexcept>
#include <string_view>
#include <vector>

#include "sampler/enum_names.h"
#include "sampler/io/input_file.h"
#include "sampler/io/round_trip.h"

namespace nuld {
namespace {

[[noreturn]] void fail(const std::string &path, const std::string &what) {
  throw std::runtime_error(path + ": " + what);
}

// --- Header ------------------------------------------------------------------

enum class Scalar { kInt8, kUInt8, kInt16, kUInt16, kInt32, kUInt32, kFloat32, kFloat64 };

// Both the original PLY names and the sized ones that newer writers use.
constexpr EnumEntry<Scalar> kScalarEntries[] = {
    {"char", Scalar::kInt8},      {"int8", Scalar::kInt8},       {"uchar", Scalar::kUInt8},
    {"uint8", Scalar::kUInt8},    {"short", Scalar::kInt16},     {"int16", Scalar::kInt16},
    {"ushort", Scalar::kUInt16},  {"uint16", Scalar::kUInt16},   {"int", Scalar::kInt32},
    {"int32", Scalar::kInt32},    {"uint", Scalar::kUInt32},     {"uint32", Scalar::kUInt32},
    {"float", Scalar::kFloat32},  {"float32", Scalar::kFloat32}, {"double", Scalar::kFloat64},
    {"float64", Scalar::kFloat64}};
constexpr auto kScalarNames = enumTable("type", kScalarEntries);

bool isInteger(Scalar t) { return t != Scalar::kFloat32 && t != Scalar::kFloat64; }

struct Property {
  std::string name;
  Scalar type = Scalar::kFloat32;   // the item type, for a list
  std::optional<Scalar> countType;  // set for a list property
};

struct Element {
  std::string name;
  std::size_t count = 0;
  std::vector<Property> properties;
};

enum class Format { kAscii, kBinaryLittleEndian, kBinaryBigEndian };
constexpr auto kFormatNames =
    enumTable<Format>("format", {{"ascii", Format::kAscii},
                                 {"binary_little_endian", Format::kBinaryLittleEndian},
                                 {"binary_big_endian", Format::kBinaryBigEndian}});

struct Header {
  Format format = Format::kAscii;
  std::vector<Element> elements;
  std::size_t dataStart = 0;  // byte offset of the first element's data
};

std::vector<std::string_view> splitWords(std::string_view line) {
  std::vector<std::string_view> words;
  std::size_t pos = 0;
  while (true) {
    pos = line.find_first_not_of(" \t", pos);
    if (pos == std::string_view::npos) break;
    const std::size_t end = std::min(line.find_first_of(" \t", pos), line.size());
    words.push_back(line.substr(pos, end - pos));
    pos = end;
  }
  return words;
}

Header parseHeader(const std::string &path, std::string_view file) {
  Header header;
  bool sawFormat = false;
  std::size_t pos = 0;
  for (std::size_t lineNo = 1;; ++lineNo) {
    const std::size_t eol = file.find('\n', pos);
    if (eol == std::string_view::npos)
      fail(path, lineNo == 1 ? "not a PLY file: expected 'ply' on the first line"
                             : "truncated PLY header: expected an 'end_header' line");
    std::string_view line = file.substr(pos, eol - pos);
    pos = eol + 1;
    if (line.ends_with('\r')) line.remove_suffix(1);  // files written on Windows
    if (lineNo == 1) {
      if (line != "ply") fail(path, "not a PLY file: expected 'ply' on the first line");
      continue;
    }
    const std::vector<std::string_view> words = splitWords(line);
    const auto bad = [&](const std::string &expected) {
      fail(path, "bad PLY header, line " + std::to_string(lineNo) + " '" + std::string(line) +
                     "': expected " + expected);
    };
    if (words.empty() || words[0] == "comment" || words[0] == "obj_info") continue;
    if (words[0] == "end_header") {
      if (words.size() != 1) bad("'end_header' alone");
      break;
    }
    if (words[0] == "format") {
      if (words.size() != 3 || words[2] != "1.0")
        bad("'format ascii|binary_little_endian|binary_big_endian 1.0'");
      const auto format = kFormatNames.find(words[1]);
      if (!format) bad("format " + kFormatNames.expected());
      header.format = *format;
      sawFormat = true;
    } else if (words[0] == "element") {
      Element e;
      if (words.size() == 3) {
        e.name = words[1];
        const std::string_view n = words[2];
        const auto [end, ec] = std::from_chars(n.data(), n.data() + n.size(), e.count);
        if (ec == std::errc() && end == n.data() + n.size()) {
          header.elements.push_back(std::move(e));
          continue;
        }
      }
      bad("'element NAME COUNT' with a non-negative integer COUNT");
    } else if (words[0] == "property") {
      if (header.elements.empty()) bad("an 'element' line before the first 'property'");
      Property p;
      if (words.size() == 5 && words[1] == "list") {
        const auto countType = kScalarNames.find(words[2]);
        const auto itemType = kScalarNames.find(words[3]);
        if (!countType || !isInteger(*countType) || !itemType)
          bad("'property list COUNT_TYPE ITEM_TYPE NAME' with an integer COUNT_TYPE");
        p = {std::string(words[4]), *itemType, countType};
      } else if (words.size() == 3 && words[1] != "list") {
        const auto type = kScalarNames.find(words[1]);
        if (!type) bad("a type " + kScalarNames.expected());
        p = {std::string(words[2]), *type, std::nullopt};
      } else {
        bad("'property TYPE NAME' or 'property list COUNT_TYPE ITEM_TYPE NAME'");
      }
      header.elements.back().properties.push_back(std::move(p));
    } else {
      bad("'format', 'element', 'property', 'comment' or 'end_header'");
    }
  }
  if (!sawFormat) fail(path, "bad PLY header: no 'format' line");
  header.dataStart = pos;
  return header;
}

// --- Element data --------------------------------------------------------------

std::string quoted(std::string_view s) {
  std::string q = "'";
  q.append(s).push_back('\'');
  return q;
}

// Whitespace-separated numbers. Element instances are conventionally one per
// line, but nothing depends on it: the data is read as one stream of tokens.
class AsciiSource {
 public:
  explicit AsciiSource(std::string_view data) : data_(data) {}

  // The next value, or nullopt at the end of the data or on a bad token;
  // error() then says which.
  std::optional<double> next(Scalar type) {
    constexpr std::string_view kSpace = " \t\r\n\v\f";
    const std::size_t begin = data_.find_first_not_of(kSpace, pos_);
    if (begin == std::string_view::npos) {
      error_ = "truncated data (unexpected end of file)";
      return std::nullopt;
    }
    pos_ = std::min(data_.find_first_of(kSpace, begin), data_.size());
    const std::string_view token = data_.substr(begin, pos_ - begin);
    // from_chars takes no leading '+', which some writers emit.
    const std::string_view digits = token.starts_with('+') ? token.substr(1) : token;
    double value = 0;
    const auto [end, ec] = std::from_chars(digits.data(), digits.data() + digits.size(), value);
    if (ec != std::errc() || end != digits.data() + digits.size()) {
      error_ = quoted(token) + " is not a number";
      return std::nullopt;
    }
    if (isInteger(type) && value != std::floor(value)) {
      error_ = quoted(token) + " is not an integer";
      return std::nullopt;
    }
    return value;
  }
  const std::string &error() const { return error_; }

 private:
  std::string_view data_;
  std::size_t pos_ = 0;
  std::string error_;
};

// Packed binary values in the file's byte order.
class BinarySource {
 public:
  BinarySource(std::string_view data, bool littleEndian)
      : data_(data), swap_(littleEndian != (std::endian::native == std::endian::little)) {}

  std::optional<double> next(Scalar type) {
    switch (type) {
      case Scalar::kInt8: return read<std::int8_t>();
      case Scalar::kUInt8: return read<std::uint8_t>();
      case Scalar::kInt16: return read<std::int16_t>();
      case Scalar::kUInt16: return read<std::uint16_t>();
      case Scalar::kInt32: return read<std::int32_t>();
      case Scalar::kUInt32: return read<std::uint32_t>();
      case Scalar::kFloat32: return read<float>();
      case Scalar::kFloat64: return read<double>();
    }
    return std::nullopt;
  }
  std::string error() const { return "truncated data (unexpected end of file)"; }

 private:
  template <typename T>
  std::optional<double> read() {
    if (data_.size() - pos_ < sizeof(T)) return std::nullopt;
    char bytes[sizeof(T)];
    for (std::size_t i = 0; i < sizeof(T); ++i)
      bytes[i] = data_[pos_ + (swap_ ? sizeof(T) - 1 - i : i)];
    pos_ += sizeof(T);
    T v;
    std::memcpy(&v, bytes, sizeof(T));
    return static_cast<double>(v);
  }

  std::string_view data_;
  std::size_t pos_ = 0;
  bool swap_;
};

// What the loader takes from each property of an element.
enum Role { kX, kY, kZ, kNx, kNy, kNz, kIndices, kSkip };

std::vector<Role> rolesOf(const std::string &path, const Element &e) {
  std::vector<Role> roles(e.properties.size(), kSkip);
  const auto find = [&](std::string_view name) {
    const auto it = std::find_if(e.properties.begin(), e.properties.end(),
                                 [&](const Property &p) { return p.name == name; });
    return it == e.properties.end() ? -1 : static_cast<int>(it - e.properties.begin());
  };
  if (e.name == "vertex") {
    const std::array<int, 6> k = {find("x"),  find("y"),  find("z"),
                                  find("nx"), find("ny"), find("nz")};
    for (int r = 0; r < 6; ++r) {
      if (k[r] < 0) continue;
      if (e.properties[k[r]].countType)
        fail(path,
             "vertex property '" + e.properties[k[r]].name + "' is a list; expected a number");
      roles[k[r]] = static_cast<Role>(r);
    }
    if (k[0] < 0 || k[1] < 0 || k[2] < 0) fail(path, "element 'vertex' lacks property x, y or z");
    const int normals = (k[3] >= 0) + (k[4] >= 0) + (k[5] >= 0);
    if (normals != 0 && normals != 3)
      fail(path, "element 'vertex' has only some of nx, ny, nz; expected all three or none");
  } else if (e.name == "face") {
    int k = find("vertex_indices");
    if (k < 0) k = find("vertex_index");
    if (k < 0) fail(path, "element 'face' lacks a 'vertex_indices' (or 'vertex_index') list");
    const Property &p = e.properties[k];
    if (!p.countType || !isInteger(p.type))
      fail(path, "face property '" + p.name + "' must be a list of integers");
    roles[k] = kIndices;
  }
  return roles;
}

// What the loader takes from each property of each element, checked against
// the header before any data is read.
std::vector<std::vector<Role>> planElements(const std::string &path, const Header &header) {
  std::vector<std::vector<Role>> plan;
  int vertexElements = 0, faceElements = 0;
  for (const Element &e : header.elements) {
    plan.push_back(rolesOf(path, e));
    vertexElements += e.name == "vertex";
    faceElements += e.name == "face";
  }
  if (vertexElements > 1 || faceElements > 1)
    fail(path, "element 'vertex' or 'face' appears twice in the header");
  if (vertexElements == 0) fail(path, "no 'vertex' element; expected a triangle mesh");
  if (faceElements == 0)
    fail(path, "no 'face' element; expected a triangle mesh, not a point cloud");
  return plan;
}

template <typename Source>
void readElements(const std::string &path, const Header &header, Source &source,
                  TriangleMesh &mesh) {
  const std::vector<std::vector<Role>> plan = planElements(path, header);
  std::vector<std::uint32_t> polygon;
  for (std::size_t elementIndex = 0; elementIndex < header.elements.size(); ++elementIndex) {
    const Element &e = header.elements[elementIndex];
    const std::vector<Role> &roles = plan[elementIndex];
    const bool isVertex = e.name == "vertex", isFace = e.name == "face";
    // Cap the reservation: a corrupt count must not allocate before the data runs out.
    const std::size_t plausible = std::min<std::size_t>(e.count, 1 << 24);
    if (isVertex) mesh.positions.reserve(plausible);
    if (isFace) mesh.triangles.reserve(plausible);
    const bool hasNormals = std::find(roles.begin(), roles.end(), kNx) != roles.end();
    if (hasNormals) mesh.normals.reserve(plausible);

    for (std::size_t i = 0; i < e.count; ++i) {
      const auto where = [&] {
        return "element '" + e.name + "' item " + std::to_string(i + 1) + " of " +
               std::to_string(e.count) + ": ";
      };
      const auto next = [&](Scalar type) {
        if (const auto v = source.next(type)) return *v;
        fail(path, where() + source.error());
      };
      std::array<double, 6> v{};  // x, y, z, nx, ny, nz
      for (std::size_t k = 0; k < e.properties.size(); ++k) {
        const Property &p = e.properties[k];
        if (!p.countType) {
          const double value = next(p.type);
          if (roles[k] < kIndices) v[roles[k]] = value;
          continue;
        }
        const double n = next(*p.countType);
        if (n < 0) fail(path, where() + "negative list length");
        if (roles[k] != kIndices) {
          for (double j = 0; j < n; ++j) next(p.type);
          continue;
        }
        polygon.clear();
        for (double j = 0; j < n; ++j) {
          const double index = next(p.type);
          if (index < 0 || index > std::numeric_limits<std::uint32_t>::max())
            fail(path, where() + "vertex index " + formatRoundTrip(index) + " is out of range");
          polygon.push_back(static_cast<std::uint32_t>(index));
        }
        if (polygon.size() < 3)
          fail(path, where() + "face has " + std::to_string(polygon.size()) +
                         " vertices; expected at least 3");
        // Fan triangulation: exact for the convex polygons PLY writers emit.
        for (std::size_t j = 1; j + 1 < polygon.size(); ++j)
          mesh.triangles.push_back({polygon[0], polygon[j], polygon[j + 1]});
      }
      if (!isVertex) continue;
      const Vec3 position{v[0], v[1], v[2]};
      if (!isFinite(position)) fail(path, where() + "position is not finite");
      mesh.positions.push_back(position);
      if (!hasNormals) continue;
      const Vec3 normal{v[3], v[4], v[5]};
      const double len = length(normal);
      if (!(len > 0) || !std::isfinite(len))
        fail(path, where() + "normal is zero or not finite; expected a nonzero direction");
      mesh.normals.push_back(normal / len);
    }
  }
}

std::string readFile(const std::string &path) {
  requireInputFile(path, "PLY file");
  std::ifstream in(path, std::ios::binary);
  if (!in) fail(path, "cannot open PLY file");
  in.seekg(0, std::ios::end);
  const std::streamoff size = in.tellg();
  if (size < 0) fail(path, "cannot read PLY file");
  std::string bytes(static_cast<std::size_t>(size), '\0');
  in.seekg(0);
  in.read(bytes.data(), size);
  if (!in) fail(path, "cannot read PLY file");
  return bytes;
}

}  // namespace

TriangleMesh loadPly(const std::string &path) {
  const std::string file = readFile(path);
  const Header header = parseHeader(path, file);
  const std::string_view data = std::string_view(file).substr(header.dataStart);

  TriangleMesh mesh;
  mesh.name = std::filesystem::path(path).stem().string();
  if (header.format == Format::kAscii) {
    AsciiSource source(data);
    readElements(path, header, source, mesh);
  } else {
    BinarySource source(data, header.format == Format::kBinaryLittleEndian);
    readElements(path, header, source, mesh);
  }
  const std::size_t vertexCount = mesh.positions.size();
  for (const auto &t : mesh.triangles)
    for (const std::uint32_t index : t)
      if (index >= vertexCount)
        fail(path, "face vertex index " + std::to_string(index) +
                       " is out of range; the file has " + std::to_string(vertexCount) +
                       " vertices");
  return mesh;
}

}  // namespace nuld
