// Point-set files: exact round trips and clear errors on malformed input.
#include "sampler/io/pointset_io.h"

#include <gtest/gtest.h>
#include <sys/stat.h>
#include <unistd.h>

#include <cstring>
#include <filesystem>
#include <fstream>
#include <sstream>

#include "sampler/io/atomic_file.h"
#include "sampler/io/pointset_metadata.h"
#include "sampler/sequences/sequence.h"
#include "tests/common/expect_error.h"
#include "tests/common/temp_dir.h"

namespace nuld {
namespace {

namespace fs = std::filesystem;

void writeText(const fs::path &p, const std::string &s) { std::ofstream(p) << s; }

std::string errorOf(const fs::path &p) {
  try {
    readPointSet(p.string());
  } catch (const std::exception &e) {
    return e.what();
  }
  return "";
}

TEST(PointSetIo, TextAndBinaryRoundTripsAreExact) {
  PointSet set = generatePointSet({SequenceKind::Sobol, Scramble::Owen, 3}, 37, 3);
  set.metadata["target"] = "quarterdisc";
  for (const char *name : {"a.txt", "a.ptsb"}) {
    const test::TempDir dir;
    const fs::path p = dir / name;
    writePointSet(p.string(), set);
    const PointSet back = readPointSet(p.string());
    EXPECT_EQ(back.n, 37u);
    EXPECT_EQ(back.instances(), 3u);
    EXPECT_EQ(back.points, set.points) << name;
    EXPECT_EQ(back.metadata, set.metadata) << name;
  }
}

// The keys are the files' format: their spellings must not change.
TEST(PointSetIo, MetadataKeysKeepTheirSpellingsInFiles) {
  PointSet set = generatePointSet({SequenceKind::Sobol, Scramble::Owen, 3}, 4, 2);
  setMeta(set, meta::kTarget, "quarterdisc");
  setMeta(set, meta::kOptimizeSeconds, "1.5");
  std::ostringstream text;
  writePointSetText(text, set);
  for (const char *line :
       {"# nuld-pointset: 1\n", "# n: 4\n", "# instances: 2\n", "# generator: sobol\n",
        "# seed: 3\n", "# target: quarterdisc\n", "# optimize_seconds: 1.5\n"})
    EXPECT_NE(text.str().find(line), std::string::npos) << line;
  EXPECT_EQ(set.metadata.at("target"), "quarterdisc");
  // The header is derived from the data: reading drops it.
  const test::TempDir dir;
  writeText(dir / "s.txt", text.str());
  const PointSet back = readPointSet((dir / "s.txt").string());
  EXPECT_EQ(back.metadata, set.metadata);
  EXPECT_EQ(findMeta(back, meta::kN), nullptr);
  EXPECT_EQ(findMeta(back, meta::kInstances), nullptr);
}

TEST(PointSetIo, MetadataAccessorsFallBackWhenAKeyIsAbsent) {
  PointSet set;
  setMeta(set, meta::kTarget, "uniform");
  EXPECT_EQ(metaOr(set, meta::kTarget, "none"), "uniform");
  EXPECT_EQ(metaOr(set, meta::kDomain, "square"), "square");
  ASSERT_NE(findMeta(set, meta::kTarget), nullptr);
  EXPECT_EQ(*findMeta(set, meta::kTarget), "uniform");
  EXPECT_EQ(findMeta(set, meta::kDomain), nullptr);
}

TEST(PointSetIo, ReadsUtkStyleFiles) {
  const test::TempDir dir;
  const fs::path p = dir / "utk.dat";
  writeText(p, "0.1 0.2\n0.3 0.4\n#\n0.5 0.6\n0.7 0.8\n");
  const PointSet s = readPointSet(p.string());
  EXPECT_EQ(s.n, 2u);
  EXPECT_EQ(s.instances(), 2u);
  EXPECT_EQ(s.points[3], (Point2{0.7, 0.8}));
}

// A UTK .dat file round-trips through nuld byte for byte: read, then
// exported as .dat (UTK's own text format, without the metadata lines its
// reader would take for separators).
TEST(PointSetIo, UtkFilesRoundTrip) {
  const test::TempDir dir;
  const std::string utk = "0.1 0.2\n0.3 0.4\n0.25 0.125\n#\n0.5 0.6\n0.7 0.8\n0.9 1e-05\n";
  writeText(dir / "in.dat", utk);
  const PointSet s = readPointSet((dir / "in.dat").string());
  exportPointSet((dir / "out.dat").string(), s);
  std::ifstream in(dir / "out.dat");
  std::stringstream back;
  back << in.rdbuf();
  EXPECT_EQ(back.str(), utk);
  EXPECT_EQ(readPointSet((dir / "out.dat").string()).points, s.points);
}

// Exports for numpy: the .npy header numpy expects and the raw doubles; CSV
// columns with the instance index.
TEST(PointSetIo, ExportsForNumpy) {
  const test::TempDir dir;
  SequenceOptions o;
  const PointSet s = generatePointSet(o, 5, 3);
  exportPointSet((dir / "s.npy").string(), s);
  std::ifstream in(dir / "s.npy", std::ios::binary);
  std::string bytes((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  ASSERT_GE(bytes.size(), 10u);
  EXPECT_EQ(bytes.substr(0, 8), std::string("\x93NUMPY\x01\x00", 8));
  const std::size_t headerLength = std::uint8_t(bytes[8]) | std::uint8_t(bytes[9]) << 8;
  EXPECT_EQ((10 + headerLength) % 64, 0u);
  const std::string header = bytes.substr(10, headerLength);
  EXPECT_NE(header.find("'shape': (3, 5, 2)"), std::string::npos) << header;
  EXPECT_EQ(header.back(), '\n');
  ASSERT_EQ(bytes.size(), 10 + headerLength + 30 * sizeof(double));
  EXPECT_EQ(std::memcmp(bytes.data() + 10 + headerLength, s.points.data(), 30 * sizeof(double)), 0);
  exportPointSet((dir / "s.csv").string(), s);
  std::ifstream csv(dir / "s.csv");
  std::string line;
  std::getline(csv, line);
  EXPECT_EQ(line, "instance,x,y");
  int lines = 0;
  while (std::getline(csv, line)) ++lines;
  EXPECT_EQ(lines, 15);
  const std::string refusal =
      test::errorMessage([&] { exportPointSet((dir / "s.xyz").string(), s); });
  EXPECT_NE(refusal.find("s.xyz"), std::string::npos) << refusal;
  EXPECT_NE(refusal.find(".npy, .csv or .dat"), std::string::npos) << refusal;
}

TEST(PointSetIo, MalformedFilesNameFileLineAndProblem) {
  const test::TempDir dir;
  const fs::path &d = dir.path();
  writeText(d / "three.txt", "0.1 0.2\n0.3 0.4 0.5\n");
  EXPECT_NE(errorOf(d / "three.txt").find("three.txt:2"), std::string::npos);
  writeText(d / "word.txt", "0.1 0.2\nabc 0.4\n");
  EXPECT_NE(errorOf(d / "word.txt").find("word.txt:2"), std::string::npos);
  writeText(d / "nan.txt", "0.1 nan\n");
  EXPECT_NE(errorOf(d / "nan.txt").find("nan.txt:1"), std::string::npos);
  writeText(d / "sizes.txt", "0 0\n1 1\n# set\n0.5 0.5\n");
  EXPECT_NE(errorOf(d / "sizes.txt").find("different sizes"), std::string::npos);
  writeText(d / "empty.txt", "# only: metadata\n");
  EXPECT_NE(errorOf(d / "empty.txt").find("no points"), std::string::npos);
  EXPECT_NE(errorOf(d / "missing.txt").find("missing.txt"), std::string::npos);
  // Truncated binary.
  PointSet set = generatePointSet({SequenceKind::Sobol, Scramble::Owen, 3}, 16, 1);
  writePointSet((d / "t.ptsb").string(), set);
  fs::resize_file(d / "t.ptsb", fs::file_size(d / "t.ptsb") - 5);
  EXPECT_NE(errorOf(d / "t.ptsb").find("does not match"), std::string::npos);
}

// Every byte of a binary file is under its checksum: one flipped bit of a
// coordinate's exponent (a point still in the square) and a same-length
// edit of a setting are refused by name; the untouched file reads back.
TEST(PointSetIo, BinaryChecksumRefusesFlippedBitsAndEdits) {
  const test::TempDir dir;
  PointSet set = generatePointSet({SequenceKind::Sobol, Scramble::Owen, 3}, 16, 2);
  setMeta(set, "seed", "1");
  const fs::path file = dir / "s.ptsb";
  writePointSet(file.string(), set);
  EXPECT_EQ(readPointSet(file.string()).points, set.points);
  const auto bytesOf = [&] {
    std::ifstream in(file, std::ios::binary);
    return std::string(std::istreambuf_iterator<char>(in), {});
  };
  const std::string clean = bytesOf();
  const auto writeBytes = [&](const std::string &bytes) {
    std::ofstream(file, std::ios::binary | std::ios::trunc) << bytes;
  };
  // The lowest exponent bit of the last point's y (bit 52 of the double
  // before the checksum): the value halves or doubles.
  std::string flipped = clean;
  flipped[clean.size() - 8 - 8 + 6] ^= char(0x10);
  writeBytes(flipped);
  EXPECT_NE(errorOf(file).find("s.ptsb: checksum mismatch"), std::string::npos) << errorOf(file);
  std::string edited = clean;
  const auto at = edited.find("seed=1");
  ASSERT_NE(at, std::string::npos);
  edited[at + 5] = '2';
  writeBytes(edited);
  EXPECT_NE(errorOf(file).find("checksum mismatch"), std::string::npos) << errorOf(file);
  writeBytes(clean);
  EXPECT_EQ(readPointSet(file.string()).metadata.at("seed"), "1");
}

TEST(PointSetIo, WriteIsAtomicAndLeavesNoTemporaries) {
  const test::TempDir dir;
  const fs::path d = dir / "atomic";
  fs::create_directories(d);
  PointSet set = generatePointSet({SequenceKind::Halton, Scramble::Owen, 1}, 10, 1);
  writePointSet((d / "x.txt").string(), set);
  writePointSet((d / "x.txt").string(), set);
  int files = 0;
  for (const auto &e : fs::directory_iterator(d)) files += e.is_regular_file();
  EXPECT_EQ(files, 1);
  EXPECT_THROW(writePointSet((d / "no_such_dir" / "x.txt").string(), set), std::runtime_error);
}

// Outputs never replace what is not a regular file: a pipe (as /dev/null
// or a terminal would be) and a directory are refused by name, nothing is
// written and the pipe is still a pipe; a link to a regular file is written
// through, and stays a link.
TEST(AtomicFile, RefusesToReplaceWhatIsNotARegularFile) {
  const test::TempDir dir;
  const auto fifo = dir / "pipe.txt";
  ASSERT_EQ(::mkfifo(fifo.c_str(), 0600), 0);
  const PointSet set = generatePointSet({SequenceKind::Sobol, Scramble::Owen, 3}, 8, 1);
  const std::string message =
      test::errorMessage<std::runtime_error>([&] { writePointSet(fifo.string(), set); });
  EXPECT_NE(message.find("pipe.txt"), std::string::npos) << message;
  EXPECT_NE(message.find("not a regular file"), std::string::npos) << message;
  EXPECT_TRUE(std::filesystem::is_fifo(fifo));
  const auto sub = dir / "sub.txt";
  std::filesystem::create_directory(sub);
  EXPECT_THROW(writeFileAtomically(sub, "x"), std::runtime_error);
  EXPECT_TRUE(std::filesystem::is_directory(sub));
  const auto target = dir / "target.txt", link = dir / "link.txt";
  writeFileAtomically(target, "old");
  std::filesystem::create_symlink(target, link);
  writeFileAtomically(link, "new");
  EXPECT_TRUE(std::filesystem::is_symlink(link));
  std::ifstream in(target);
  std::string text;
  in >> text;
  EXPECT_EQ(text, "new");
}

// A dangling link is refused by name, as GNU cp refuses to write through
// one, and stays a link: the rename would have replaced it by a file.
TEST(AtomicFile, RefusesToWriteThroughADanglingLink) {
  const test::TempDir dir;
  const auto link = dir / "out.exr";
  std::filesystem::create_symlink(dir / "gone" / "out.exr", link);
  const std::string message =
      test::errorMessage<std::runtime_error>([&] { writeFileAtomically(link, "x"); });
  EXPECT_NE(message.find("out.exr: is a dangling symbolic link"), std::string::npos) << message;
  EXPECT_TRUE(std::filesystem::is_symlink(link));
  EXPECT_FALSE(std::filesystem::exists(dir / "gone"));
}

// A file made read-only is kept, also through a link and for root (whose
// writes ignore the mode).
TEST(AtomicFile, RefusesToReplaceAReadOnlyFile) {
  const test::TempDir dir;
  const auto file = dir / "kept.txt", link = dir / "link.txt";
  writeFileAtomically(file, "mine");
  std::filesystem::permissions(
      file, std::filesystem::perms::owner_read | std::filesystem::perms::group_read);
  std::filesystem::create_symlink(file, link);
  for (const auto &path : {file, link}) {
    const std::string message =
        test::errorMessage<std::runtime_error>([&] { writeFileAtomically(path, "new"); });
    EXPECT_NE(message.find("kept.txt: is read-only; refusing to replace it"), std::string::npos)
        << message;
  }
  std::ifstream in(file);
  std::string text;
  in >> text;
  EXPECT_EQ(text, "mine");
}

}  // namespace
}  // namespace nuld
