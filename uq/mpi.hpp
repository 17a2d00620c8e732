// The MPI communicator (Open MPI or any MPI-3 library): built only where CMake's FindMPI finds one
// (LG_HAVE_MPI), so the programs build and run as one process without it.
#pragma once

#include <memory>

#include "uq/batch.hpp"

namespace lg::uq {

// True when the process was started by an MPI launcher (mpirun / mpiexec set these variables): only
// then is MPI initialised, so a plain run never needs an MPI runtime.
bool launchedByMpi();

// MPI_Init on construction (with MPI_THREAD_FUNNELED: only the main thread calls MPI), MPI_Finalize on
// destruction; MPI_COMM_WORLD.
class MpiCommunicator final : public Communicator {
 public:
  MpiCommunicator(int* argc, char*** argv);
  ~MpiCommunicator() override;
  MpiCommunicator(const MpiCommunicator&) = delete;
  MpiCommunicator& operator=(const MpiCommunicator&) = delete;
  int rank() const override { return rank_; }
  int size() const override { return size_; }
  std::vector<std::string> allGather(const std::string& mine) override;
  // Ends every rank with this status (a rank that fails alone must not leave the others waiting).
  [[noreturn]] void abort(int status);

 private:
  int rank_ = 0, size_ = 1;
};

}  // namespace lg::uq
