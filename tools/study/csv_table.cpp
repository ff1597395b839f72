#include "tools/study/csv_table.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <sstream>
#include <stdexcept>
#include <utility>

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

// "a=1 b=2" -> {{"a", "1"}, {"b", "2"}}, in order.
std::vector<std::pair<std::string, std::string>> optionWords(const std::string &text) {
  std::vector<std::pair<std::string, std::string>> out;
  std::istringstream in(text);
  for (std::string word; in >> word;) {
    const auto eq = word.find('=');
    out.emplace_back(word.substr(0, eq), eq == std::string::npos ? "" : word.substr(eq + 1));
  }
  return out;
}

// "--repeats 1 there, 4 now; --seed ..." for the options that differ.
std::string optionDifferences(const std::string &there, const std::string &now) {
  const auto old = optionWords(there), cur = optionWords(now);
  std::string out;
  const auto add = [&](const std::string &name, const std::string &a, const std::string &b) {
    out += (out.empty() ? "" : "; ") + std::string("--") + name + " " + a + " there, " + b + " now";
  };
  for (const auto &[name, value] : cur) {
    std::string before = "(not recorded)";
    for (const auto &[oldName, oldValue] : old)
      if (oldName == name) before = oldValue;
    if (before != value) add(name, before, value);
  }
  for (const auto &[name, value] : old) {
    bool kept = false;
    for (const auto &c : cur) kept = kept || c.first == name;
    if (!kept) add(name, value, "(not an option now)");
  }
  return out;
}

}  // namespace

CsvTable::CsvTable(std::filesystem::path path, std::vector<std::string> columns,
                   std::vector<std::string> derived)
    : path_(std::move(path)), columns_(std::move(columns)), derived_(std::move(derived)) {}

void CsvTable::loadExisting() {
  std::ifstream in(path_);
  if (!in) return;
  std::string line;
  if (!std::getline(in, line)) return;
  // The file's columns: ours, or ours without some derived ones (a file
  // older than they are), whose values are then left empty.
  const std::vector<std::string> header = splitRow(line);
  std::vector<std::size_t> from(columns_.size(), header.size());  // header index per column
  bool matches = true;
  std::size_t k = 0;
  for (std::size_t c = 0; c < columns_.size() && matches; ++c) {
    if (k < header.size() && header[k] == columns_[c])
      from[c] = k++;
    else
      matches = std::find(derived_.begin(), derived_.end(), columns_[c]) != derived_.end();
  }
  if (!matches || k != header.size())
    throw std::runtime_error(path_.string() + ": header '" + line + "' differs from '" +
                             joinRow(columns_) +
                             "' (a study of another kind or version; use a new directory)");
  int lineNo = 1;
  while (std::getline(in, line)) {
    ++lineNo;
    if (line.empty()) continue;
    auto row = splitRow(line);
    if (row.size() != header.size())
      throw std::runtime_error(path_.string() + ":" + std::to_string(lineNo) + ": " +
                               std::to_string(row.size()) + " values, expected " +
                               std::to_string(header.size()));
    std::vector<std::string> full(columns_.size());
    for (std::size_t c = 0; c < columns_.size(); ++c)
      if (from[c] < header.size()) full[c] = std::move(row[from[c]]);
    row = std::move(full);
    rows_.push_back(std::move(row));
  }
}

std::size_t CsvTable::column(const std::string &name) const {
  for (std::size_t i = 0; i < columns_.size(); ++i)
    if (columns_[i] == name) return i;
  throw std::logic_error(path_.string() + ": no column '" + name + "'");
}

void CsvTable::requireOptions(const std::string &options, bool write) {
  const std::filesystem::path file = path_.string() + ".options";
  if (!rows_.empty() && std::filesystem::exists(file)) {
    std::ifstream in(file);
    std::string recorded;
    if (!in || !std::getline(in, recorded))
      throw std::runtime_error(file.string() + ": cannot be read (expected one line of options)");
    if (const std::string diff = optionDifferences(recorded, options); !diff.empty())
      throw std::runtime_error(path_.string() + " holds rows made with other options (" + diff +
                               "; recorded in " + file.string() +
                               "): pass the same options to add rows to it, or use another "
                               "output directory");
    return;
  }
  if (!write) return;
  if (path_.has_parent_path()) std::filesystem::create_directories(path_.parent_path());
  writeFileAtomically(file, options + "\n");
}

const std::vector<std::string> *CsvTable::findRow(const std::vector<std::string> &key) const {
  for (const auto &row : rows_) {
    bool same = key.size() <= row.size();
    for (std::size_t i = 0; same && i < key.size(); ++i) same = row[i] == key[i];
    if (same) return &row;
  }
  return nullptr;
}

void CsvTable::checkRow(const std::vector<std::string> &values) const {
  if (values.size() != columns_.size())
    throw std::logic_error("CsvTable: " + std::to_string(values.size()) + " values for " +
                           std::to_string(columns_.size()) + " columns");
  for (const auto &v : values)
    if (v.find_first_of(",\n\"") != std::string::npos)
      throw std::invalid_argument("CSV value '" + v + "' contains a comma, quote or newline");
}

void CsvTable::addRow(std::vector<std::string> values) {
  checkRow(values);
  rows_.push_back(std::move(values));
  write();
}

void CsvTable::putRow(std::vector<std::string> values, std::size_t keySize) {
  const std::vector<std::string> key(values.begin(),
                                     values.begin() + std::min(keySize, values.size()));
  for (auto &row : rows_)
    if (std::equal(key.begin(), key.end(), row.begin())) {
      if (row == values) return;
      checkRow(values);
      row = std::move(values);
      write();
      return;
    }
  addRow(std::move(values));
}

void CsvTable::setColumn(const std::string &name, const std::vector<std::string> &values) {
  if (values.size() != rows_.size())
    throw std::logic_error("CsvTable::setColumn: " + std::to_string(values.size()) +
                           " values for " + std::to_string(rows_.size()) + " rows");
  const std::size_t c = column(name);
  for (std::size_t i = 0; i < rows_.size(); ++i) rows_[i][c] = values[i];
  write();
}

void CsvTable::write() const {
  std::string text = joinRow(columns_) + "\n";
  for (const auto &row : rows_) text += joinRow(row) + "\n";
  if (path_.has_parent_path()) std::filesystem::create_directories(path_.parent_path());
  writeFileAtomically(path_, text);
}

double parseNumber(const std::string &s) {
  try {
    return std::stod(s);
  } catch (...) {
    return NAN;
  }
}

}  // namespace nuld::study
