#pragma once
// The studies' result tables: a header row of column names, then one row per
// measurement, every value already formatted. Written atomically after every
// row, so an interrupted study leaves a valid CSV and resumes by skipping the
// rows it finds (see hasRow).

#include <filesystem>
#include <string>
#include <vector>

#include "sampler/io/round_trip.h"  // formatNumber

namespace nuld::study {

// The owner's word in a study folder's mark (sampler/io/output_folder.h):
// both studies and their report write into one folder.
inline constexpr const char *kStudyFolder = "study";

class CsvTable {
 public:
  // `derived`: columns computed from the others (setColumn), which a file
  // written before they existed may lack; loadExisting leaves them empty.
  CsvTable(std::filesystem::path path, std::vector<std::string> columns,
           std::vector<std::string> derived = {});

  // Reads the rows of an existing file with the same columns, or with the
  // same but for derived ones (resume); throws std::runtime_error naming the
  // file when its header differs otherwise.
  void loadExisting();

  // The options the rows depend on beyond their key columns, as words
  // "name=value" named like the command's options ("repeats=4 seed=1").
  // They are kept beside the table in PATH.options: a rerun that asks for
  // other values is refused with an error naming each option that differs,
  // since its rows would stand next to rows made otherwise. A table with no
  // rows takes the new values; one made before the file existed adopts them.
  // `write` false (MPI ranks but the root) checks without writing.
  void requireOptions(const std::string &options, bool write = true);

  // The row that has these values in the first key.size() columns, or null.
  const std::vector<std::string> *findRow(const std::vector<std::string> &key) const;
  bool hasRow(const std::vector<std::string> &key) const { return findRow(key) != nullptr; }

  // Appends a row (as many values as columns, or throws) and rewrites the file.
  void addRow(std::vector<std::string> values);
  // Replaces the row whose first `keySize` values are these, or appends it;
  // rewrites the file when that changed anything.
  void putRow(std::vector<std::string> values, std::size_t keySize);

  // Sets a column's value in every row (as many values as rows, or throws)
  // and rewrites the file.
  void setColumn(const std::string &name, const std::vector<std::string> &values);

  const std::vector<std::string> &columns() const { return columns_; }
  // The index of a column; throws std::logic_error for a name it lacks.
  std::size_t column(const std::string &name) const;
  const std::vector<std::vector<std::string>> &rows() const { return rows_; }
  const std::filesystem::path &path() const { return path_; }

 private:
  void checkRow(const std::vector<std::string> &values) const;
  void write() const;

  std::filesystem::path path_;
  std::vector<std::string> columns_, derived_;
  std::vector<std::vector<std::string>> rows_;
};

// A table's value as a number: NaN for an empty or unreadable one.
double parseNumber(const std::string &s);

}  // namespace nuld::study
