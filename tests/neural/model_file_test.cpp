// The model file format: round trips bit-exactly; truncated, corrupted and
// foreign files are errors that name the file.

#include "sampler/neural/model_file.h"

#include <gtest/gtest.h>

#include <cmath>
#include <fstream>
#include <limits>
#include <sstream>

#include "tests/common/temp_dir.h"

namespace nuld {
namespace {

ModelFile sample() {
  ModelFile m;
  m.metadata = {{"format", "test"}, {"n", "3"}};
  m.tensors.push_back({"a", {2, 3}, {1.5f, -0.f, 3e-38f, 1e38f, std::nextafter(1.f, 2.f), 7}});
  m.tensors.push_back({"empty", {0}, {}});
  return m;
}

std::string readAll(const std::string &path) {
  std::ifstream in(path, std::ios::binary);
  std::ostringstream s;
  s << in.rdbuf();
  return s.str();
}

void expectErrorNaming(const std::string &path, const std::string &fragment) {
  try {
    readModelFile(path);
    FAIL() << "no error for " << path;
  } catch (const std::runtime_error &e) {
    EXPECT_NE(std::string(e.what()).find(path), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find(fragment), std::string::npos) << e.what();
  }
}

TEST(ModelFile, RoundTripsBitExactly) {
  test::TempDir dir;
  const std::string path = (dir / "m.nuldnet").string();
  writeModelFile(path, sample());
  const ModelFile back = readModelFile(path);
  EXPECT_EQ(back.metadata, sample().metadata);
  ASSERT_EQ(back.tensors.size(), 2u);
  EXPECT_EQ(back.tensors[0].shape, (std::vector<std::int64_t>{2, 3}));
  for (std::size_t i = 0; i < 6; ++i)
    EXPECT_EQ(std::bit_cast<std::uint32_t>(back.tensors[0].data[i]),
              std::bit_cast<std::uint32_t>(sample().tensors[0].data[i]));
  EXPECT_TRUE(back.tensors[1].data.empty());
  EXPECT_EQ(back.tensor("a", path).name, "a");
  EXPECT_THROW(back.tensor("b", path), std::runtime_error);
  EXPECT_THROW(back.value("missing", path), std::runtime_error);
}

// The process keeps the last model read from a path while the file keeps its
// size, time and closing checksum: a read again returns the same model; a
// different model of the same size written there at once (the same time to
// the file system's resolution, perhaps) has another checksum and is read
// anew; so is the file after a truncation, which is an error.
TEST(ModelFile, ReadingAgainFollowsTheFilesContent) {
  test::TempDir dir;
  const std::string path = (dir / "m.nuldnet").string();
  writeModelFile(path, sample());
  const ModelFile first = readModelFile(path);
  const ModelFile again = readModelFile(path);
  EXPECT_EQ(again.checksum, first.checksum);
  EXPECT_EQ(again.tensors[0].data, first.tensors[0].data);
  ModelFile other = sample();
  other.tensors[0].data[0] = 2.5f;  // the same size, other content
  writeModelFile(path, other);
  const ModelFile changed = readModelFile(path);
  EXPECT_NE(changed.checksum, first.checksum);
  EXPECT_EQ(changed.tensors[0].data[0], 2.5f);
  const std::string bytes = readAll(path);
  dir.write("m.nuldnet", bytes.substr(0, bytes.size() - 5));
  expectErrorNaming(path, "checksum");
}

TEST(ModelFile, EveryTruncationIsAnErrorNamingTheFile) {
  test::TempDir dir;
  const std::string good = (dir / "good.nuldnet").string();
  writeModelFile(good, sample());
  const std::string bytes = readAll(good);
  for (std::size_t len = 0; len < bytes.size(); ++len) {
    const std::string path = dir.write("cut.nuldnet", bytes.substr(0, len));
    EXPECT_THROW(readModelFile(path), std::runtime_error) << "length " << len;
  }
  expectErrorNaming(dir.write("cut.nuldnet", bytes.substr(0, bytes.size() - 5)), "checksum");
}

TEST(ModelFile, CorruptedAndForeignFilesAreClearErrors) {
  test::TempDir dir;
  const std::string good = (dir / "good.nuldnet").string();
  writeModelFile(good, sample());
  std::string bytes = readAll(good);
  bytes[bytes.size() / 2] ^= 0x10;
  expectErrorNaming(dir.write("flipped.nuldnet", bytes), "checksum");
  expectErrorNaming(dir.write("points.txt", "# set\n0.5 0.5\n"), "not a nuld model file");
  expectErrorNaming(dir.write("empty.nuldnet", ""), "not a nuld model file");
  expectErrorNaming((dir / "absent.nuldnet").string(), "cannot open");
}

TEST(ModelFile, RejectsShapeDataMismatchOnWrite) {
  test::TempDir dir;
  ModelFile m;
  m.tensors.push_back({"bad", {2, 2}, {1, 2, 3}});
  EXPECT_THROW(writeModelFile((dir / "m").string(), m), std::invalid_argument);
}

}  // namespace
}  // namespace nuld
