#pragma once

// numpy arrays from the library's containers. Arrays of Vec3 and Mat3 and of doubles
// are handed to numpy without a copy (the vector is moved into a capsule that owns it);
// quaternions are copied into (w, x, y, z) order (Eigen stores x, y, z, w).

#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>

#include <Eigen/Core>
#include <chrono>
#include <string>
#include <vector>

#include "deploysim/math/types.h"

namespace deploysim::python {

/// (N,) float64, owning `v`.
pybind11::array_t<double> Doubles(std::vector<double>&& v);
/// (N,) float64, a copy.
pybind11::array_t<double> DoublesCopy(const std::vector<double>& v);
/// (N, 3), owning `v`.
pybind11::array_t<double> Vec3s(std::vector<math::Vec3>&& v);
/// (N, 3, 3) with [n][i][j] = J_n(i, j), owning `v` (a strided view of Eigen's
/// column-major storage: values identical, no arithmetic).
pybind11::array_t<double> Mat3s(std::vector<math::Mat3>&& v);
/// (N, 4) scalar first (w, x, y, z).
pybind11::array_t<double> Quats(const std::vector<math::Quat>& v);
/// (N, P) from rows of equal length P (P = 0 if there are no rows).
pybind11::array_t<double> Rows(const std::vector<Eigen::VectorXd>& rows);
/// (3,) and (3, 3) copies; (4,) w, x, y, z.
pybind11::array_t<double> Vec(const math::Vec3& v);
pybind11::array_t<double> Mat(const math::Mat3& J);
pybind11::array_t<double> QuatArray(const math::Quat& q);

/// A 3-vector from any sequence or array of 3 numbers; throws ValueError naming `what`.
math::Vec3 ToVec3(const pybind11::handle& h, const std::string& what);
/// A 3x3 matrix from a (3, 3) array or nested sequence, or a diagonal from 3 numbers.
math::Mat3 ToMat3(const pybind11::handle& h, const std::string& what);
/// A unit quaternion from (w, x, y, z).
math::Quat ToQuat(const pybind11::handle& h, const std::string& what);

/// Polls Python for a pending signal (Ctrl-C) and calls an optional Python progress
/// callback, at most every `interval` seconds, from a thread that runs C++ with the GIL
/// released. When Python raises (KeyboardInterrupt, or the callback's exception) the
/// error is kept, `stop()` turns true and Rethrow() raises it once the caller holds the
/// GIL again; nothing Python-side is touched without the GIL.
class PythonPoll {
 public:
  explicit PythonPoll(pybind11::object callback, double interval = 0.1);
  ~PythonPoll();
  PythonPoll(const PythonPoll&) = delete;
  PythonPoll& operator=(const PythonPoll&) = delete;

  /// From C++ without the GIL: when due (or `force`), takes the GIL, checks signals and
  /// From C++ without the GIL: when due (or `force`), takes the GIL, checks signals and
  /// calls callback(fraction), fraction in [0, 1]. Returns false once Python has raised.
  bool PollFraction(double fraction, bool force = false);
  /// Same, with callback(done, total).
  bool PollCount(std::size_t done, std::size_t total, bool force = false);
  bool stopped() const { return stopped_; }
  /// With the GIL: raises the kept Python error, if any.
  void Rethrow();

 private:
  bool Due(bool force);
  void Capture();  // with the GIL, after a Python error
  // Both polls: signals first, then the callback with `args`; false once stopped.
  template <class... Args>
  bool Poll(bool force, Args... args);

  pybind11::object callback_;
  double interval_;
  std::chrono::steady_clock::time_point last_;
  bool stopped_ = false;
  PyObject* type_ = nullptr;
  PyObject* value_ = nullptr;
  PyObject* trace_ = nullptr;
};

/// Thrown through the library (which never catches) to stop a run that Python wants
/// stopped; the binding catches it and raises the kept Python error.
struct PythonStop {};

}  // namespace deploysim::python
