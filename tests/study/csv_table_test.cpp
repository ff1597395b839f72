// CsvTable: the options record that keeps a rerun from mixing its rows with
// rows made under other options.
#include "tools/study/csv_table.h"

#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <stdexcept>
#include <string>

#include "tests/common/temp_dir.h"

namespace nuld::study {
namespace {

namespace fs = std::filesystem;
using test::TempDir;

std::string readLine(const fs::path &path) {
  std::ifstream in(path);
  std::string line;
  std::getline(in, line);
  return line;
}

// A table with one row, made under `options`.
CsvTable tableWithRow(const fs::path &csv, const std::string &options) {
  CsvTable t(csv, {"key", "value"});
  t.loadExisting();
  t.requireOptions(options);
  t.addRow({"a", "1"});
  return t;
}

TEST(CsvTableOptions, SameOptionsResumeAndOthersAreRefusedNamingEachDifference) {
  TempDir dir;
  const fs::path csv = dir / "t.csv";
  tableWithRow(csv, "repeats=4 seed=1 mix=auto");
  EXPECT_EQ(readLine(csv.string() + ".options"), "repeats=4 seed=1 mix=auto");

  CsvTable same(csv, {"key", "value"});
  same.loadExisting();
  EXPECT_NO_THROW(same.requireOptions("repeats=4 seed=1 mix=auto"));

  CsvTable other(csv, {"key", "value"});
  other.loadExisting();
  try {
    other.requireOptions("repeats=2 seed=1 mix=auto new=3");
    FAIL() << "other options were accepted";
  } catch (const std::runtime_error &e) {
    const std::string what = e.what();
    EXPECT_NE(what.find(csv.string()), std::string::npos) << what;
    EXPECT_NE(what.find("--repeats 4 there, 2 now"), std::string::npos) << what;
    EXPECT_NE(what.find("--new (not recorded) there, 3 now"), std::string::npos) << what;
    EXPECT_EQ(what.find("--seed"), std::string::npos) << "only differences are named: " << what;
  }
  // The refusal leaves the record as it was.
  EXPECT_EQ(readLine(csv.string() + ".options"), "repeats=4 seed=1 mix=auto");
}

TEST(CsvTableOptions, AnEmptyTableTakesNewOptionsAndAnOldOneAdoptsThem) {
  TempDir dir;
  const fs::path csv = dir / "t.csv";
  tableWithRow(csv, "repeats=4");
  // The rows are gone (a user removed the CSV): nothing to mix with.
  fs::remove(csv);
  CsvTable fresh(csv, {"key", "value"});
  fresh.loadExisting();
  EXPECT_NO_THROW(fresh.requireOptions("repeats=2"));
  EXPECT_EQ(readLine(csv.string() + ".options"), "repeats=2");

  // A table written before the record existed adopts the options it is
  // resumed with.
  fs::remove(csv.string() + ".options");
  tableWithRow(dir / "u.csv", "repeats=2");
  fs::remove(dir / "u.csv.options");
  CsvTable old(dir / "u.csv", {"key", "value"});
  old.loadExisting();
  EXPECT_NO_THROW(old.requireOptions("repeats=8"));
  EXPECT_EQ(readLine(dir / "u.csv.options"), "repeats=8");
}

TEST(CsvTableOptions, CheckingWithoutWritingLeavesNoFile) {
  TempDir dir;
  CsvTable t(dir / "t.csv", {"key", "value"});
  t.loadExisting();
  t.requireOptions("repeats=1", /*write=*/false);
  EXPECT_FALSE(fs::exists(dir / "t.csv.options"));
}

// A table written before its derived columns existed loads with them empty
// (then filled by setColumn); any other header is refused naming the file.
TEST(CsvTableDerived, AnOlderFileWithoutDerivedColumnsLoadsAndFills) {
  TempDir dir;
  const fs::path csv = dir / "t.csv";
  {
    std::ofstream out(csv);
    out << "key,value,file\na,1,x.exr\nb,2,y.exr\n";
  }
  CsvTable t(csv, {"key", "value", "ratio", "file"}, {"ratio"});
  t.loadExisting();
  ASSERT_EQ(t.rows().size(), 2u);
  EXPECT_EQ(t.rows()[0], (std::vector<std::string>{"a", "1", "", "x.exr"}));
  t.setColumn("ratio", {"0.5", "2"});
  EXPECT_EQ(readLine(csv), "key,value,ratio,file");
  CsvTable again(csv, {"key", "value", "ratio", "file"}, {"ratio"});
  again.loadExisting();
  EXPECT_EQ(again.rows()[1], (std::vector<std::string>{"b", "2", "2", "y.exr"}));
  EXPECT_THROW(t.setColumn("ratio", {"1"}), std::logic_error);

  CsvTable other(csv, {"key", "value", "file"}, {"ratio"});
  try {
    other.loadExisting();
    ADD_FAILURE() << "a header with a column this table lacks was accepted";
  } catch (const std::runtime_error &e) {
    EXPECT_NE(std::string(e.what()).find(csv.string()), std::string::npos) << e.what();
  }
}

// A file older than some of the derived columns (render.csv with the
// equal-time columns but not the baselines) loads with just those empty; a
// missing column that is not derived is still refused.
TEST(CsvTableDerived, AFileMissingSomeDerivedColumnsLoads) {
  TempDir dir;
  const fs::path csv = dir / "t.csv";
  std::ofstream(csv) << "key,value,ratio,file\na,1,0.5,x.exr\n";
  CsvTable t(csv, {"key", "value", "ratio", "file", "extra"}, {"ratio", "extra"});
  t.loadExisting();
  ASSERT_EQ(t.rows().size(), 1u);
  EXPECT_EQ(t.rows()[0], (std::vector<std::string>{"a", "1", "0.5", "x.exr", ""}));
  CsvTable strict(csv, {"key", "value", "ratio", "file", "extra"}, {"extra"});
  strict.loadExisting();  // ratio is in the file
  CsvTable lacking(csv, {"key", "value", "ratio", "file", "must"}, {"ratio"});
  EXPECT_THROW(lacking.loadExisting(), std::runtime_error);
}

// putRow replaces the row of its key (rewriting the file) or appends one.
TEST(CsvTable, PutRowReplacesTheRowOfItsKey) {
  TempDir dir;
  const fs::path csv = dir / "t.csv";
  CsvTable t(csv, {"key", "value"});
  t.putRow({"a", "1"}, 1);
  t.putRow({"b", "2"}, 1);
  t.putRow({"a", "3"}, 1);
  EXPECT_EQ(t.rows(), (std::vector<std::vector<std::string>>{{"a", "3"}, {"b", "2"}}));
  CsvTable again(csv, {"key", "value"});
  again.loadExisting();
  EXPECT_EQ(again.rows(), t.rows());
  EXPECT_THROW(t.putRow({"a"}, 1), std::logic_error);
}

}  // namespace
}  // namespace nuld::study
