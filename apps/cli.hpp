// Command-line conventions shared by every program (simulate, certify, optimize, sensitivity, calibrate,
// the benchmarks): --help and --version answer and exit 0; a usage error prints one line
// "error: command line: key '--flag': <rule>" and exits 2 with nothing written; --threads N means N
// threads, 0 all cores; Ctrl-C sets a flag the runs poll, and the program stops cleanly with exit
// status 130.
//
// The words of an error are the project's, never the argument parser's: parse() reads the command line
// itself first (every option known, every value present and non-empty, a single-valued option given
// once, the positional arguments counted), and every typed value is converted by the add* declarations
// below, which state their rule. The parser (CLI11) then only assigns what was already checked and
// writes --help.
#pragma once

#include <csignal>
#include <string>
#include <vector>

#include <CLI/CLI.hpp>

namespace lg::cli {

constexpr int kOk = 0;            // done
constexpr int kFailed = 1;        // a run failed, or an output could not be written
constexpr int kUsage = 2;         // bad input: nothing written
constexpr int kInterrupted = 130; // Ctrl-C (128 + SIGINT)

// "certify 0.2.0 (commit <sha>)": the version and the commit embedded at build time.
std::string version(const std::string& program);
// A program's CLI::App with --version; its description is the first line of --help.
void addVersion(CLI::App& app, const std::string& program);

// ---- options, each read by its own rule ------------------------------------------------------------
// An integer in [lo, hi]; 'note' follows the rule in an error (e.g. "0: all cores").
CLI::Option* addInteger(CLI::App& app, const std::string& name, long long& target, const std::string& help,
                        long long lo, long long hi, const std::string& note = "");
CLI::Option* addInteger(CLI::App& app, const std::string& name, int& target, const std::string& help, long long lo,
                        long long hi, const std::string& note = "");
// A finite number > 0 ('positive') or any finite number; 'unit' is named in errors and help ("s", "").
CLI::Option* addNumber(CLI::App& app, const std::string& name, double& target, const std::string& help,
                       bool positive, const std::string& unit = "");
// One of 'choices' (exactly as written).
CLI::Option* addChoice(CLI::App& app, const std::string& name, std::string& target, const std::string& help,
                       const std::vector<std::string>& choices);
// A non-empty text (a name, a path, a list the program reads itself), given once.
CLI::Option* addText(CLI::App& app, const std::string& name, std::string& target, const std::string& help);
// A non-empty text per occurrence, repeatable ("--set a=1 --set b=2").
CLI::Option* addTexts(CLI::App& app, const std::string& name, std::vector<std::string>& target,
                      const std::string& help);
// The required positional input file, named 'name' in errors ("scene", "study", "calibration").
CLI::Option* addInputFile(CLI::App& app, const std::string& name, std::string& target, const std::string& help);
// --threads N, 0 (the default) for all cores.
CLI::Option* addThreads(CLI::App& app, int& threads, const std::string& over);
int resolveThreads(int threads);

// The rule an add* declaration states, as the error text after "key '--flag': " (exposed for tests).
std::string integerError(const std::string& text, long long lo, long long hi, const std::string& note, long long* value);
std::string numberError(const std::string& text, bool positive, const std::string& unit, double* value);

// Parses the command line. Returns -1 when the program should go on, else the exit status to return
// (0 after --help or --version, 2 after a usage error, reported as one "error: command line: ..." line).
// 'speak' false: the same answer, nothing printed (the MPI ranks other than 0).
int parse(CLI::App& app, int argc, char** argv, bool speak = true);

// Ctrl-C: the first SIGINT sets the flag (runs poll it and stop cleanly), a second one kills.
inline volatile std::sig_atomic_t gInterrupted = 0;
extern "C" inline void onInterrupt(int) {
  if (gInterrupted) std::_Exit(kInterrupted);
  gInterrupted = 1;
}
inline void installInterruptHandler() { std::signal(SIGINT, onInterrupt); }
inline bool interrupted() { return gInterrupted != 0; }

}  // namespace lg::cli
