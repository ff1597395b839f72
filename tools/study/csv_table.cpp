#include "tools/study/csv_table.h"

#include <cmath>
#include <cstdio>
#include <fstream>
#include <sstream>
#include <stdexcept>

#include "sampler/io/atomic_file.h"

namespace nuld::study {

namespace {

// Values never contain commas or quotes (names are ours, paths are quoted by
// the caller's choice of names), so a row is a plain comma join.
std::vector<std::string> splitRow(const std::string &line) {
  std::vector<std::string> out;
  std::stringstream in(line);
  std::string cell;
  while (std::getline(in, cell, ',')) out.push_back(cell);
  if (!line.empty() && line.back() == ',') out.emplace_back();
  return out;
}

std::string joinRow(const std::vector<std::string> &cells) {
  std::string out;
  for (std::size_t i = 0; i < cells.size(); ++i) out += (i ? "," : "") + cells[i];
  return out;
}

}  // namespace

CsvTable::CsvTable(std::filesystem::path path, std::vector<std::string> columns)
    : path_(std::move(path)), columns_(std::move(columns)) {}

void CsvTable::loadExisting() {
  std::ifstream in(path_);
  if (!in) return;
  std::string line;
  if (!std::getline(in, line)) return;
  if (splitRow(line) != columns_)
    throw std::runtime_error(path_.string() + ": header '" + line + "' differs from '" +
                             joinRow(columns_) +
                             "' (a study of another kind or version; use a new directory)");
  int lineNo = 1;
  while (std::getline(in, line)) {
    ++lineNo;
    if (line.empty()) continue;
    auto row = splitRow(line);
    if (row.size() != columns_.size())
      throw std::runtime_error(path_.string() + ":" + std::to_string(lineNo) + ": " +
                               std::to_string(row.size()) + " values, expected " +
                               std::to_string(columns_.size()));
    rows_.push_back(std::move(row));
  }
}

std::size_t CsvTable::column(const std::string &name) const {
  for (std::size_t i = 0; i < columns_.size(); ++i)
    if (columns_[i] == name) return i;
  throw std::logic_error(path_.string() + ": no column '" + name + "'");
}

bool CsvTable::hasRow(const std::vector<std::string> &key) const {
  for (const auto &row : rows_) {
    bool same = key.size() <= row.size();
    for (std::size_t i = 0; same && i < key.size(); ++i) same = row[i] == key[i];
    if (same) return true;
  }
  return false;
}

void CsvTable::addRow(std::vector<std::string> values) {
  if (values.size() != columns_.size())
    throw std::logic_error("CsvTable::addRow: " + std::to_string(values.size()) + " values for " +
                           std::to_string(columns_.size()) + " columns");
  for (const auto &v : values)
    if (v.find_first_of(",\n\"") != std::string::npos)
      throw std::invalid_argument("CSV value '" + v + "' contains a comma, quote or newline");
  rows_.push_back(std::move(values));
  write();
}

void CsvTable::write() const {
  std::string text = joinRow(columns_) + "\n";
  for (const auto &row : rows_) text += joinRow(row) + "\n";
  if (path_.has_parent_path()) std::filesystem::create_directories(path_.parent_path());
  writeFileAtomically(path_, text);
}

std::string formatNumber(double v) {
  if (std::isnan(v)) return "nan";
  if (std::isinf(v)) return v > 0 ? "inf" : "-inf";
  char buf[32];
  std::snprintf(buf, sizeof buf, "%.6g", v);
  return buf;
}

}  // namespace nuld::study
