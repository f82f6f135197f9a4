#include "deploysim/io/hdf5_writer.h"

#include <cstdint>
#include <functional>
#include <numeric>
#include <optional>
#include <stdexcept>

#include "deploysim/io/atomic_file.h"
#include "deploysim/io/hdf5_common.h"

namespace deploysim::io {

namespace {

using hdf5::QuietErrors;
using hdf5::TextType;

/// Room kept free beyond the current end of the file for the metadata HDF5 may add
/// during the next call and at close (object headers, chunk index nodes, heaps).
constexpr std::uint64_t kMetadataMargin = 256u << 10;
constexpr std::size_t kMaxChunkBytes = 1u << 20;

void WriteTextAttribute(const H5::H5Object& object,
                        const std::string& name,
                        const std::string& value) {
  const H5::StrType type = TextType();
  const H5::Attribute a = object.createAttribute(name, type, H5::DataSpace(H5S_SCALAR));
  a.write(type, ValidUtf8(value));
}

/// A GrowingDoubles dataset.
struct Growing {
  std::string path;
  std::vector<hsize_t> trailing;
  std::size_t width = 1;  // doubles per row
  hsize_t rows = 0;
  std::string units, description;
  std::optional<H5::DataSet> ds;  // none for zero-width rows (made at Close)
};

}  // namespace

std::string ValidUtf8(const std::string& s) {
  std::string out;
  out.reserve(s.size());
  const std::size_t n = s.size();
  auto byte = [&](std::size_t i) { return static_cast<unsigned char>(s[i]); };
  std::size_t i = 0;
  while (i < n) {
    const unsigned char c = byte(i);
    if (c < 0x80) {
      out += static_cast<char>(c);
      ++i;
      continue;
    }
    // Lead byte: length and the allowed range of the second byte (Unicode table 3-7).
    std::size_t len = 0;
    unsigned char lo = 0x80, hi = 0xBF;
    if (c >= 0xC2 && c <= 0xDF) {
      len = 2;
    } else if (c >= 0xE0 && c <= 0xEF) {
      len = 3;
      if (c == 0xE0) lo = 0xA0;  // no overlongs
      if (c == 0xED) hi = 0x9F;  // no surrogates
    } else if (c >= 0xF0 && c <= 0xF4) {
      len = 4;
      if (c == 0xF0) lo = 0x90;  // no overlongs
      if (c == 0xF4) hi = 0x8F;  // <= U+10FFFF
    }
    if (len == 0) {
      out += "\xEF\xBF\xBD";
      ++i;
      continue;
    }
    std::size_t k = 1;
    for (; k < len && i + k < n; ++k) {
      const unsigned char b = byte(i + k);
      const unsigned char l = k == 1 ? lo : 0x80, h = k == 1 ? hi : 0xBF;
      if (b < l || b > h) break;
    }
    if (k == len) {
      out.append(s, i, len);
    } else {
      out += "\xEF\xBF\xBD";  // the maximal subpart s[i, i + k) is one replacement
    }
    i += k;
  }
  return out;
}

struct Hdf5Writer::Impl {
  // A named temporary: HDF5 cannot open an anonymous one (atomic_file.cc).
  explicit Impl(const std::string& path) : target(path), atomic(path, false) {}
  ~Impl() {
    // Close in order (datasets, then the file) and never throw; the temporary then goes
    // with `atomic`.
    try {
      growing.clear();
      if (file) file->close();
    } catch (...) {
    }
  }
  Impl(const Impl&) = delete;
  Impl& operator=(const Impl&) = delete;

  std::string target;
  AtomicFile atomic;
  QuietErrors quiet;
  std::optional<H5::H5File> file;
  std::vector<Growing> growing;
  bool failed = false;
  bool closed = false;

  // Runs f, turning H5::Exception (not a std::exception) into one-line runtime_errors.
  // After a failure nothing more is written.
  void Guard(const std::function<void()>& f) {
    if (failed) throw std::runtime_error(target + ": not written: an earlier write failed");
    if (closed) throw std::logic_error(target + ": Hdf5Writer used after Close()");
    try {
      f();
    } catch (const H5::Exception& e) {
      failed = true;
      hdf5::Throw(target, e);
    } catch (...) {
      failed = true;
      throw;
    }
  }

  // Room for `bytes` more (plus metadata) before HDF5 writes them.
  void Reserve(std::uint64_t bytes) {
    atomic.Reserve(static_cast<std::uint64_t>(file->getFileSize()) + bytes + kMetadataMargin);
  }

  // The group holding `dataset` (made on demand) and the dataset's own name.
  std::pair<H5::Group, std::string> Parent(const std::string& dataset) {
    const std::string path = dataset.front() == '/' ? dataset.substr(1) : dataset;
    H5::Group g = file->openGroup("/");
    std::size_t start = 0;
    for (std::size_t slash = path.find('/'); slash != std::string::npos;
         slash = path.find('/', start)) {
      const std::string name = path.substr(start, slash - start);
      g = g.nameExists(name) ? g.openGroup(name) : g.createGroup(name);
      start = slash + 1;
    }
    return {g, path.substr(start)};
  }

  void FixedDoubles(const std::string& dataset,
                    const std::vector<hsize_t>& dims,
                    const std::vector<double>& data,
                    const std::string& units,
                    const std::string& description) {
    Reserve(8 * data.size());
    auto [group, name] = Parent(dataset);
    const H5::DataSpace space(static_cast<int>(dims.size()), dims.data());
    const H5::DataSet ds = group.createDataSet(name, H5::PredType::IEEE_F64LE, space);
    if (!data.empty()) ds.write(data.data(), H5::PredType::NATIVE_DOUBLE);
    WriteTextAttribute(ds, "units", units);
    WriteTextAttribute(ds, "description", description);
  }
};

Hdf5Writer::Hdf5Writer(const std::string& path) : impl_(std::make_unique<Impl>(path)) {
  // Room for the superblock and what closing an empty file writes: checked before HDF5
  // opens the file (which it cannot then fail to close), and allocated again after,
  // as opening it truncates the temporary and frees the blocks.
  impl_->atomic.Reserve(kMetadataMargin);
  impl_->Guard([&] { impl_->file.emplace(impl_->atomic.temporary_path(), H5F_ACC_TRUNC); });
  impl_->atomic.ReleaseReserve();
  impl_->Guard([&] { impl_->Reserve(0); });
}

Hdf5Writer::~Hdf5Writer() = default;

void Hdf5Writer::Doubles(const std::string& dataset,
                         const std::vector<std::size_t>& dims,
                         const std::vector<double>& data,
                         const std::string& units,
                         const std::string& description) {
  const std::size_t count =
      std::accumulate(dims.begin(), dims.end(), std::size_t{1}, std::multiplies<>());
  if (count != data.size()) {
    throw std::invalid_argument(impl_->target + ": " + dataset + ": " +
                                std::to_string(data.size()) + " values for a shape of " +
                                std::to_string(count));
  }
  impl_->Guard([&] {
    impl_->FixedDoubles(dataset, std::vector<hsize_t>(dims.begin(), dims.end()), data, units,
                        description);
  });
}

std::size_t Hdf5Writer::GrowingDoubles(const std::string& dataset,
                                       const std::vector<std::size_t>& trailing,
                                       const std::string& units,
                                       const std::string& description) {
  Growing g;
  g.path = dataset;
  g.trailing.assign(trailing.begin(), trailing.end());
  g.width = std::accumulate(trailing.begin(), trailing.end(), std::size_t{1}, std::multiplies<>());
  g.units = units;
  g.description = description;
  impl_->Guard([&] {
    if (g.width == 0) return;  // no chunk can have a zero extent: written whole at Close
    impl_->Reserve(0);
    auto [group, name] = impl_->Parent(dataset);
    std::vector<hsize_t> dims{0}, max_dims{H5S_UNLIMITED}, chunk;
    // A power of two, so that blocks of kChunkRows rows fill whole chunks.
    hsize_t chunk_rows = kChunkRows;
    while (chunk_rows > 1 && chunk_rows * 8 * g.width > kMaxChunkBytes) chunk_rows /= 2;
    chunk.push_back(chunk_rows);
    for (hsize_t d : g.trailing) {
      dims.push_back(d);
      max_dims.push_back(d);
      chunk.push_back(d);
    }
    const H5::DataSpace space(static_cast<int>(dims.size()), dims.data(), max_dims.data());
    H5::DSetCreatPropList props;
    props.setChunk(static_cast<int>(chunk.size()), chunk.data());
    // No chunk cache: each append goes to the file at once, so the file grows inside the
    // space Reserve() checked (a cached chunk would be allocated and written later, at
    // eviction or close, where a full disk cannot be reported cleanly). Appends of whole
    // chunks lose nothing by it.
    H5::DSetAccPropList access;
    access.setChunkCache(0, 0, 1.0);
    g.ds = group.createDataSet(name, H5::PredType::IEEE_F64LE, space, props, access);
    WriteTextAttribute(*g.ds, "units", units);
    WriteTextAttribute(*g.ds, "description", description);
  });
  impl_->growing.push_back(std::move(g));
  return impl_->growing.size() - 1;
}

void Hdf5Writer::AppendRows(std::size_t handle, const std::vector<double>& data, std::size_t rows) {
  if (handle >= impl_->growing.size()) {
    throw std::logic_error(impl_->target + ": AppendRows: no such dataset");
  }
  Growing& g = impl_->growing[handle];
  if (data.size() != rows * g.width) {
    throw std::invalid_argument(impl_->target + ": " + g.path + ": " + std::to_string(data.size()) +
                                " values for " + std::to_string(rows) + " rows of " +
                                std::to_string(g.width));
  }
  const hsize_t added = rows;
  if (added == 0) return;
  if (g.width == 0) {
    g.rows += added;
    return;
  }
  impl_->Guard([&] {
    impl_->Reserve(8 * data.size());
    std::vector<hsize_t> size{g.rows + added}, start{g.rows}, count{added};
    for (hsize_t d : g.trailing) {
      size.push_back(d);
      start.push_back(0);
      count.push_back(d);
    }
    g.ds->extend(size.data());
    const H5::DataSpace file_space = g.ds->getSpace();
    file_space.selectHyperslab(H5S_SELECT_SET, count.data(), start.data());
    const H5::DataSpace memory(static_cast<int>(count.size()), count.data());
    g.ds->write(data.data(), H5::PredType::NATIVE_DOUBLE, memory, file_space);
    g.rows += added;
  });
}

void Hdf5Writer::Integers(const std::string& dataset,
                          const std::vector<long long>& data,
                          const std::string& units,
                          const std::string& description) {
  impl_->Guard([&] {
    impl_->Reserve(8 * data.size());
    auto [group, name] = impl_->Parent(dataset);
    const hsize_t n = data.size();
    const H5::DataSet ds = group.createDataSet(name, H5::PredType::STD_I64LE, H5::DataSpace(1, &n));
    if (!data.empty()) ds.write(data.data(), H5::PredType::NATIVE_LLONG);
    WriteTextAttribute(ds, "units", units);
    WriteTextAttribute(ds, "description", description);
  });
}

void Hdf5Writer::Strings(const std::string& dataset,
                         const std::vector<std::string>& values,
                         const std::string& description) {
  impl_->Guard([&] {
    std::vector<std::string> valid;
    std::uint64_t bytes = 0;
    for (const std::string& v : values) {
      valid.push_back(ValidUtf8(v));
      bytes += valid.back().size() + 32;
    }
    impl_->Reserve(bytes);
    auto [group, name] = impl_->Parent(dataset);
    const hsize_t n = valid.size();
    const H5::StrType type = TextType();
    const H5::DataSet ds = group.createDataSet(name, type, H5::DataSpace(1, &n));
    std::vector<const char*> pointers;
    for (const std::string& v : valid) pointers.push_back(v.c_str());
    if (!pointers.empty()) ds.write(pointers.data(), type);
    WriteTextAttribute(ds, "units", "none");
    WriteTextAttribute(ds, "description", description);
  });
}

void Hdf5Writer::Attribute(const std::string& object,
                           const std::string& name,
                           const std::string& value) {
  impl_->Guard([&] {
    impl_->Reserve(value.size() + name.size());
    if (object == "/" || object.empty()) {
      WriteTextAttribute(*impl_->file, name, value);
      return;
    }
    const H5::H5Location& root = *impl_->file;
    if (root.childObjType(object) == H5O_TYPE_GROUP) {
      WriteTextAttribute(impl_->file->openGroup(object), name, value);
    } else {
      WriteTextAttribute(impl_->file->openDataSet(object), name, value);
    }
  });
}

void Hdf5Writer::Close() {
  impl_->Guard([&] {
    for (Growing& g : impl_->growing) {
      if (g.width != 0) continue;
      std::vector<hsize_t> dims{g.rows};
      dims.insert(dims.end(), g.trailing.begin(), g.trailing.end());
      impl_->FixedDoubles(g.path, dims, {}, g.units, g.description);
    }
    impl_->growing.clear();
    impl_->Reserve(0);
    impl_->file->close();
  });
  impl_->file.reset();
  impl_->closed = true;
  impl_->atomic.ReleaseReserve();
}

void Hdf5Writer::Commit() {
  if (!impl_->closed) Close();
  impl_->atomic.Commit();
}

}  // namespace deploysim::io
