#include "deploysim/io/atomic_file.h"

#include <fcntl.h>
#include <unistd.h>

#include <atomic>
#include <cerrno>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <stdexcept>
#include <utility>

namespace deploysim::io {

namespace {

/// Distinguishes the temporaries of one process (several files may be written at once).
std::atomic<unsigned long> temporary_counter{0};

constexpr int kMaxCreateAttempts = 100;

}  // namespace

AtomicFile::AtomicFile(std::string target) : target_(std::move(target)) {
  const std::filesystem::path t(target_);
  if (t.filename().empty()) {
    throw std::runtime_error(target_ + ": cannot write: the path names a directory");
  }
  const std::filesystem::path dir = t.parent_path();
  for (int attempt = 0; attempt < kMaxCreateAttempts; ++attempt) {
    const std::string name = "." + t.filename().string() + "." + std::to_string(::getpid()) + "." +
                             std::to_string(temporary_counter++) + ".tmp";
    const std::string candidate = (dir / name).string();
    const int fd = ::open(candidate.c_str(), O_WRONLY | O_CREAT | O_EXCL | O_CLOEXEC, 0666);
    if (fd >= 0) {
      ::close(fd);
      temporary_ = candidate;
      return;
    }
    if (errno != EEXIST) {
      throw std::runtime_error(target_ + ": cannot create a temporary file in " +
                               (dir.empty() ? std::string(".") : dir.string()) + ": " +
                               std::strerror(errno));
    }
  }
  throw std::runtime_error(target_ + ": cannot create a temporary file in " +
                           (dir.empty() ? std::string(".") : dir.string()) +
                           ": too many existing temporaries");
}

AtomicFile::~AtomicFile() {
  if (!committed_ && !temporary_.empty()) std::remove(temporary_.c_str());
}

void AtomicFile::Commit() {
  const int fd = ::open(temporary_.c_str(), O_RDONLY | O_CLOEXEC);
  if (fd < 0 || ::fsync(fd) != 0) {
    const int err = errno;
    if (fd >= 0) ::close(fd);
    throw std::runtime_error(target_ + ": cannot flush " + temporary_ + ": " + std::strerror(err));
  }
  ::close(fd);
  if (std::rename(temporary_.c_str(), target_.c_str()) != 0) {
    throw std::runtime_error(target_ + ": cannot rename " + temporary_ +
                             " onto it: " + std::strerror(errno));
  }
  committed_ = true;
}

}  // namespace deploysim::io
