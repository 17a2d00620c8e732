// MPI communicator (mpi.hpp).
#include "uq/mpi.hpp"

#include <cstdlib>
#include <stdexcept>

#include <mpi.h>

namespace lg::uq {

bool launchedByMpi() {
  for (const char* v : {"OMPI_COMM_WORLD_SIZE", "PMIX_RANK", "PMI_SIZE", "PMI_RANK", "MPI_LOCALNRANKS"})
    if (std::getenv(v)) return true;
  return false;
}

MpiCommunicator::MpiCommunicator(int* argc, char*** argv) {
  int provided = 0;
  if (MPI_Init_thread(argc, argv, MPI_THREAD_FUNNELED, &provided) != MPI_SUCCESS)
    throw std::runtime_error("MPI_Init_thread failed");
  MPI_Comm_rank(MPI_COMM_WORLD, &rank_);
  MPI_Comm_size(MPI_COMM_WORLD, &size_);
}

MpiCommunicator::~MpiCommunicator() { MPI_Finalize(); }

std::vector<std::string> MpiCommunicator::allGather(const std::string& mine) {
  // Sizes first (a rank's part can pass 2 GiB only with far larger studies than these), then the bytes.
  if (mine.size() > static_cast<std::size_t>(1) << 30) throw std::runtime_error("MPI gather: a rank's part is over 1 GiB");
  int n = static_cast<int>(mine.size());
  std::vector<int> sizes(static_cast<std::size_t>(size_)), offsets(static_cast<std::size_t>(size_));
  MPI_Allgather(&n, 1, MPI_INT, sizes.data(), 1, MPI_INT, MPI_COMM_WORLD);
  long long total = 0;
  for (int q = 0; q < size_; ++q) {
    offsets[q] = static_cast<int>(total);
    total += sizes[q];
  }
  if (total > (1LL << 31) - 1) throw std::runtime_error("MPI gather: more than 2 GiB of results");
  std::string all(static_cast<std::size_t>(total), '\0');
  MPI_Allgatherv(mine.data(), n, MPI_BYTE, all.data(), sizes.data(), offsets.data(), MPI_BYTE, MPI_COMM_WORLD);
  std::vector<std::string> out;
  for (int q = 0; q < size_; ++q) out.push_back(all.substr(static_cast<std::size_t>(offsets[q]), static_cast<std::size_t>(sizes[q])));
  return out;
}

void MpiCommunicator::abort(int status) {
  MPI_Abort(MPI_COMM_WORLD, status);
  std::exit(status);
}

}  // namespace lg::uq
