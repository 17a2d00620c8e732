// Batches over ranks and threads: the same outcomes in run order for any count. Ranks are simulated
// here by threads sharing a gather (the MPI runs themselves are tests/optim/sensitivity_mpi_test.cpp).
#include <cmath>
#include <condition_variable>
#include <cstring>
#include <mutex>
#include <stdexcept>
#include <string>
#include <thread>
#include <vector>

#include "uq/batch.hpp"

#include <catch2/catch.hpp>

using namespace lg::uq;

namespace {

// K "ranks" in one process: allGather waits for all of them (one gather at a time, any number of times).
struct Hub {
  explicit Hub(int k) : parts(static_cast<std::size_t>(k)), ranks(k) {}
  std::mutex m;
  std::condition_variable cv;
  std::vector<std::string> parts;
  int arrived = 0, generation = 0, ranks;
};

class ThreadRank final : public Communicator {
 public:
  ThreadRank(Hub& h, int rank) : h_(h), rank_(rank) {}
  int rank() const override { return rank_; }
  int size() const override { return h_.ranks; }
  std::vector<std::string> allGather(const std::string& mine) override {
    std::unique_lock<std::mutex> lock(h_.m);
    const int gen = h_.generation;
    h_.parts[static_cast<std::size_t>(rank_)] = mine;
    if (++h_.arrived == h_.ranks) {
      h_.arrived = 0;
      ++h_.generation;
      h_.cv.notify_all();
    } else {
      h_.cv.wait(lock, [&] { return h_.generation != gen; });
    }
    return h_.parts;
  }

 private:
  Hub& h_;
  int rank_;
};

Outcome model(std::size_t k) {
  Outcome o;
  o.y = {std::sin(0.37 * static_cast<double>(k)), static_cast<double>(k * k)};
  if (k % 7 == 3) {
    o.y[1] = std::nan("");
    o.failure = "run " + std::to_string(k) + " failed";
  }
  return o;
}

bool same(const std::vector<Outcome>& a, const std::vector<Outcome>& b) {
  if (a.size() != b.size()) return false;
  for (std::size_t k = 0; k < a.size(); ++k) {
    if (a[k].failure != b[k].failure || a[k].y.size() != b[k].y.size()) return false;
    if (std::memcmp(a[k].y.data(), b[k].y.data(), a[k].y.size() * sizeof(double)) != 0) return false;
  }
  return true;
}

}  // namespace

TEST_CASE("batch: outcomes in run order, the same bits on 1 and 2 threads and on 1, 2 and 3 ranks", "[uq][batch]") {
  const std::size_t runs = 50;
  SingleProcess one;
  const std::vector<Outcome> ref = evaluateBatch(runs, 2, model, one, BatchOptions{1, {}});
  REQUIRE(ref.size() == runs);
  CHECK(ref[3].failure == "run 3 failed");
  CHECK(same(ref, evaluateBatch(runs, 2, model, one, BatchOptions{2, {}})));
  for (int k : {2, 3}) {
    Hub hub(k);
    std::vector<std::vector<Outcome>> got(static_cast<std::size_t>(k));
    std::vector<std::thread> ranks;
    for (int q = 0; q < k; ++q)
      ranks.emplace_back([&, q] {
        ThreadRank c(hub, q);
        got[static_cast<std::size_t>(q)] = evaluateBatch(runs, 2, model, c, BatchOptions{2, {}});
      });
    for (auto& t : ranks) t.join();
    for (int q = 0; q < k; ++q) CHECK(same(ref, got[static_cast<std::size_t>(q)]));
  }
}

TEST_CASE("batch: ranges cover the runs once, and a throwing or short model is a failed run", "[uq][batch]") {
  std::size_t covered = 0, last = 0;
  for (int q = 0; q < 3; ++q) {
    std::size_t b, e;
    rankRange(10, q, 3, &b, &e);
    CHECK(b == last);
    covered += e - b;
    last = e;
  }
  CHECK(covered == 10);
  SingleProcess one;
  const auto out = evaluateBatch(3, 2, [](std::size_t k) -> Outcome {
    if (k == 1) throw std::runtime_error("boom");
    if (k == 2) return Outcome{{1.0}, ""};
    return Outcome{{1.0, 2.0}, ""};
  }, one);
  CHECK(out[0].failure.empty());
  CHECK(out[1].failure == "exception: boom");
  CHECK(std::isnan(out[1].y[0]));
  CHECK(out[2].y.size() == 2);
  CHECK_FALSE(out[2].failure.empty());
  CHECK(same(unpackOutcomes(packOutcomes(out)), out));  // the bytes a rank sends: the same bits back
}
