// `sensitivity` under Open MPI: 2 and 3 ranks on this machine write exactly the bytes that one process
// writes (every CSV, the JSON, the report and the gnuplot data). CI runs as root on 2 cores, so the
// command allows root and oversubscribes. Built only with MPI (tests/CMakeLists.txt: without it, a
// test says that these were skipped).
#ifdef LG_MPIEXEC
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <set>
#include <sstream>
#include <string>

#include <sys/wait.h>
#include <unistd.h>

#include "files_support.hpp"  // TempDir, readFile, writeFile

// After the project headers: glog (through Ceres) defines CHECK too; Catch's must win.
#include <catch2/catch.hpp>

namespace fs = std::filesystem;

namespace {

// This test process's temporary directory (removed when it exits).
fs::path tempDir() {
  static const lgtest::TempDir dir("sensitivity_mpi_test");
  return dir.path;
}

using lgtest::readFile;

// Every regular file under dir, by its relative path.
std::set<std::string> files(const fs::path& dir) {
  std::set<std::string> out;
  for (const auto& e : fs::recursive_directory_iterator(dir))
    if (e.is_regular_file()) out.insert(fs::relative(e.path(), dir).string());
  return out;
}

int run(const std::string& cmd) {
  const int status = std::system(cmd.c_str());
  return WIFEXITED(status) ? WEXITSTATUS(status) : -1;
}

}  // namespace

TEST_CASE("sensitivity MPI: 2 and 3 ranks write the same bytes as one process", "[optim][sensitivity][mpi]") {
  const fs::path dir = tempDir();
  const std::string scene = std::string(LG_SOURCE_DIR) + "/data/seed_gear.toml";
  const fs::path studyPath = dir / "mpi.cfg";
  std::ofstream(studyPath) << "scene = \"" << scene << "\"\n[solver]\nintegrator = \"ros34pw2\"\nrtol = 3e-3\n"
                           << "[[variable]]\npath = \"strut.f1\"\nlower = 5e-5\nupper = 1e-4\nlog = true\n"
                           << "[[variable]]\npath = \"strut.Omega0\"\nlower = 1.2e-3\nupper = 1.6e-3\ninitial = 1.3e-3\n"
                           << "[[case]]\nname = \"cert-limit-landing\"\n[[case]]\nname = \"cert-reserve\"\n"
                           << "[sensitivity]\nmetrics = [\"peak_load\", \"stroke\"]\ntrajectories = 4\nsamples = 16\n";
  const std::string exe = std::string(LG_BIN_DIR) + "/sensitivity '" + studyPath.string() + "' --quiet 2>>'" + (dir / "stderr.log").string() + "'";
  const fs::path one = dir / "one";
  REQUIRE(run(exe + " --threads 1 --out '" + one.string() + "'") == 0);
  const std::set<std::string> expected = files(one);
  CHECK(expected.count("indices.json") == 1);
  CHECK(expected.count("samples_sobol.csv") == 1);
  // with failed runs in it: Omega0 below 1.2566e-3 m^3 is rejected by the scene
  CHECK(readFile(one / "indices.json").find("the scene rejects the design") != std::string::npos);
  for (int ranks : {2, 3}) {
    const fs::path out = dir / ("ranks" + std::to_string(ranks));
    const std::string cmd = "OMPI_ALLOW_RUN_AS_ROOT=1 OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1 OMPI_MCA_rmaps_base_oversubscribe=1 " +
                            std::string(LG_MPIEXEC) + " --allow-run-as-root --oversubscribe -n " + std::to_string(ranks) +
                            " " + exe + " --threads 2 --out '" + out.string() + "'";
    INFO(cmd);
    REQUIRE(run(cmd) == 0);
    CHECK(files(out) == expected);
    for (const std::string& f : expected) {
      INFO(ranks << " ranks: " << f);
      CHECK(lgtest::withoutProvenance(readFile(out / f)) == lgtest::withoutProvenance(readFile(one / f)));
    }
  }
}
#endif
