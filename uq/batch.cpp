// Batches of runs over ranks and threads (batch.hpp).
#include "uq/batch.hpp"

#include <atomic>
#include <cstdint>
#include <cstring>
#include <exception>
#include <limits>
#include <stdexcept>

#include <omp.h>

namespace lg::uq {

void rankRange(std::size_t runs, int rank, int ranks, std::size_t* begin, std::size_t* end) {
  const auto q = static_cast<unsigned long long>(rank), k = static_cast<unsigned long long>(ranks);
  *begin = static_cast<std::size_t>(runs * q / k);
  *end = static_cast<std::size_t>(runs * (q + 1) / k);
}

namespace {
void putU64(std::string& s, std::uint64_t v) { s.append(reinterpret_cast<const char*>(&v), sizeof v); }
std::uint64_t getU64(const std::string& s, std::size_t& at) {
  if (at + sizeof(std::uint64_t) > s.size()) throw std::runtime_error("batch: truncated message");
  std::uint64_t v;
  std::memcpy(&v, s.data() + at, sizeof v);
  at += sizeof v;
  return v;
}
}  // namespace

std::string packOutcomes(const std::vector<Outcome>& v) {
  std::string s;
  putU64(s, v.size());
  for (const auto& o : v) {
    putU64(s, o.y.size());
    s.append(reinterpret_cast<const char*>(o.y.data()), o.y.size() * sizeof(double));
    putU64(s, o.failure.size());
    s += o.failure;
  }
  return s;
}

std::vector<Outcome> unpackOutcomes(const std::string& s) {
  std::size_t at = 0;
  std::vector<Outcome> v(getU64(s, at));
  for (auto& o : v) {
    o.y.resize(getU64(s, at));
    const std::size_t bytes = o.y.size() * sizeof(double);
    if (at + bytes > s.size()) throw std::runtime_error("batch: truncated message");
    std::memcpy(o.y.data(), s.data() + at, bytes);
    at += bytes;
    const std::size_t n = getU64(s, at);
    if (at + n > s.size()) throw std::runtime_error("batch: truncated message");
    o.failure = s.substr(at, n);
    at += n;
  }
  return v;
}

std::vector<Outcome> evaluateBatch(std::size_t runs, std::size_t outputs, const std::function<Outcome(std::size_t)>& model,
                                   Communicator& comm, const BatchOptions& o) {
  std::size_t begin, end;
  rankRange(runs, comm.rank(), comm.size(), &begin, &end);
  std::vector<Outcome> mine(end - begin);
  std::atomic<std::size_t> done{0};
  const long n = static_cast<long>(mine.size());
#pragma omp parallel for schedule(dynamic, 1) num_threads(o.threads > 0 ? o.threads : 1)
  for (long k = 0; k < n; ++k) {
    Outcome out;
    try {
      out = model(begin + static_cast<std::size_t>(k));
    } catch (const std::exception& e) {
      out.failure = std::string("exception: ") + e.what();
      out.y.clear();
    } catch (...) {
      out.failure = "unknown exception";
      out.y.clear();
    }
    if (out.y.size() != outputs) {
      out.y.assign(outputs, std::numeric_limits<double>::quiet_NaN());
      if (out.failure.empty()) out.failure = "the model returned a wrong number of outputs";
    }
    mine[static_cast<std::size_t>(k)] = std::move(out);
    const std::size_t d = ++done;
    if (o.progress && omp_get_thread_num() == 0) o.progress(d, mine.size());
  }
  if (comm.size() == 1) return mine;
  std::vector<Outcome> all;
  all.reserve(runs);
  for (const std::string& part : comm.allGather(packOutcomes(mine))) {
    std::vector<Outcome> v = unpackOutcomes(part);
    for (auto& x : v) all.push_back(std::move(x));
  }
  if (all.size() != runs) throw std::runtime_error("batch: gathered " + std::to_string(all.size()) + " of " +
                                                   std::to_string(runs) + " runs");
  return all;
}

}  // namespace lg::uq
