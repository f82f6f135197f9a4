#pragma once

/// HDF5 helpers shared by the files that read or write HDF5 (io's writer and readers,
/// the sweep results reader). Includes H5Cpp.h: include it only from .cc files.

#include <H5Cpp.h>

#include <stdexcept>
#include <string>
#include <vector>

namespace deploysim::io::hdf5 {

/// The description of the innermost entry of the last HDF5 error stack seen by
/// QuietErrors in this thread (where the failure was detected: "unable to extend file
/// properly, errno = 28, ..."); empty if none.
inline std::string& LastInnermostError() {
  thread_local std::string last;
  return last;
}

/// Turns off the HDF5 library's printing of its error stack to stderr while alive
/// (errors reach the caller as exceptions with one-line messages instead; the innermost
/// description is kept for them, LastInnermostError), and restores the previous setting
/// afterwards.
class QuietErrors {
 public:
  QuietErrors() {
    H5Eget_auto2(H5E_DEFAULT, &func_, &data_);
    H5Eset_auto2(H5E_DEFAULT, &QuietErrors::Record, nullptr);
    LastInnermostError().clear();
  }
  ~QuietErrors() { H5Eset_auto2(H5E_DEFAULT, func_, data_); }
  QuietErrors(const QuietErrors&) = delete;
  QuietErrors& operator=(const QuietErrors&) = delete;

 private:
  // Called by HDF5 when an API function fails, before it returns.
  static herr_t Record(hid_t stack, void*) {
    LastInnermostError().clear();
    H5Ewalk2(stack, H5E_WALK_UPWARD, &QuietErrors::First, nullptr);
    return 0;
  }
  static herr_t First(unsigned n, const H5E_error2_t* e, void*) {
    if (n == 0 && e != nullptr && e->desc != nullptr) LastInnermostError() = e->desc;
    return 0;
  }
  H5E_auto2_t func_ = nullptr;
  void* data_ = nullptr;
};

/// The HDF5 C++ API throws H5::Exception (not a std::exception): report it as
/// std::runtime_error "<path>: HDF5 error in <function>: <detail> (<innermost reason>)".
[[noreturn]] inline void Throw(const std::string& path, const H5::Exception& e) {
  std::string reason = LastInnermostError();
  if (reason.size() > 160) reason = reason.substr(0, 160) + "...";
  throw std::runtime_error(path + ": HDF5 error in " + e.getFuncName() + ": " + e.getDetailMsg() +
                           (reason.empty() ? "" : " (" + reason + ")"));
}

/// Variable-length UTF-8 strings, the type of every text dataset and attribute.
inline H5::StrType TextType() {
  H5::StrType type(H5::PredType::C_S1, H5T_VARIABLE);
  type.setCset(H5T_CSET_UTF8);
  return type;
}

/// The values of a string dataset, read as TextType (the caller has checked its type).
inline std::vector<std::string> ReadTextValues(const H5::DataSet& ds) {
  const H5::DataSpace space = ds.getSpace();
  const H5::StrType type = TextType();
  std::vector<char*> buffer(static_cast<std::size_t>(space.getSimpleExtentNpoints()), nullptr);
  std::vector<std::string> values;
  if (!buffer.empty()) {
    ds.read(buffer.data(), type);
    for (char* s : buffer) values.emplace_back(s == nullptr ? "" : s);
    H5::DataSet::vlenReclaim(buffer.data(), type, space);
  }
  return values;
}

}  // namespace deploysim::io::hdf5
