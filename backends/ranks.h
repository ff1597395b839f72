#pragma once
// The processes of one job started by an MPI launcher (mpirun, srun): the
// studies and `nuld optimize` split their work over them (docs/usage.md,
// "Running on several machines"). Without a launcher, or in a build without
// MPI, the job is one process, rank 0 of 1, and every call here is a no-op
// or the identity, so the same code runs both ways.
//
// The work is split statically: tasks 0..n-1 run in rounds, rank r running
// task round * K + r. After each round rank 0 gathers the round's results,
// in task order, and alone writes them; so a job's output does not depend on
// the rank count, and a rerun resumes from the last round written.
// A rank that fails prints its error and stops the whole job (MPI_Abort).
//
// mpi.h stays in ranks.cpp; nothing else needs it.

#include <cstdint>
#include <cstring>
#include <functional>
#include <string>
#include <string_view>
#include <type_traits>
#include <utility>
#include <vector>

#include "sampler/io/image_io.h"
#include "sampler/point.h"

namespace nuld {

class Ranks {
 public:
  // This process's view of the job: rank 0 of 1 unless an MpiSession started
  // MPI under a launcher.
  static const Ranks &world();

  int rank() const { return rank_; }
  int size() const { return size_; }
  bool root() const { return rank_ == 0; }
  bool distributed() const { return size_ > 1; }

  void barrier() const;
  // Each rank's bytes, in rank order, on rank 0; the other ranks get {}.
  std::vector<std::string> gather(std::string_view bytes) const;
  // Rank 0's bytes, on every rank.
  std::string broadcast(std::string bytes) const;
  // Prints "nuld: error on rank R of K: WHAT" (or "nuld: error: WHAT" in a
  // single process) and ends the job: every rank, with `status`.
  [[noreturn]] void fail(const std::string &what, int status = 1) const;

  // For MpiSession only.
  Ranks(int rank, int size) : rank_(rank), size_(size) {}

 private:
  int rank_ = 0, size_ = 1;
};

// Starts MPI when this process was started by a launcher (Open MPI's mpirun,
// Slurm's srun under PMI or PMIx), and ends it when destroyed. In a job of
// several ranks each rank's TBB threads are at most its share of the node's
// cores and at most the cores the launcher bound it to.
class MpiSession {
 public:
  MpiSession(int &argc, char **&argv);
  ~MpiSession();
  MpiSession(const MpiSession &) = delete;
  MpiSession &operator=(const MpiSession &) = delete;

 private:
  bool started_ = false;
  struct ThreadLimit;
  ThreadLimit *threads_ = nullptr;
};

// Runs tasks [0, count) over the ranks, in rounds of size() tasks: `run(i)`
// runs on the rank owning task i and returns its result as bytes;
// `collect(i, bytes)` runs on rank 0 for every task of a round, in task
// order, once the round is done, and then `roundDone(tasksCollected)`
// (optional) on rank 0, where a caller saves its progress. In a single
// process each task is run and collected in turn.
void runInRounds(const Ranks &ranks, std::size_t count,
                 const std::function<std::string(std::size_t)> &run,
                 const std::function<void(std::size_t, const std::string &)> &collect,
                 const std::function<void(std::size_t)> &roundDone = {});

// Flat byte records for results sent between ranks: values and strings
// appended in order and read back in the same order.
class ByteWriter {
 public:
  template <class T>
  requires std::is_trivially_copyable_v<T> ByteWriter &put(const T &v) {
    bytes_.append(reinterpret_cast<const char *>(&v), sizeof v);
    return *this;
  }
  ByteWriter &put(const std::string &s) {
    put(std::uint64_t(s.size()));
    bytes_ += s;
    return *this;
  }
  template <class A, class B>
  ByteWriter &put(const std::pair<A, B> &p) {
    return put(p.first).put(p.second);
  }
  template <class T>
  ByteWriter &put(const std::vector<T> &v) {
    put(std::uint64_t(v.size()));
    if constexpr (std::is_trivially_copyable_v<T>)
      bytes_.append(reinterpret_cast<const char *>(v.data()), v.size() * sizeof(T));
    else
      for (const T &x : v) put(x);
    return *this;
  }
  ByteWriter &put(const Image &image) {
    return put(image.width).put(image.height).put(image.channels).put(image.pixels);
  }
  ByteWriter &put(const PointSet &set) {
    return put(std::uint64_t(set.n))
        .put(set.points)
        .put(std::vector<std::pair<std::string, std::string>>(set.metadata.begin(),
                                                              set.metadata.end()));
  }
  std::string take() { return std::move(bytes_); }

 private:
  std::string bytes_;
};

class ByteReader {
 public:
  explicit ByteReader(std::string_view bytes) : bytes_(bytes) {}
  // The reader keeps a view: the bytes must outlive it.
  explicit ByteReader(std::string &&) = delete;
  template <class T>
  requires std::is_trivially_copyable_v<T>
  void get(T &v) {
    need(sizeof v);
    std::memcpy(&v, bytes_.data() + pos_, sizeof v);
    pos_ += sizeof v;
  }
  void get(std::string &s) {
    std::uint64_t n = 0;
    get(n);
    need(n);
    s.assign(bytes_.substr(pos_, n));
    pos_ += n;
  }
  template <class A, class B>
  void get(std::pair<A, B> &p) {
    get(p.first);
    get(p.second);
  }
  template <class T>
  void get(std::vector<T> &v) {
    std::uint64_t n = 0;
    get(n);
    if constexpr (std::is_trivially_copyable_v<T>) {
      if (n > (bytes_.size() - pos_) / sizeof(T)) need(bytes_.size() - pos_ + 1);  // no overflow
      need(n * sizeof(T));
      v.resize(n);
      // An empty vector's data() may be null, which memcpy must not get.
      if (n > 0) std::memcpy(v.data(), bytes_.data() + pos_, n * sizeof(T));
      pos_ += n * sizeof(T);
    } else {
      // Every element takes at least its 8-byte length.
      if (n > (bytes_.size() - pos_) / 8) need(bytes_.size() - pos_ + 1);
      v.resize(n);
      for (T &x : v) get(x);
    }
  }
  void get(Image &image) {
    get(image.width);
    get(image.height);
    get(image.channels);
    get(image.pixels);
  }
  void get(PointSet &set) {
    set.n = std::size_t(get<std::uint64_t>());
    get(set.points);
    const auto metadata = get<std::vector<std::pair<std::string, std::string>>>();
    set.metadata = {metadata.begin(), metadata.end()};
  }
  template <class T>
  T get() {
    T v{};
    get(v);
    return v;
  }

 private:
  void need(std::size_t n) const;
  std::string_view bytes_;
  std::size_t pos_ = 0;
};

// The one value a record holds.
template <class T>
T fromBytes(std::string_view bytes) {
  ByteReader r(bytes);
  return r.get<T>();
}

}  // namespace nuld
