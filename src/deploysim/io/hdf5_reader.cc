#include "deploysim/io/hdf5_reader.h"

#include <cerrno>
#include <cstdint>
#include <cstring>
#include <fstream>
#include <functional>
#include <optional>
#include <stdexcept>

#include "deploysim/io/hdf5_common.h"

namespace deploysim::io {

namespace {

std::string ReadStringAttribute(const H5::Attribute& a) {
  std::string value;
  a.read(a.getStrType(), value);
  return value;
}

}  // namespace

struct Hdf5Reader::Impl {
  std::string path;
  hdf5::QuietErrors quiet;
  std::optional<H5::H5File> file;

  // Runs f, turning H5::Exception (not a std::exception) into one-line runtime_errors.
  template <typename F>
  auto Guard(const F& f) const -> decltype(f()) {
    try {
      return f();
    } catch (const H5::Exception& e) {
      hdf5::Throw(path, e);
    }
  }

  // The object at `name` with its attributes: the root, a group or a dataset.
  template <typename F>
  auto WithObject(const std::string& name, const F& f) const -> decltype(f(*file)) {
    return Guard([&] {
      if (name.empty() || name == "/") return f(*file);
      const H5::H5Location& root = *file;
      if (root.childObjType(name) == H5O_TYPE_GROUP) return f(file->openGroup(name));
      return f(file->openDataSet(name));
    });
  }
};

Hdf5Reader::Hdf5Reader(const std::string& path) : impl_(std::make_unique<Impl>()) {
  impl_->path = path;
  {
    std::ifstream probe(path, std::ios::binary);
    if (!probe) throw std::runtime_error(path + ": cannot read: " + std::strerror(errno));
  }
  if (H5Fis_hdf5(path.c_str()) <= 0) throw std::runtime_error(path + ": not an HDF5 file");
  impl_->Guard([&] { impl_->file.emplace(path, H5F_ACC_RDONLY); });
}

Hdf5Reader::~Hdf5Reader() = default;

const std::string& Hdf5Reader::path() const { return impl_->path; }

bool Hdf5Reader::Exists(const std::string& object) const {
  return impl_->Guard([&] {
    // Every link on the way must exist (H5Lexists does not look past a missing group).
    const std::string p = object.front() == '/' ? object.substr(1) : object;
    std::string prefix;
    std::size_t start = 0;
    for (;;) {
      const std::size_t slash = p.find('/', start);
      prefix = p.substr(0, slash);
      if (!impl_->file->nameExists(prefix)) return false;
      if (slash == std::string::npos) return true;
      start = slash + 1;
    }
  });
}

Hdf5Reader::Kind Hdf5Reader::KindOf(const std::string& dataset) const {
  return impl_->Guard([&] {
    switch (impl_->file->openDataSet(dataset).getTypeClass()) {
      case H5T_FLOAT:
        return Kind::kFloat;
      case H5T_INTEGER:
        return Kind::kInteger;
      case H5T_STRING:
        return Kind::kText;
      default:
        return Kind::kOther;
    }
  });
}

std::map<std::string, std::string> Hdf5Reader::Attributes(const std::string& object) const {
  return impl_->WithObject(object, [](const H5::H5Object& o) {
    std::map<std::string, std::string> out;
    for (int k = 0; k < o.getNumAttrs(); ++k) {
      const H5::Attribute a = o.openAttribute(static_cast<unsigned>(k));
      if (a.getTypeClass() == H5T_STRING) out[a.getName()] = ReadStringAttribute(a);
    }
    return out;
  });
}

std::string Hdf5Reader::Attribute(const std::string& object, const std::string& name) const {
  return impl_->WithObject(object, [&](const H5::H5Object& o) {
    if (!o.attrExists(name)) {
      throw std::runtime_error(impl_->path + ": " + object + ": no attribute " + name);
    }
    return ReadStringAttribute(o.openAttribute(name));
  });
}

std::vector<double> Hdf5Reader::Numbers(const std::string& dataset) const {
  return impl_->Guard([&] {
    const H5::DataSet ds = impl_->file->openDataSet(dataset);
    const auto n = static_cast<std::size_t>(ds.getSpace().getSimpleExtentNpoints());
    std::vector<double> v(n);
    if (ds.getTypeClass() == H5T_INTEGER) {
      std::vector<std::int64_t> iv(n);
      if (n > 0) ds.read(iv.data(), H5::PredType::NATIVE_INT64);
      for (std::size_t k = 0; k < n; ++k) v[k] = static_cast<double>(iv[k]);
    } else if (ds.getTypeClass() == H5T_FLOAT) {
      if (n > 0) ds.read(v.data(), H5::PredType::NATIVE_DOUBLE);
    } else {
      throw std::runtime_error(impl_->path + ": " + dataset + ": expected numbers");
    }
    return v;
  });
}

std::vector<std::string> Hdf5Reader::Strings(const std::string& dataset) const {
  return impl_->Guard([&] {
    const H5::DataSet ds = impl_->file->openDataSet(dataset);
    if (ds.getTypeClass() != H5T_STRING) {
      throw std::runtime_error(impl_->path + ": " + dataset + ": expected strings");
    }
    return hdf5::ReadTextValues(ds);
  });
}

}  // namespace deploysim::io
