// Atomic, checked file writes (files.hpp).
#include "sim/io/files.hpp"

#include <fcntl.h>
#include <unistd.h>

#include <cctype>
#include <cerrno>
#include <cstdio>
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

void writeFileAtomic(const std::string& path, const std::string& text) {
  const std::string tmp = path + ".tmp" + std::to_string(::getpid());
  auto fail = [&](const char* what, int err) {
    ::unlink(tmp.c_str());
    throw std::runtime_error("cannot write '" + path + "': " + what + ": " + std::strerror(err));
  };
  const int fd = ::open(tmp.c_str(), O_WRONLY | O_CREAT | O_TRUNC | O_CLOEXEC, 0644);
  if (fd < 0) fail("open", errno);
  size_t done = 0;
  while (done < text.size()) {
    const ssize_t n = ::write(fd, text.data() + done, text.size() - done);
    if (n < 0) {
      if (errno == EINTR) continue;
      const int err = errno;
      ::close(fd);
      fail("write", err);
    }
    done += static_cast<size_t>(n);
  }
  if (::fsync(fd) != 0 && errno != EINVAL && errno != EROFS) {
    const int err = errno;
    ::close(fd);
    fail("sync", err);
  }
  if (::close(fd) != 0) fail("close", errno);
  if (::rename(tmp.c_str(), path.c_str()) != 0) fail("rename", errno);
}

void prepareOutputDir(const std::string& dir) {
  namespace fs = std::filesystem;
  std::error_code ec;
  fs::create_directories(dir, ec);
  if (ec || !fs::is_directory(dir, ec))
    throw std::runtime_error("cannot create the output directory '" + dir + "'" + (ec ? ": " + ec.message() : std::string()));
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
