#pragma once

/// HDF5 helpers shared by the files that read or write HDF5 (io's writer and readers,
/// the sweep results reader). Includes H5Cpp.h: include it only from .cc files.

#include <H5Cpp.h>

#include <stdexcept>
#include <string>

namespace deploysim::io::hdf5 {

/// Turns off the HDF5 library's printing of its error stack to stderr while alive
/// (errors reach the caller as exceptions with one-line messages instead), and restores
/// the previous setting afterwards.
class QuietErrors {
 public:
  QuietErrors() {
    H5Eget_auto2(H5E_DEFAULT, &func_, &data_);
    H5Eset_auto2(H5E_DEFAULT, nullptr, nullptr);
  }
  ~QuietErrors() { H5Eset_auto2(H5E_DEFAULT, func_, data_); }
  QuietErrors(const QuietErrors&) = delete;
  QuietErrors& operator=(const QuietErrors&) = delete;

 private:
  H5E_auto2_t func_ = nullptr;
  void* data_ = nullptr;
};

/// The HDF5 C++ API throws H5::Exception (not a std::exception): report it as
/// std::runtime_error "<path>: HDF5 error in <function>: <detail>".
[[noreturn]] inline void Throw(const std::string& path, const H5::Exception& e) {
  throw std::runtime_error(path + ": HDF5 error in " + e.getFuncName() + ": " + e.getDetailMsg());
}

/// Variable-length UTF-8 strings, the type of every text dataset and attribute.
inline H5::StrType TextType() {
  H5::StrType type(H5::PredType::C_S1, H5T_VARIABLE);
  type.setCset(H5T_CSET_UTF8);
  return type;
}

}  // namespace deploysim::io::hdf5
