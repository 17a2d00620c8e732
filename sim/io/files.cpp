// Atomic, checked file writes (files.hpp).
#include "sim/io/files.hpp"

#include <fcntl.h>
#include <signal.h>
#include <unistd.h>

#include <cctype>
#include <cerrno>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <stdexcept>

namespace lg {

std::string safeFileStem(const std::string& name) {
  std::string s;
  for (unsigned char c : name) s += (std::isalnum(c) || c == '-' || c == '_' || c == '.') ? static_cast<char>(c) : '_';
  while (!s.empty() && s[0] == '.') s[0] = '_';
  return s.empty() ? "case" : s;
}

namespace {

// Writes all of 'text' to fd and syncs it; false with errno set on a failure.
bool writeAll(int fd, const std::string& text) {
  size_t done = 0;
  while (done < text.size()) {
    const ssize_t n = ::write(fd, text.data() + done, text.size() - done);
    if (n < 0) {
      if (errno == EINTR) continue;
      return false;
    }
    done += static_cast<size_t>(n);
  }
  return ::fsync(fd) == 0 || errno == EINVAL || errno == EROFS;
}

// "best.toml.tmp1234": the temporary of process 1234 (also the form a killed run may have left).
std::string temporaryOf(const std::string& path) { return path + ".tmp" + std::to_string(::getpid()); }

// The temporary written as an unnamed file of the target's folder (O_TMPFILE) and given its name only
// once whole: a kill while it is written leaves nothing behind. False where the file system or the
// kernel has no unnamed files (then the caller writes a named temporary).
bool writeUnnamed(const std::string& path, const std::string& tmp, const std::string& text, std::string& why) {
#ifdef O_TMPFILE
  std::string dir = std::filesystem::path(path).parent_path().string();
  if (dir.empty()) dir = ".";
  const int fd = ::open(dir.c_str(), O_TMPFILE | O_WRONLY | O_CLOEXEC, 0644);
  if (fd < 0) return false;
  if (!writeAll(fd, text)) {
    why = std::string("write: ") + std::strerror(errno);
    ::close(fd);
    return true;
  }
  const std::string self = "/proc/self/fd/" + std::to_string(fd);
  const bool linked = ::linkat(fd, "", AT_FDCWD, tmp.c_str(), AT_EMPTY_PATH) == 0 ||
                      ::linkat(AT_FDCWD, self.c_str(), AT_FDCWD, tmp.c_str(), AT_SYMLINK_FOLLOW) == 0;
  ::close(fd);
  return linked;
#else
  (void)path, (void)tmp, (void)text, (void)why;
  return false;
#endif
}

}  // namespace

void writeFileAtomic(const std::string& path, const std::string& text) {
  const std::string tmp = temporaryOf(path);
  auto fail = [&](const std::string& what) {
    ::unlink(tmp.c_str());
    throw std::runtime_error("cannot write '" + path + "': " + what);
  };
  std::string why;
  if (!writeUnnamed(path, tmp, text, why)) {
    const int fd = ::open(tmp.c_str(), O_WRONLY | O_CREAT | O_TRUNC | O_CLOEXEC, 0644);
    if (fd < 0) fail(std::string("open: ") + std::strerror(errno));
    if (!writeAll(fd, text)) {
      why = std::string("write: ") + std::strerror(errno);
      ::close(fd);
    } else if (::close(fd) != 0) {
      why = std::string("close: ") + std::strerror(errno);
    }
  }
  if (!why.empty()) fail(why);
  if (::rename(tmp.c_str(), path.c_str()) != 0) fail(std::string("rename: ") + std::strerror(errno));
}

void removeStaleTemporaries(const std::string& dir) {
  namespace fs = std::filesystem;
  std::error_code ec;
  for (fs::directory_iterator it(dir, ec), end; !ec && it != end; it.increment(ec)) {
    const std::string name = it->path().filename().string();
    const auto at = name.rfind(".tmp") != std::string::npos ? name.rfind(".tmp") + 4
                    : name.rfind(".write-test", 0) == 0    ? std::string(".write-test").size()
                                                            : std::string::npos;
    if (at == std::string::npos || at >= name.size() ||
        name.find_first_not_of("0123456789", at) != std::string::npos)
      continue;
    const long pid = std::strtol(name.c_str() + at, nullptr, 10);
    if (pid > 0 && pid != ::getpid() && ::kill(static_cast<pid_t>(pid), 0) != 0 && errno == ESRCH) {
      std::error_code rm;
      fs::remove(it->path(), rm);
    }
  }
}

void prepareOutputDir(const std::string& dir) {
  namespace fs = std::filesystem;
  std::error_code ec;
  fs::create_directories(dir, ec);
  if (ec || !fs::is_directory(dir, ec))
    throw std::runtime_error("cannot create the output directory '" + dir + "'" + (ec ? ": " + ec.message() : std::string()));
  removeStaleTemporaries(dir);
  const std::string probe = (fs::path(dir) / (".write-test" + std::to_string(::getpid()))).string();
  writeFileAtomic(probe, "probe\n");
  fs::remove(probe, ec);
}

LineLog::~LineLog() { close(); }

bool LineLog::open(const std::string& path) {
  close();
  path_ = path;
  error_.clear();
  fd_ = ::open(path.c_str(), O_WRONLY | O_CREAT | O_TRUNC | O_CLOEXEC, 0644);
  if (fd_ < 0) error_ = "cannot write '" + path + "': open: " + std::strerror(errno);
  return fd_ >= 0;
}

bool LineLog::write(const std::string& line) {
  if (fd_ < 0 || !error_.empty()) {
    if (error_.empty()) error_ = "cannot write '" + path_ + "': not open";
    return false;
  }
  const std::string text = line + "\n";
  size_t done = 0;
  while (done < text.size()) {
    const ssize_t n = ::write(fd_, text.data() + done, text.size() - done);
    if (n < 0 && errno == EINTR) continue;
    if (n <= 0) {
      error_ = "cannot write '" + path_ + "': write: " + std::strerror(n < 0 ? errno : ENOSPC);
      return false;
    }
    done += static_cast<size_t>(n);
  }
  return true;
}

bool LineLog::close() {
  if (fd_ < 0) return error_.empty();
  const bool ok = ::close(fd_) == 0;
  if (!ok && error_.empty()) error_ = "cannot write '" + path_ + "': close: " + std::strerror(errno);
  fd_ = -1;
  return ok && error_.empty();
}

}  // namespace lg
