// Command-line conventions shared by every program (simulate, certify, optimize, the benchmarks):
// --help and --version answer and exit 0; a usage error prints one line "error: ..." and exits 2;
// --threads N means N threads, 0 all cores; Ctrl-C sets a flag the runs poll, and the program stops
// cleanly with exit status 130.
#pragma once

#include <csignal>
#include <cstdio>
#include <string>
#include <thread>

#include <CLI/CLI.hpp>

#include "sim/io/provenance.hpp"

namespace lg::cli {

constexpr int kOk = 0;            // done
constexpr int kFailed = 1;        // a run failed, or an output could not be written
constexpr int kUsage = 2;         // bad input: nothing written
constexpr int kInterrupted = 130; // Ctrl-C (128 + SIGINT)

// "certify 0.2.0 (commit <sha>)": the version and the commit embedded at build time.
inline std::string version(const std::string& program) { return versionLine(program); }

// A program's CLI::App with --version; its description is the first line of --help.
inline void addVersion(CLI::App& app, const std::string& program) {
  app.set_version_flag("--version", version(program), "print the version and exit");
}

// --threads N, 0 (the default) for all cores.
inline CLI::Option* addThreads(CLI::App& app, int& threads, const std::string& over) {
  return app.add_option("--threads", threads, "threads over " + over + " (default 0: all cores)")
      ->check(CLI::Range(0, 4096));
}
inline int resolveThreads(int threads) {
  return threads > 0 ? threads : static_cast<int>(std::max(1u, std::thread::hardware_concurrency()));
}

// Parses the command line. Returns -1 when the program should go on, else the exit status to return
// (0 after --help or --version, 2 after a usage error, reported as "error: ...").
inline int parse(CLI::App& app, int argc, char** argv) {
  try {
    app.parse(argc, argv);
    return -1;
  } catch (const CLI::CallForHelp& e) {
    return app.exit(e);
  } catch (const CLI::CallForAllHelp& e) {
    return app.exit(e);
  } catch (const CLI::CallForVersion& e) {
    return app.exit(e);
  } catch (const CLI::ParseError& e) {
    std::fprintf(stderr, "error: %s (see --help)\n", e.what());
    return kUsage;
  }
}

// Ctrl-C: the first SIGINT sets the flag (runs poll it and stop cleanly), a second one kills.
inline volatile std::sig_atomic_t gInterrupted = 0;
extern "C" inline void onInterrupt(int) {
  if (gInterrupted) std::_Exit(kInterrupted);
  gInterrupted = 1;
}
inline void installInterruptHandler() { std::signal(SIGINT, onInterrupt); }
inline bool interrupted() { return gInterrupted != 0; }

}  // namespace lg::cli
