// Writing output files: atomically (a temporary file in the same folder, flushed, synced, then
// renamed over the target) and checked, so that a reader never sees half a file and a full disk is an
// error, never a silent loss.
#pragma once

#include <string>

namespace lg {

// A file stem made from a name: letters, digits, '-', '_' and '.' kept, anything else '_', never empty,
// never starting with '.'; "case" if nothing is left. Names of scenes are checked at load
// (TomlReader::name); this keeps any other text from becoming a path outside the output directory.
std::string safeFileStem(const std::string& name);

// Writes 'text' to 'path' atomically; throws std::runtime_error naming the path and the cause. The
// text goes to an unnamed file of the same folder (O_TMPFILE), named "<path>.tmp<pid>" only once whole
// and synced, then renamed over 'path'; where unnamed files are not available, straight to the named one.
void writeFileAtomic(const std::string& path, const std::string& text);

// Removes the temporaries that killed runs of the programs left in 'dir' ("<file>.tmp<pid>",
// ".write-test<pid>" of a process that no longer exists).
void removeStaleTemporaries(const std::string& dir);

// Creates the output directory (and its parents), removes its stale temporaries and proves it takes a
// file, before any work is done; throws std::runtime_error naming the directory and the cause.
void prepareOutputDir(const std::string& dir);

// A log written line by line as it grows (a study's history.csv): each line goes to the file in one
// write, whole, as soon as it is given, so that a run that stops at any moment leaves every finished
// line behind. A failed write is remembered (error()) and later lines are refused.
class LineLog {
 public:
  LineLog() = default;
  LineLog(const LineLog&) = delete;
  LineLog& operator=(const LineLog&) = delete;
  ~LineLog();
  // Creates (truncates) the file; false with error() set if it cannot.
  bool open(const std::string& path);
  // Appends 'line' and a newline; false with error() set if the write fails (a full disk, say).
  bool write(const std::string& line);
  bool close();
  const std::string& error() const { return error_; }

 private:
  int fd_ = -1;
  std::string path_, error_;
};

}  // namespace lg
