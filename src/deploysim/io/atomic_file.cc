#include "deploysim/io/atomic_file.h"

#include <dirent.h>
#include <fcntl.h>
#include <pthread.h>
#include <sys/resource.h>
#include <sys/stat.h>
#include <unistd.h>

#include <algorithm>
#include <array>
#include <atomic>
#include <cerrno>
#include <csignal>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <limits>
#include <stdexcept>
#include <utility>

namespace deploysim::io {

namespace {

// Why O_TMPFILE: an anonymous temporary is the only kind that nothing can leave behind
// (SIGKILL, OOM killer, power cut), with no cleanup code at all. std::ofstream opens it
// by /proc/self/fd/<n> (the magic link reopens the same inode), and
// linkat(AT_SYMLINK_FOLLOW) from that link gives it a name without privileges
// (AT_EMPTY_PATH would need CAP_DAC_READ_SEARCH). HDF5 cannot use it: 1.10.8's H5Fcreate
// lstat()s the name, finds a symlink and realpath()s it to "<dir>/#<inode> (deleted)",
// which does not exist ("can't retrieve real path for file"); and an unlinked named
// file cannot be linked back (linkat refuses a file with no links unless it was made
// O_TMPFILE and never linked). So HDF5 writes a named temporary, and so does everything
// where O_TMPFILE is refused (EOPNOTSUPP on file systems without it, EISDIR/EINVAL on
// kernels before 3.11) or /proc is missing. Named temporaries are removed by the
// destructor (exceptions), by the signal handlers (SIGINT/SIGTERM/SIGHUP), and, after a
// SIGKILL or a crash, by the next AtomicFile of the same target
// (RemoveStaleTemporaries: a temporary whose process is gone).

/// Distinguishes the temporaries of one process (several files may be written at once).
std::atomic<unsigned long> temporary_counter{0};

constexpr int kMaxCreateAttempts = 100;
constexpr std::size_t kNameMax = 255;  // NAME_MAX of Linux file systems
// Longest "<pid>.<n>.tmp" tail: 10 + 1 + 20 + 4 bytes.
constexpr std::size_t kTailMax = 35;

// ---- live named temporaries, for the signal handlers ----

constexpr std::size_t kSlots = 32;
constexpr std::size_t kSlotPath = 4096;
struct Slot {
  std::atomic<int> state{0};  // 0 free, 1 being filled, 2 holds a path to unlink
  char path[kSlotPath];
};
std::array<Slot, kSlots> slots;
static_assert(std::atomic<int>::is_always_lock_free);

/// Registers `path` for removal by a signal; returns the slot or -1 (no room: then
/// only RemoveStaleTemporaries will clean it after a signal).
int Register(const std::string& path) {
  if (path.size() + 1 > kSlotPath) return -1;
  for (std::size_t i = 0; i < kSlots; ++i) {
    int expected = 0;
    if (slots[i].state.compare_exchange_strong(expected, 1)) {
      std::memcpy(slots[i].path, path.c_str(), path.size() + 1);
      slots[i].state.store(2);
      return static_cast<int>(i);
    }
  }
  return -1;
}

void Unregister(int slot) {
  if (slot >= 0) slots[static_cast<std::size_t>(slot)].state.store(0);
}

bool Registered(const std::string& path) {
  for (Slot& s : slots) {
    if (s.state.load() == 2 && path == s.path) return true;
  }
  return false;
}

extern "C" void RemoveTemporariesAndDie(int signal) {
  for (Slot& s : slots) {
    if (s.state.load() == 2) ::unlink(s.path);
  }
  std::signal(signal, SIG_DFL);
  std::raise(signal);
}

std::string Hex64(std::uint64_t h) {
  static const char* digits = "0123456789abcdef";
  std::string s(16, '0');
  for (int i = 15; i >= 0; --i, h >>= 4) s[static_cast<std::size_t>(i)] = digits[h & 0xf];
  return s;
}

std::string DirName(const std::filesystem::path& dir) {
  return dir.empty() ? std::string(".") : dir.string();
}

/// A named temporary, created O_EXCL, with its signal-handler registration.
struct Named {
  std::string path;
  int fd = -1;
  int slot = -1;
};

/// Creates a named temporary O_EXCL (read-write). The name is registered for the signal
/// handlers *before* the file exists: registered after, a signal arriving between the
/// two would leave the file behind. Unlinking a registered name that was not created yet
/// is harmless (the name carries our pid: no other live process uses it).
Named CreateNamed(const std::string& target,
                  const std::filesystem::path& dir,
                  const std::string& stem) {
  for (int attempt = 0; attempt < kMaxCreateAttempts; ++attempt) {
    const std::string name =
        stem + std::to_string(::getpid()) + "." + std::to_string(temporary_counter++) + ".tmp";
    const std::string candidate = (dir / name).string();
    const int slot = Register(candidate);
    const int fd = ::open(candidate.c_str(), O_RDWR | O_CREAT | O_EXCL | O_CLOEXEC, 0666);
    if (fd >= 0) return {candidate, fd, slot};
    const int err = errno;
    Unregister(slot);
    if (err != EEXIST) {
      throw std::runtime_error(target + ": cannot create a temporary file in " + DirName(dir) +
                               ": " + std::strerror(err));
    }
  }
  throw std::runtime_error(target + ": cannot create a temporary file in " + DirName(dir) +
                           ": too many existing temporaries");
}

/// "<digits>.<digits>.tmp"; sets pid.
bool ParseTail(const std::string& tail, long& pid) {
  std::size_t i = 0;
  auto digits = [&]() {
    const std::size_t start = i;
    while (i < tail.size() && tail[i] >= '0' && tail[i] <= '9') ++i;
    return i > start && i - start <= 20;
  };
  if (!digits()) return false;
  const std::string p = tail.substr(0, i);
  if (p.size() > 10) return false;
  pid = std::stol(p);
  if (i >= tail.size() || tail[i] != '.') return false;
  ++i;
  if (!digits()) return false;
  return tail.substr(i) == ".tmp";
}

}  // namespace

std::string TemporaryStem(const std::string& file_name) {
  if (1 + file_name.size() + 1 + kTailMax <= kNameMax) return "." + file_name + ".";
  // FNV-1a 64 of the whole name: two long names with the same prefix get other stems.
  std::uint64_t h = 1469598103934665603ULL;
  for (unsigned char c : file_name) {
    h ^= c;
    h *= 1099511628211ULL;
  }
  const std::size_t keep = kNameMax - (1 + 1 + 16 + 1 + kTailMax);
  return "." + file_name.substr(0, keep) + "~" + Hex64(h) + ".";
}

int RemoveStaleTemporaries(const std::string& target) {
  const std::filesystem::path t(target);
  const std::string name = t.filename().string();
  if (name.empty()) return 0;
  const std::string stem = TemporaryStem(name);
  const std::string dir = DirName(t.parent_path());
  DIR* d = ::opendir(dir.c_str());
  if (d == nullptr) return 0;
  int removed = 0;
  while (const dirent* e = ::readdir(d)) {
    const std::string entry = e->d_name;
    if (entry.size() <= stem.size() || entry.compare(0, stem.size(), stem) != 0) continue;
    long pid = 0;
    if (!ParseTail(entry.substr(stem.size()), pid) || pid <= 0) continue;
    const std::string path = (t.parent_path() / entry).string();
    bool dead;
    if (pid == static_cast<long>(::getpid())) {
      dead = !Registered(path);  // an earlier process with our pid (a container restart)
    } else {
      // EPERM: alive, another user's; ESRCH: gone.
      dead = ::kill(static_cast<pid_t>(pid), 0) != 0 && errno == ESRCH;
    }
    if (!dead) continue;
    struct stat st {};
    if (::lstat(path.c_str(), &st) == 0 && S_ISREG(st.st_mode) && ::unlink(path.c_str()) == 0) {
      ++removed;
    }
  }
  ::closedir(d);
  return removed;
}

SignalsHeld::SignalsHeld() {
  sigset_t held;
  sigemptyset(&held);
  for (int s : {SIGINT, SIGTERM, SIGHUP}) sigaddset(&held, s);
  ::pthread_sigmask(SIG_BLOCK, &held, &saved_);
}

SignalsHeld::~SignalsHeld() { ::pthread_sigmask(SIG_SETMASK, &saved_, nullptr); }

void RemoveTemporariesOnSignals() {
  struct sigaction sa {};
  sa.sa_handler = RemoveTemporariesAndDie;
  sigemptyset(&sa.sa_mask);
  for (int s : {SIGINT, SIGTERM, SIGHUP}) sigaddset(&sa.sa_mask, s);
  sa.sa_flags = 0;
  for (int s : {SIGINT, SIGTERM, SIGHUP}) ::sigaction(s, &sa, nullptr);
}

AtomicFile::AtomicFile(std::string target, bool allow_anonymous) : target_(std::move(target)) {
  const std::filesystem::path t(target_);
  if (t.filename().empty()) {
    throw std::runtime_error(target_ + ": cannot write: the path names a directory");
  }
  const std::filesystem::path dir = t.parent_path();
  // Up front: an anonymous temporary would only meet the limit at the final rename.
  const long name_max = ::pathconf(DirName(dir).c_str(), _PC_NAME_MAX);
  if (t.filename().string().size() >
      (name_max > 0 ? static_cast<std::size_t>(name_max) : kNameMax)) {
    throw std::runtime_error(target_ + ": cannot write: " + std::strerror(ENAMETOOLONG));
  }
  RemoveStaleTemporaries(target_);
#ifdef O_TMPFILE
  const int fd =
      allow_anonymous ? ::open(DirName(dir).c_str(), O_TMPFILE | O_RDWR | O_CLOEXEC, 0666) : -2;
  if (fd == -2) {
    // a named temporary (below)
  } else if (fd >= 0) {
    const std::string proc = "/proc/self/fd/" + std::to_string(fd);
    if (::access(proc.c_str(), W_OK) == 0) {
      fd_ = fd;
      temporary_ = proc;
      anonymous_ = true;
      return;
    }
    ::close(fd);  // no /proc: a named temporary
  } else if (errno != EOPNOTSUPP && errno != EISDIR && errno != EINVAL) {
    throw std::runtime_error(target_ + ": cannot create a temporary file in " + DirName(dir) +
                             ": " + std::strerror(errno));
  }
#endif
  const Named named = CreateNamed(target_, dir, TemporaryStem(t.filename().string()));
  named_ = named.path;
  temporary_ = named.path;
  fd_ = named.fd;
  slot_ = named.slot;
}

AtomicFile::~AtomicFile() {
  if (!committed_ && !named_.empty()) ::unlink(named_.c_str());
  Unregister(slot_);
  if (fd_ >= 0) ::close(fd_);
}

void AtomicFile::Reserve(std::uint64_t size) {
  if (size <= reserved_) return;
  auto fail = [&](int err) {
    throw std::runtime_error(target_ + ": cannot write: " + std::strerror(err) + " (no room for " +
                             std::to_string(size) + " bytes)");
  };
  rlimit limit{};
  if (::getrlimit(RLIMIT_FSIZE, &limit) != 0) limit.rlim_cur = RLIM_INFINITY;
  if (limit.rlim_cur != RLIM_INFINITY && size > limit.rlim_cur) {
    fail(EFBIG);
  }
  if (size > static_cast<std::uint64_t>(std::numeric_limits<off_t>::max() / 2)) fail(EFBIG);
  // Reserve ahead (an eighth more) so that a file growing by small writes calls
  // fallocate a few dozen times, not at every write; never past the size limit.
  std::uint64_t want = std::max(size, reserved_ + reserved_ / 8);
  if (limit.rlim_cur != RLIM_INFINITY) want = std::min<std::uint64_t>(want, limit.rlim_cur);
  const off_t from = static_cast<off_t>(reserved_);
  const int rc = ::fallocate(fd_, FALLOC_FL_KEEP_SIZE, from, static_cast<off_t>(want) - from);
  if (rc != 0 && errno != EOPNOTSUPP && errno != ENOSYS) fail(errno);
  reserved_ = want;
}

void AtomicFile::ReleaseReserve() {
  if (reserved_ == 0) return;
  struct stat st {};
  // Truncating to the current size frees the blocks allocated past it (KEEP_SIZE).
  if (::fstat(fd_, &st) == 0) {
    if (::ftruncate(fd_, st.st_size) != 0) {
      // Only space is lost: the contents are complete.
    }
  }
  reserved_ = 0;
}

void AtomicFile::Commit() {
  if (::fsync(fd_) != 0) {
    throw std::runtime_error(target_ + ": cannot flush its temporary: " + std::strerror(errno));
  }
  const std::filesystem::path t(target_);
  const std::filesystem::path dir = t.parent_path();
  int slot = -1;
  if (anonymous_) {
    // Give the anonymous file a (named temporary) name, then rename that onto the
    // target: linkat cannot replace an existing file.
    const std::string stem = TemporaryStem(t.filename().string());
    for (int attempt = 0; attempt < kMaxCreateAttempts && named_.empty(); ++attempt) {
      const std::string candidate = (dir / (stem + std::to_string(::getpid()) + "." +
                                            std::to_string(temporary_counter++) + ".tmp"))
                                        .string();
      slot = Register(candidate);
      if (::linkat(AT_FDCWD, temporary_.c_str(), AT_FDCWD, candidate.c_str(), AT_SYMLINK_FOLLOW) ==
          0) {
        named_ = candidate;
        break;
      }
      const int err = errno;
      Unregister(slot);
      slot = -1;
      if (err != EEXIST) {
        throw std::runtime_error(target_ + ": cannot link its temporary into " + DirName(dir) +
                                 ": " + std::strerror(err));
      }
    }
    if (named_.empty()) {
      throw std::runtime_error(target_ + ": cannot link its temporary into " + DirName(dir) +
                               ": too many existing temporaries");
    }
    Unregister(slot_);
    slot_ = slot;
  }
  if (std::rename(named_.c_str(), target_.c_str()) != 0) {
    throw std::runtime_error(target_ + ": cannot rename " + named_ +
                             " onto it: " + std::strerror(errno));
  }
  committed_ = true;
  Unregister(slot_);
  slot_ = -1;
  // Make the rename durable too (best effort: some file systems refuse fsync on a folder).
  const int d = ::open(DirName(dir).c_str(), O_RDONLY | O_DIRECTORY | O_CLOEXEC);
  if (d >= 0) {
    ::fsync(d);
    ::close(d);
  }
}

}  // namespace deploysim::io
