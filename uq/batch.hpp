// Evaluating a batch of independent model runs over MPI ranks and threads, with results that do not
// depend on either count: run k always computes the same bits wherever it runs, every rank gets every
// result in run order, and the estimators (run on the gathered results) reduce in a fixed order.
//
// Distribution: rank q of K takes the runs [q M / K, (q+1) M / K); within a rank, OpenMP threads take
// runs one at a time (dynamic schedule). Nothing here knows MPI: a Communicator does (mpi.hpp).
#pragma once

#include <cstddef>
#include <functional>
#include <string>
#include <vector>

namespace lg::uq {

// One run's outputs (NaN where it failed) and why it failed, if it did ("" otherwise).
struct Outcome {
  std::vector<double> y;
  std::string failure;
};

// The processes of a run. The single-process one is below; the MPI one is in mpi.hpp.
class Communicator {
 public:
  virtual ~Communicator() = default;
  virtual int rank() const = 0;
  virtual int size() const = 0;
  // Every rank's bytes, in rank order, on every rank.
  virtual std::vector<std::string> allGather(const std::string& mine) = 0;
};

class SingleProcess final : public Communicator {
 public:
  int rank() const override { return 0; }
  int size() const override { return 1; }
  std::vector<std::string> allGather(const std::string& mine) override { return {mine}; }
};

// Runs [begin, end) of rank q of K for M runs.
void rankRange(std::size_t runs, int rank, int ranks, std::size_t* begin, std::size_t* end);

// Serialised outcomes (same machine type on every rank).
std::string packOutcomes(const std::vector<Outcome>& v);
std::vector<Outcome> unpackOutcomes(const std::string& bytes);

struct BatchOptions {
  int threads = 1;                                          // OpenMP threads within a rank
  std::function<void(std::size_t done, std::size_t mine)> progress;  // this rank's runs (thread 0 only)
};

// Runs model(k) for k = 0 .. runs-1 spread over the ranks and threads; every rank returns all outcomes.
// 'model' must not throw (an exception becomes the run's failure with every output NaN) and must
// return the same number of outputs for every run ('outputs').
std::vector<Outcome> evaluateBatch(std::size_t runs, std::size_t outputs, const std::function<Outcome(std::size_t)>& model,
                                   Communicator& comm, const BatchOptions& o = {});

}  // namespace lg::uq
