// Rollouts across MPI ranks (include/plumb/mpi_rollout.h).

#include "plumb/mpi_rollout.h"

#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <map>
#include <string>

#include "plumb/error.h"

#ifdef PLUMB_WITH_MPI
#include <mpi.h>
#endif

namespace plumb {

#ifdef PLUMB_WITH_MPI

namespace {
bool g_initialised = false;
bool g_in_batch = false;        // past MpiGo(true): the ranks depend on each other
constexpr int kTagResults = 1;  // worker -> root: results of the last chunk (maybe none)
constexpr int kTagWork = 2;     // root -> worker: the next chunk of indices
constexpr int kTagStop = 3;     // root -> worker: nothing left
constexpr std::size_t kChunk = 32;

bool LaunchedByMpi() {
  for (const char* v : {"OMPI_COMM_WORLD_SIZE", "PMI_SIZE", "PMIX_RANK"}) {
    if (std::getenv(v)) return true;
  }
  return false;
}

int Size() {
  int size = 1;
  MPI_Comm_size(MPI_COMM_WORLD, &size);
  return size;
}

// A message of results: each encoded result prefixed with its length.
std::string Pack(const std::vector<RolloutResult>& results) {
  std::string out;
  for (const RolloutResult& r : results) {
    std::string bytes = EncodeResult(r);
    std::uint64_t n = bytes.size();
    out.append(reinterpret_cast<const char*>(&n), sizeof(n));
    out += bytes;
  }
  return out;
}

std::vector<RolloutResult> Unpack(const std::string& in) {
  std::vector<RolloutResult> out;
  std::size_t at = 0;
  while (at < in.size()) {
    std::uint64_t n;
    if (in.size() - at < sizeof(n)) {
      throw Error("MPI: a results message ends inside a length prefix (" +
                  std::to_string(in.size() - at) + " bytes left)");
    }
    std::memcpy(&n, in.data() + at, sizeof(n));
    at += sizeof(n);
    if (n > in.size() - at) {
      throw Error("MPI: a results message announces " + std::to_string(n) + " bytes where " +
                  std::to_string(in.size() - at) + " are left");
    }
    out.push_back(DecodeResult(in.substr(at, n)));
    at += n;
  }
  return out;
}

std::string Receive(int source, int tag, MPI_Status* status) {
  MPI_Probe(source, tag, MPI_COMM_WORLD, status);
  int count = 0;
  MPI_Get_count(status, MPI_BYTE, &count);
  std::string buffer(count, '\0');
  MPI_Recv(buffer.data(), count, MPI_BYTE, status->MPI_SOURCE, status->MPI_TAG, MPI_COMM_WORLD,
           MPI_STATUS_IGNORE);
  return buffer;
}
}  // namespace

void MpiInit(int* argc, char*** argv) {
  if (!LaunchedByMpi()) return;
  MPI_Init(argc, argv);
  g_initialised = true;
}

void MpiFinalize() {
  if (g_initialised) MPI_Finalize();
}

bool MpiActive() { return g_initialised && Size() > 1; }

int MpiRank() {
  if (!g_initialised) return 0;
  int rank = 0;
  MPI_Comm_rank(MPI_COMM_WORLD, &rank);
  return rank;
}

bool MpiGo(bool ok) {
  if (!MpiActive()) return ok;
  int go = ok ? 1 : 0;
  MPI_Bcast(&go, 1, MPI_INT, 0, MPI_COMM_WORLD);
  g_in_batch = go != 0;
  return g_in_batch;
}

void MpiAbortOnError(int code) {
  // before the batch every rank meets the same errors and ends on its own
  if (MpiActive() && g_in_batch) {
    std::fflush(stdout);
    std::fflush(stderr);
    MPI_Abort(MPI_COMM_WORLD, code);
  }
}

void MpiRollout(const Model& model, const RolloutSpec& spec, const std::vector<long>& indices,
                const std::function<void(const RolloutResult&)>& emit, const StopToken& stop) {
  if (MpiRank() != 0) {
    // a worker: ask for work with the results of the last chunk, until told to stop
    std::vector<RolloutResult> results;
    RolloutSpec local = spec;
    local.progress = nullptr;
    RolloutPool pool(model, local);  // one model copy per thread for every chunk
    while (true) {
      std::string message = Pack(results);
      MPI_Send(message.data(), static_cast<int>(message.size()), MPI_BYTE, 0, kTagResults,
               MPI_COMM_WORLD);
      MPI_Status status;
      std::string work = Receive(0, MPI_ANY_TAG, &status);
      if (status.MPI_TAG == kTagStop) return;
      if (work.size() % sizeof(long) != 0) {
        throw Error("MPI: a work message of " + std::to_string(work.size()) +
                    " bytes is not a whole number of rollout indices");
      }
      std::vector<long> chunk(work.size() / sizeof(long));
      std::memcpy(chunk.data(), work.data(), chunk.size() * sizeof(long));
      results.clear();
      pool.Run(
          chunk, [&](const RolloutResult& r) { results.push_back(r); }, stop);
    }
  }
  // the root: hand out chunks in index order as workers ask, emit results in order
  std::map<long, RolloutResult> pending;
  std::size_t next = 0, emitted = 0;
  int active = Size() - 1;
  while (active > 0) {
    MPI_Status status;
    std::string message = Receive(MPI_ANY_SOURCE, kTagResults, &status);
    for (RolloutResult& r : Unpack(message)) pending.emplace(r.index, std::move(r));
    if (next < indices.size()) {
      std::size_t n = std::min(kChunk, indices.size() - next);
      MPI_Send(indices.data() + next, static_cast<int>(n * sizeof(long)), MPI_BYTE,
               status.MPI_SOURCE, kTagWork, MPI_COMM_WORLD);
      next += n;
    } else {
      MPI_Send(nullptr, 0, MPI_BYTE, status.MPI_SOURCE, kTagStop, MPI_COMM_WORLD);
      --active;
    }
    while (emitted < indices.size()) {
      auto it = pending.find(indices[emitted]);
      if (it == pending.end()) break;
      emit(it->second);
      pending.erase(it);
      ++emitted;
      if (spec.progress)
        spec.progress(static_cast<long>(emitted), static_cast<long>(indices.size()));
    }
  }
  if (emitted != indices.size()) throw Error("MPI: some rollouts were never returned");
}

#else  // without MPI

void MpiInit(int*, char***) {}
void MpiFinalize() {}
bool MpiActive() { return false; }
int MpiRank() { return 0; }
bool MpiGo(bool ok) { return ok; }
void MpiAbortOnError(int) {}
void MpiRollout(const Model&, const RolloutSpec&, const std::vector<long>&,
                const std::function<void(const RolloutResult&)>&, const StopToken&) {
  throw Error("plumb was built without MPI (PLUMB_WITH_MPI=OFF)");
}

#endif

}  // namespace plumb
