// Output files (sim/io/files.hpp): atomic writes leave no temporary behind, not even under SIGKILL, and
// the temporaries of dead processes are removed when a run prepares its output directory.
#include "sim/io/files.hpp"

#include <signal.h>
#include <sys/wait.h>
#include <unistd.h>

#include <chrono>
#include <filesystem>
#include <string>
#include <thread>
#include <vector>

#include "files_support.hpp"
#include "sim/engine_support.hpp"  // lgtest::report, then Catch

namespace {

namespace fs = std::filesystem;

// The names in 'dir' (recursively) that are temporaries: "<file>.tmp<digits>" or ".write-test<digits>".
std::vector<std::string> temporariesIn(const std::string& dir) {
  std::vector<std::string> out;
  std::error_code ec;
  for (fs::recursive_directory_iterator it(dir, ec), end; !ec && it != end; it.increment(ec)) {
    const std::string n = it->path().filename().string();
    if (n.find(".tmp") != std::string::npos || n.find(".write-test") != std::string::npos) out.push_back(it->path());
  }
  return out;
}

// A pid that belonged to a process which has exited (a child that is reaped).
pid_t deadPid() {
  const pid_t p = ::fork();
  if (p == 0) ::_exit(0);
  int st = 0;
  ::waitpid(p, &st, 0);
  return p;
}

}  // namespace

TEST_CASE("files: an atomic write leaves the file whole and no temporary", "[io][files]") {
  lgtest::TempDir dir("files_atomic");
  const std::string path = dir / "a.txt";
  lg::writeFileAtomic(path, "one\n");
  lg::writeFileAtomic(path, "two\n");
  CHECK(lgtest::readFile(path) == "two\n");
  CHECK(temporariesIn(dir.path.string()).empty());
}

TEST_CASE("files: the temporaries of dead processes are removed, nothing else", "[io][files]") {
  lgtest::TempDir dir("files_stale");
  const std::string dead = std::to_string(deadPid());
  const std::string mine = std::to_string(::getpid());
  for (const std::string& n : std::vector<std::string>{"best.toml.tmp" + dead, ".write-test" + dead, "result.json.tmp" + mine,
                                                      "notes.tmp", "data.tmpx" + dead, "keep.csv"})
    lgtest::writeFile(dir / n, "x");
  lg::prepareOutputDir(dir.path.string());
  CHECK(!fs::exists(dir / ("best.toml.tmp" + dead)));
  CHECK(!fs::exists(dir / (".write-test" + dead)));
  CHECK(fs::exists(dir / ("result.json.tmp" + mine)));  // a live process's: not ours to remove
  CHECK(fs::exists(dir / "notes.tmp"));
  CHECK(fs::exists(dir / ("data.tmpx" + dead)));
  CHECK(fs::exists(dir / "keep.csv"));
}

TEST_CASE("files: simulate killed at any moment leaves no temporary in its output directory", "[io][files][cli]") {
  lgtest::TempDir dir("files_kill");
  const std::string out = dir / "out";
  const std::string scene = lgtest::sourcePath("data/seed_gear.toml");
  const std::string bin = lgtest::binPath("simulate");
  auto start = [&]() {
    const pid_t p = ::fork();
    if (p == 0) {
      ::freopen("/dev/null", "w", stdout);
      ::freopen("/dev/null", "w", stderr);
      ::execl(bin.c_str(), bin.c_str(), scene.c_str(), "--out", out.c_str(), "--threads", "1", "--quiet", "--plots",
              static_cast<char*>(nullptr));
      ::_exit(127);
    }
    return p;
  };
  // One whole run first: the kills then spread over its length, the writes at its end included.
  const auto t0 = std::chrono::steady_clock::now();
  int st = 0;
  ::waitpid(start(), &st, 0);
  REQUIRE((WIFEXITED(st) && WEXITSTATUS(st) == 0));
  const double whole = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  int killedWhileRunning = 0;
  for (int k = 0; k < 40; ++k) {
    const pid_t p = start();
    const double at = whole * (k + 0.5) / 40;
    std::this_thread::sleep_for(std::chrono::duration<double>(at));
    ::kill(p, SIGKILL);
    ::waitpid(p, &st, 0);
    if (WIFSIGNALED(st)) ++killedWhileRunning;
    INFO("kill after " << at << " s of a " << whole << " s run");
    CHECK(temporariesIn(out) == std::vector<std::string>{});
  }
  lgtest::report("files: %d of 40 runs of simulate (%.2f s each) killed while running, none left a temporary",
                 killedWhileRunning, whole);
  CHECK(killedWhileRunning > 20);
}
