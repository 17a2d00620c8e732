// What was run, when, and on which inputs: the provenance block every program writes into its outputs
// (docs/commands.md, "Provenance"). The tool's version and commit are embedded at build time
// (cmake/build_info.cmake: "unknown" outside a git checkout, "<sha>-modified" with uncommitted changes);
// the date is UTC; the command line is the exact one; every input file is named with its SHA-256
// (FIPS 180-4), so that a reviewer can match a report to the files it came from.
//
// The block is the one part of an output that changes from run to run (date, command line); it sits
// apart ("provenance" first in JSON, a "## Provenance" section last in markdown, a "# " comment head in
// TOML) so that a diff can skip it: the rest of every output is bitwise reproducible.
#pragma once

#include <string>
#include <vector>

#include "sim/io/scene.hpp"

namespace lg {

const char* buildVersion();  // "0.2.0"
const char* buildCommit();   // 40 hex digits, with "-modified" for a changed tree, or "unknown"

// The SHA-256 of bytes, as 64 lower-case hex digits.
std::string sha256Hex(const std::string& bytes);
// The SHA-256 of a file's bytes; "unreadable" where it cannot be read.
std::string fileSha256(const std::string& path);

struct InputFile {
  std::string role;    // "scene", "table", "study", "calibration", "measurement"
  std::string path;    // as the run named it
  std::string sha256;  // of its bytes
};

struct Provenance {
  std::string program;        // "certify"
  std::string version, commit;
  std::string date;           // UTC, ISO 8601: 2026-12-04T22:10:03Z
  std::string commandLine;    // the arguments, shell-quoted where needed
  std::vector<InputFile> inputs;
};

// The provenance of this run: the build's version and commit, now, the command line, and the inputs
// hashed now (the same path twice counts once).
Provenance makeProvenance(const std::string& program, int argc, const char* const* argv, const std::vector<InputFile>& inputs);
// The scene file and the table files its document names ("*_table" keys given as paths), relative to
// the scene's folder.
std::vector<InputFile> sceneInputs(const Scene& scene);

// "tool certify 0.2.0 (commit abc...)", for --version and the heads of written scenes.
std::string versionLine(const std::string& program);
// The block as a JSON member, "\"provenance\": {...}" (no trailing comma), indented by 'indent'.
std::string provenanceJson(const Provenance& p, const std::string& indent = "  ");
// The block as a markdown section, "## Provenance" and its list.
std::string provenanceMarkdown(const Provenance& p);
// The block as TOML comment lines, each starting "# ".
std::string provenanceComment(const Provenance& p);

// An output with the block laid in (nothing where 'p' is null): a JSON document's first member, a
// markdown document's section after its title, a TOML document's comment head.
std::string stampJson(const std::string& json, const Provenance* p);
std::string stampMarkdown(const std::string& md, const Provenance* p);
std::string stampToml(const std::string& toml, const Provenance* p);

}  // namespace lg
