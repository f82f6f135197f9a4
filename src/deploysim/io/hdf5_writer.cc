#include "deploysim/io/hdf5_writer.h"

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

void WriteTextAttribute(const H5::H5Object& object,
                        const std::string& name,
                        const std::string& value) {
  const H5::StrType type = TextType();
  const H5::Attribute a = object.createAttribute(name, type, H5::DataSpace(H5S_SCALAR));
  a.write(type, value);
}

}  // namespace

struct Hdf5Writer::Impl {
  explicit Impl(const std::string& path) : target(path), atomic(path) {}
  std::string target;
  AtomicFile atomic;
  QuietErrors quiet;
  std::optional<H5::H5File> file;

  // Runs f, turning H5::Exception (not a std::exception) into one-line runtime_errors.
  void Guard(const std::function<void()>& f) {
    try {
      f();
    } catch (const H5::Exception& e) {
      hdf5::Throw(target, e);
    }
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
};

Hdf5Writer::Hdf5Writer(const std::string& path) : impl_(std::make_unique<Impl>(path)) {
  impl_->Guard([&] { impl_->file.emplace(impl_->atomic.temporary_path(), H5F_ACC_TRUNC); });
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
    auto [group, name] = impl_->Parent(dataset);
    const std::vector<hsize_t> h(dims.begin(), dims.end());
    const H5::DataSpace space(static_cast<int>(h.size()), h.data());
    const H5::DataSet ds = group.createDataSet(name, H5::PredType::IEEE_F64LE, space);
    if (!data.empty()) ds.write(data.data(), H5::PredType::NATIVE_DOUBLE);
    WriteTextAttribute(ds, "units", units);
    WriteTextAttribute(ds, "description", description);
  });
}

void Hdf5Writer::Integers(const std::string& dataset,
                          const std::vector<long long>& data,
                          const std::string& units,
                          const std::string& description) {
  impl_->Guard([&] {
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
    auto [group, name] = impl_->Parent(dataset);
    const hsize_t n = values.size();
    const H5::StrType type = TextType();
    const H5::DataSet ds = group.createDataSet(name, type, H5::DataSpace(1, &n));
    std::vector<const char*> pointers;
    for (const std::string& v : values) pointers.push_back(v.c_str());
    if (!pointers.empty()) ds.write(pointers.data(), type);
    WriteTextAttribute(ds, "units", "none");
    WriteTextAttribute(ds, "description", description);
  });
}

void Hdf5Writer::Attribute(const std::string& object,
                           const std::string& name,
                           const std::string& value) {
  impl_->Guard([&] {
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

void Hdf5Writer::Commit() {
  impl_->Guard([&] { impl_->file->close(); });
  impl_->file.reset();
  impl_->atomic.Commit();
}

}  // namespace deploysim::io
