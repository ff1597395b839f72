#include "backends/ranks.h"

#include <tbb/global_control.h>
#include <tbb/info.h>

#include <climits>
#include <cstdio>
#include <cstdlib>
#include <iostream>
#include <memory>
#include <stdexcept>
#include <thread>

#if NULD_HAVE_MPI
#include <mpi.h>
#endif

namespace nuld {

namespace {

Ranks &worldRanks() {
  static Ranks ranks(0, 1);
  return ranks;
}

// Launchers say so in the environment: Open MPI's mpirun, PMIx (srun
// --mpi=pmix, Open MPI 5) and PMI-1/2 (srun --mpi=pmi2, MPICH).
bool startedByLauncher() {
  for (const char *name : {"OMPI_COMM_WORLD_SIZE", "PMIX_RANK", "PMI_RANK", "PMI_SIZE"})
    if (std::getenv(name)) return true;
  return false;
}

#if NULD_HAVE_MPI
int toInt(std::size_t n, const char *what) {
  if (n > std::size_t(INT_MAX))
    throw std::runtime_error(std::string("MPI: ") + what + " of " + std::to_string(n) +
                             " bytes is over the 2 GiB one message can carry");
  return int(n);
}
#endif

}  // namespace

const Ranks &Ranks::world() { return worldRanks(); }

void Ranks::barrier() const {
#if NULD_HAVE_MPI
  if (distributed()) MPI_Barrier(MPI_COMM_WORLD);
#endif
}

std::vector<std::string> Ranks::gather(std::string_view bytes) const {
  std::vector<std::string> all;
  if (!distributed()) {
    all.emplace_back(bytes);
    return all;
  }
#if NULD_HAVE_MPI
  // Point to point, one rank after another: rank 0 holds every result of a
  // round but never two copies of one.
  if (!root()) {
    MPI_Send(bytes.data(), toInt(bytes.size(), "a result"), MPI_BYTE, 0, 0, MPI_COMM_WORLD);
    return all;
  }
  all.emplace_back(bytes);
  for (int r = 1; r < size_; ++r) {
    MPI_Status status;
    MPI_Probe(r, 0, MPI_COMM_WORLD, &status);
    int count = 0;
    MPI_Get_count(&status, MPI_BYTE, &count);
    std::string message(std::size_t(count), '\0');
    MPI_Recv(message.data(), count, MPI_BYTE, r, 0, MPI_COMM_WORLD, MPI_STATUS_IGNORE);
    all.push_back(std::move(message));
  }
#endif
  return all;
}

std::string Ranks::broadcast(std::string bytes) const {
#if NULD_HAVE_MPI
  if (distributed()) {
    unsigned long long n = bytes.size();
    MPI_Bcast(&n, 1, MPI_UNSIGNED_LONG_LONG, 0, MPI_COMM_WORLD);
    bytes.resize(n);
    MPI_Bcast(bytes.data(), toInt(n, "a broadcast"), MPI_BYTE, 0, MPI_COMM_WORLD);
  }
#endif
  return bytes;
}

void Ranks::fail(const std::string &what, int status) const {
  // One write, so that the launcher's own messages cannot cut the line.
  const std::string line = (distributed() ? "nuld: error on rank " + std::to_string(rank_) +
                                                " of " + std::to_string(size_) + ": "
                                          : std::string("nuld: error: ")) +
                           what + "\n";
  std::fwrite(line.data(), 1, line.size(), stderr);
  std::fflush(stderr);
#if NULD_HAVE_MPI
  if (distributed()) MPI_Abort(MPI_COMM_WORLD, status);
#endif
  std::exit(status);
}

void runInRounds(const Ranks &ranks, std::size_t count,
                 const std::function<std::string(std::size_t)> &run,
                 const std::function<void(std::size_t, const std::string &)> &collect,
                 const std::function<void(std::size_t)> &roundDone) {
  const std::size_t K = std::size_t(ranks.size());
  for (std::size_t first = 0; first < count; first += K) {
    const std::size_t mine = first + std::size_t(ranks.rank());
    const std::string result = mine < count ? run(mine) : std::string();
    const std::vector<std::string> round = ranks.gather(result);
    if (!ranks.root()) continue;
    const std::size_t end = std::min(count, first + K);
    for (std::size_t i = first; i < end; ++i) collect(i, round[i - first]);
    if (roundDone) roundDone(end);
  }
}

void ByteReader::need(std::size_t n) const {
  if (n > bytes_.size() - pos_)
    throw std::runtime_error("a result sent between ranks ended early (" +
                             std::to_string(bytes_.size()) + " bytes)");
}

struct MpiSession::ThreadLimit {
  std::unique_ptr<tbb::global_control> control;
};

MpiSession::MpiSession(int &argc, char **&argv) {
#if NULD_HAVE_MPI
  if (!startedByLauncher()) return;
  int provided = 0;
  // Only the main thread calls MPI; TBB's workers never do.
  MPI_Init_thread(&argc, &argv, MPI_THREAD_FUNNELED, &provided);
  started_ = true;
  int rank = 0, size = 1;
  MPI_Comm_rank(MPI_COMM_WORLD, &rank);
  MPI_Comm_size(MPI_COMM_WORLD, &size);
  worldRanks() = Ranks(rank, size);
  if (size == 1) return;
  // The ranks sharing this node share its cores: each runs at most its share
  // of them, and at most those the launcher bound it to (TBB's default
  // follows the binding), so that neither socket binding nor none
  // oversubscribes the node.
  MPI_Comm node;
  MPI_Comm_split_type(MPI_COMM_WORLD, MPI_COMM_TYPE_SHARED, rank, MPI_INFO_NULL, &node);
  int onNode = 1;
  MPI_Comm_size(node, &onNode);
  MPI_Comm_free(&node);
  const int share = std::max(1, int(std::thread::hardware_concurrency()) / onNode);
  if (share < tbb::info::default_concurrency())
    threads_ = new ThreadLimit{std::make_unique<tbb::global_control>(
        tbb::global_control::max_allowed_parallelism, std::size_t(share))};
#else
  (void)argc;
  (void)argv;
  if (startedByLauncher() && std::getenv("OMPI_COMM_WORLD_SIZE") &&
      std::string(std::getenv("OMPI_COMM_WORLD_SIZE")) != "1") {
    // Each copy would run the whole job and write the same files.
    std::cerr << "nuld: error: started by an MPI launcher, but this nuld was built without MPI "
                 "(install libopenmpi-dev and rebuild: tools/build.sh)\n";
    std::exit(2);
  }
#endif
}

MpiSession::~MpiSession() {
  delete threads_;
#if NULD_HAVE_MPI
  if (started_) MPI_Finalize();
#endif
}

}  // namespace nuld
