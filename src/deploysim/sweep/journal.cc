#include "deploysim/sweep/journal.h"

#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <cstring>
#include <fstream>
#include <iterator>
#include <stdexcept>

#include "deploysim/sweep/case_outcome_table.h"

namespace deploysim::sweep {

namespace {

constexpr char kMagic[8] = {'D', 'S', 'W', 'P', 'J', 'R', 'N', '2'};
constexpr std::size_t kMagicStem = 7;  // "DSWPJRN": a journal of any format version
// The fixed part of the header; the build identity and the header checksum follow.
constexpr std::size_t kFixedHeaderSize = 8 + 8 + 8 + 4 + 4;
constexpr std::size_t kMaxBuildIdLength = 4096;
// Bump when CaseOutcome's record layout or its meaning changes.
// 2: horizon-independent and hinge outcomes; 3: the outcome measured from the motion
constexpr std::uint64_t kRecordLayoutVersion = 3;

constexpr std::uint64_t kFnvOffset = 0xcbf29ce484222325ULL;
constexpr std::uint64_t kFnvPrime = 0x100000001b3ULL;

std::uint64_t Fnv1a(const void* data, std::size_t n, std::uint64_t h = kFnvOffset) {
  const auto* p = static_cast<const unsigned char*>(data);
  for (std::size_t i = 0; i < n; ++i) {
    h ^= p[i];
    h *= kFnvPrime;
  }
  return h;
}

/// Appends / reads fields by memcpy (native byte order).
class Writer {
 public:
  template <typename T>
  void Put(const T& v) {
    const auto* p = reinterpret_cast<const char*>(&v);
    bytes_.insert(bytes_.end(), p, p + sizeof(T));
  }
  /// `n` bytes more at the end, to be filled.
  char* Append(std::size_t n) {
    bytes_.resize(bytes_.size() + n);
    return bytes_.data() + bytes_.size() - n;
  }
  std::vector<char>& bytes() { return bytes_; }

 private:
  std::vector<char> bytes_;
};

class Reader {
 public:
  explicit Reader(const char* p) : p_(p) {}
  template <typename T>
  T Get() {
    T v;
    std::memcpy(&v, p_, sizeof(T));
    p_ += sizeof(T);
    return v;
  }
  /// The next `n` bytes.
  const char* Take(std::size_t n) {
    const char* p = p_;
    p_ += n;
    return p;
  }

 private:
  const char* p_;
};

/// The record's fields are CaseOutcomeTable's stored fields in slot order: the one list
/// that writing and reading both follow (a field added to the table is stored; bump
/// kRecordLayoutVersion).
void PutOutcome(Writer& w, const CaseOutcome& o) {
  for (const CaseOutcomeField* f : CaseOutcomeTable::RecordFields()) {
    f->record.put(o, w.Append(f->record.size));
  }
}

CaseOutcome GetOutcome(Reader& r) {
  CaseOutcome o;
  for (const CaseOutcomeField* f : CaseOutcomeTable::RecordFields()) {
    f->record.get(r.Take(f->record.size), o);
  }
  return o;
}

std::vector<char> Record(std::size_t index, const CaseOutcome& o) {
  Writer w;
  w.Put(static_cast<std::uint64_t>(index));
  PutOutcome(w, o);
  const std::uint64_t sum = Fnv1a(w.bytes().data(), w.bytes().size());
  w.Put(sum);
  return std::move(w.bytes());
}

std::vector<char> Header(std::uint64_t fingerprint,
                         std::size_t case_count,
                         const std::string& build_id) {
  Writer w;
  for (char c : kMagic) w.Put(c);
  w.Put(fingerprint);
  w.Put(static_cast<std::uint64_t>(case_count));
  w.Put(static_cast<std::uint32_t>(JournalRecordSize()));
  w.Put(static_cast<std::uint32_t>(build_id.size()));
  for (char c : build_id) w.Put(c);
  const std::uint64_t sum = Fnv1a(w.bytes().data(), w.bytes().size());
  w.Put(sum);
  return std::move(w.bytes());
}

std::string Errno() { return std::strerror(errno); }

void WriteAll(int fd, const std::vector<char>& bytes, const std::string& path) {
  std::size_t done = 0;
  while (done < bytes.size()) {
    const ssize_t n = ::write(fd, bytes.data() + done, bytes.size() - done);
    if (n < 0) {
      if (errno == EINTR) continue;
      throw std::runtime_error(path + ": cannot write the sweep journal: " + Errno());
    }
    done += static_cast<std::size_t>(n);
  }
}

}  // namespace

std::size_t JournalRecordSize() {
  return sizeof(std::uint64_t) + CaseOutcomeTable::RecordPayloadSize() + sizeof(std::uint64_t);
}

std::vector<char> EncodeRecords(const std::vector<CaseRecord>& records) {
  std::vector<char> bytes;
  bytes.reserve(records.size() * JournalRecordSize());
  for (const CaseRecord& r : records) {
    const std::vector<char> rec = Record(r.first, r.second);
    bytes.insert(bytes.end(), rec.begin(), rec.end());
  }
  return bytes;
}

std::vector<CaseRecord> DecodeRecords(const std::vector<char>& bytes) {
  const std::size_t rs = JournalRecordSize();
  if (bytes.size() % rs != 0) throw std::runtime_error("sweep records: truncated block");
  std::vector<CaseRecord> out;
  for (std::size_t pos = 0; pos < bytes.size(); pos += rs) {
    const char* rec = bytes.data() + pos;
    std::uint64_t sum;
    std::memcpy(&sum, rec + rs - sizeof(sum), sizeof(sum));
    if (Fnv1a(rec, rs - sizeof(sum)) != sum)
      throw std::runtime_error("sweep records: bad checksum");
    Reader r(rec);
    const auto index = r.Get<std::uint64_t>();
    out.emplace_back(static_cast<std::size_t>(index), GetOutcome(r));
  }
  return out;
}

std::uint64_t Fingerprint(const SweepSpec& spec) {
  std::uint64_t h = kFnvOffset;
  auto add = [&h](const std::string& s) {
    const std::uint64_t n = s.size();
    h = Fnv1a(&n, sizeof(n), h);
    h = Fnv1a(s.data(), s.size(), h);
  };
  h = Fnv1a(&kRecordLayoutVersion, sizeof(kRecordLayoutVersion), h);
  add(kBuildId);
  add(spec.text);
  add(spec.base.text);
  add(spec.model_text);
  const std::uint64_t cases = spec.case_count();
  h = Fnv1a(&cases, sizeof(cases), h);
  return h;
}

JournalContents ReadJournal(const std::string& path,
                            std::uint64_t fingerprint,
                            std::size_t case_count,
                            const std::string& build_id) {
  std::ifstream f(path, std::ios::binary);
  if (!f) throw std::runtime_error(path + ": cannot read the sweep journal: " + Errno());
  const std::vector<char> bytes((std::istreambuf_iterator<char>(f)),
                                std::istreambuf_iterator<char>());
  JournalContents out;
  const std::size_t stem = std::min(bytes.size(), kMagicStem);
  if (stem > 0 && std::memcmp(bytes.data(), kMagic, stem) != 0) {
    throw std::runtime_error(path + ": not a deploysim sweep journal");
  }
  if (bytes.size() >= sizeof(kMagic) && bytes[kMagicStem] != kMagic[kMagicStem]) {
    throw std::runtime_error(path +
                             ": the journal was written by another version of deploysim "
                             "(journal format " +
                             std::string(1, bytes[kMagicStem]) + ", this build writes " +
                             std::string(1, kMagic[kMagicStem]) +
                             "): delete it to start the sweep afresh");
  }
  // A header torn by a crash right after creation holds no records: start afresh.
  auto torn_header = [&out, &bytes] {
    out.torn_tail = !bytes.empty();
    return out;
  };
  if (bytes.size() < kFixedHeaderSize) return torn_header();
  Reader h(bytes.data() + sizeof(kMagic));
  const auto file_fingerprint = h.Get<std::uint64_t>();
  const auto file_cases = h.Get<std::uint64_t>();
  const auto record_size = h.Get<std::uint32_t>();
  const auto id_length = h.Get<std::uint32_t>();
  if (id_length > kMaxBuildIdLength) throw std::runtime_error(path + ": corrupt sweep journal");
  const std::size_t header_size = kFixedHeaderSize + id_length + sizeof(std::uint64_t);
  if (bytes.size() < header_size) return torn_header();
  const std::string file_build(bytes.data() + kFixedHeaderSize, id_length);
  std::uint64_t header_sum;
  std::memcpy(&header_sum, bytes.data() + kFixedHeaderSize + id_length, sizeof(header_sum));
  if (Fnv1a(bytes.data(), kFixedHeaderSize + id_length) != header_sum) {
    throw std::runtime_error(path + ": corrupt sweep journal (bad header checksum)");
  }
  if (file_build != build_id) {
    throw std::runtime_error(path + ": the journal was written by another build (" + file_build +
                             "; this is " + build_id +
                             "): finish the sweep with that build, or delete the journal to "
                             "start the sweep afresh");
  }
  if (file_fingerprint != fingerprint || file_cases != case_count ||
      record_size != JournalRecordSize()) {
    throw std::runtime_error(
        path +
        ": the journal belongs to another sweep (the sweep file, its base profile or "
        "model, or the journal layout changed since it was written): delete it to "
        "start the sweep afresh");
  }
  const std::size_t rs = JournalRecordSize();
  std::size_t pos = header_size;
  while (pos + rs <= bytes.size()) {
    const char* rec = bytes.data() + pos;
    std::uint64_t sum;
    std::memcpy(&sum, rec + rs - sizeof(sum), sizeof(sum));
    if (Fnv1a(rec, rs - sizeof(sum)) != sum) break;
    Reader r(rec);
    const auto index = r.Get<std::uint64_t>();
    if (index >= case_count) break;
    out.records.emplace_back(static_cast<std::size_t>(index), GetOutcome(r));
    pos += rs;
  }
  out.valid_bytes = pos;
  out.torn_tail = pos != bytes.size();
  return out;
}

JournalWriter::JournalWriter(std::string path,
                             std::uint64_t fingerprint,
                             std::size_t case_count,
                             const std::string& build_id)
    : path_(std::move(path)) {
  struct stat st {};
  const bool exists = ::stat(path_.c_str(), &st) == 0;
  std::size_t keep = 0;
  if (exists) keep = ReadJournal(path_, fingerprint, case_count, build_id).valid_bytes;
  fd_ = ::open(path_.c_str(), O_WRONLY | O_CREAT | O_CLOEXEC, 0666);
  if (fd_ < 0) throw std::runtime_error(path_ + ": cannot open the sweep journal: " + Errno());
  // Drop a torn tail (or a torn header) so that new records follow whole ones.
  if (::ftruncate(fd_, static_cast<off_t>(keep)) != 0 ||
      ::lseek(fd_, static_cast<off_t>(keep), SEEK_SET) < 0) {
    const std::string err = Errno();
    ::close(fd_);
    throw std::runtime_error(path_ + ": cannot repair the sweep journal: " + err);
  }
  if (keep == 0) {
    WriteAll(fd_, Header(fingerprint, case_count, build_id), path_);
    Sync();
  }
}

JournalWriter::~JournalWriter() {
  if (fd_ >= 0) {
    ::fsync(fd_);
    ::close(fd_);
  }
}

void JournalWriter::Append(std::size_t index, const CaseOutcome& outcome) {
  const std::vector<char> rec = Record(index, outcome);
  const std::lock_guard<std::mutex> lock(mutex_);
  WriteAll(fd_, rec, path_);
}

void JournalWriter::Sync() {
  if (::fsync(fd_) != 0) {
    throw std::runtime_error(path_ + ": cannot flush the sweep journal: " + Errno());
  }
}

}  // namespace deploysim::sweep
