#include "convert.h"

#include <cmath>
#include <cstring>
#include <stdexcept>
#include <utility>

#include "deploysim/math/quaternion.h"

namespace py = pybind11;

namespace deploysim::python {

namespace {

/// A capsule that owns a heap copy (moved) of `v`.
template <typename T>
py::capsule Owner(std::vector<T>** out, std::vector<T>&& v) {
  auto* held = new std::vector<T>(std::move(v));
  *out = held;
  return py::capsule(held, [](void* p) { delete static_cast<std::vector<T>*>(p); });
}

constexpr py::ssize_t kD = static_cast<py::ssize_t>(sizeof(double));

}  // namespace

py::array_t<double> Doubles(std::vector<double>&& v) {
  std::vector<double>* held = nullptr;
  py::capsule owner = Owner(&held, std::move(v));
  return py::array_t<double>({static_cast<py::ssize_t>(held->size())}, {kD}, held->data(), owner);
}

py::array_t<double> DoublesCopy(const std::vector<double>& v) {
  py::array_t<double> a(static_cast<py::ssize_t>(v.size()));
  if (!v.empty()) std::memcpy(a.mutable_data(), v.data(), v.size() * sizeof(double));
  return a;
}

py::array_t<double> Vec3s(std::vector<math::Vec3>&& v) {
  static_assert(sizeof(math::Vec3) == 3 * sizeof(double), "Vec3 is 3 packed doubles");
  std::vector<math::Vec3>* held = nullptr;
  py::capsule owner = Owner(&held, std::move(v));
  const double* data = held->empty() ? nullptr : held->front().data();
  return py::array_t<double>({static_cast<py::ssize_t>(held->size()), py::ssize_t{3}}, {3 * kD, kD},
                             data, owner);
}

py::array_t<double> Mat3s(std::vector<math::Mat3>&& v) {
  static_assert(sizeof(math::Mat3) == 9 * sizeof(double), "Mat3 is 9 packed doubles");
  std::vector<math::Mat3>* held = nullptr;
  py::capsule owner = Owner(&held, std::move(v));
  const double* data = held->empty() ? nullptr : held->front().data();
  // Column-major: J(i, j) at i + 3 j.
  return py::array_t<double>(
      {static_cast<py::ssize_t>(held->size()), py::ssize_t{3}, py::ssize_t{3}},
      {9 * kD, kD, 3 * kD}, data, owner);
}

py::array_t<double> Quats(const std::vector<math::Quat>& v) {
  py::array_t<double> a({static_cast<py::ssize_t>(v.size()), py::ssize_t{4}});
  double* out = a.mutable_data();
  for (std::size_t n = 0; n < v.size(); ++n) {
    const math::Vec4 wxyz = math::ToWxyz(v[n]);
    for (int k = 0; k < 4; ++k) out[4 * n + static_cast<std::size_t>(k)] = wxyz[k];
  }
  return a;
}

py::array_t<double> Rows(const std::vector<Eigen::VectorXd>& rows) {
  const py::ssize_t p = rows.empty() ? 0 : static_cast<py::ssize_t>(rows.front().size());
  py::array_t<double> a({static_cast<py::ssize_t>(rows.size()), p});
  double* out = a.mutable_data();
  for (std::size_t n = 0; n < rows.size(); ++n) {
    if (rows[n].size() != p) throw std::runtime_error("rows of unequal length (internal)");
    for (py::ssize_t k = 0; k < p; ++k) out[n * static_cast<std::size_t>(p) + k] = rows[n][k];
  }
  return a;
}

py::array_t<double> Vec(const math::Vec3& v) {
  py::array_t<double> a(3);
  for (int k = 0; k < 3; ++k) a.mutable_data()[k] = v[k];
  return a;
}

py::array_t<double> Mat(const math::Mat3& J) {
  py::array_t<double> a({py::ssize_t{3}, py::ssize_t{3}});
  for (int i = 0; i < 3; ++i) {
    for (int j = 0; j < 3; ++j) a.mutable_data()[3 * i + j] = J(i, j);
  }
  return a;
}

py::array_t<double> QuatArray(const math::Quat& q) {
  const math::Vec4 wxyz = math::ToWxyz(q);
  py::array_t<double> a(4);
  for (int k = 0; k < 4; ++k) a.mutable_data()[k] = wxyz[k];
  return a;
}

math::Vec3 ToVec3(const py::handle& h, const std::string& what) {
  py::array_t<double> a = py::array_t<double, py::array::c_style | py::array::forcecast>::ensure(h);
  if (!a || a.size() != 3 || a.ndim() != 1) {
    throw std::invalid_argument(what + ": must be 3 numbers");
  }
  return math::Vec3(a.data()[0], a.data()[1], a.data()[2]);
}

math::Mat3 ToMat3(const py::handle& h, const std::string& what) {
  py::array_t<double> a = py::array_t<double, py::array::c_style | py::array::forcecast>::ensure(h);
  if (a && a.ndim() == 1 && a.size() == 3) {
    math::Mat3 D = math::Mat3::Zero();
    for (int i = 0; i < 3; ++i) D(i, i) = a.data()[i];
    return D;
  }
  if (!a || a.ndim() != 2 || a.shape(0) != 3 || a.shape(1) != 3) {
    throw std::invalid_argument(what + ": must be a 3x3 matrix or 3 principal moments");
  }
  math::Mat3 J;
  for (int i = 0; i < 3; ++i) {
    for (int j = 0; j < 3; ++j) J(i, j) = a.data()[3 * i + j];
  }
  return J;
}

math::Quat ToQuat(const py::handle& h, const std::string& what) {
  py::array_t<double> a = py::array_t<double, py::array::c_style | py::array::forcecast>::ensure(h);
  if (!a || a.ndim() != 1 || a.size() != 4) {
    throw std::invalid_argument(what + ": must be 4 numbers (w, x, y, z)");
  }
  return math::FromWxyz(math::Vec4(a.data()[0], a.data()[1], a.data()[2], a.data()[3]));
}

// ---- PythonPoll ----

PythonPoll::PythonPoll(py::object callback, double interval)
    : callback_(std::move(callback)),
      interval_(interval),
      last_(std::chrono::steady_clock::now()) {}

PythonPoll::~PythonPoll() {
  Py_XDECREF(type_);
  Py_XDECREF(value_);
  Py_XDECREF(trace_);
}

bool PythonPoll::Due(bool force) {
  if (stopped_) return false;
  const auto now = std::chrono::steady_clock::now();
  if (!force && std::chrono::duration<double>(now - last_).count() < interval_) return false;
  last_ = now;
  return true;
}

void PythonPoll::Capture() {
  PyErr_Fetch(&type_, &value_, &trace_);
  stopped_ = true;
}

template <class... Args>
bool PythonPoll::Poll(bool force, Args... args) {
  if (!Due(force)) return !stopped_;
  py::gil_scoped_acquire gil;
  if (PyErr_CheckSignals() != 0) {
    Capture();
    return false;
  }
  if (!callback_.is_none()) {
    try {
      callback_(args...);
    } catch (py::error_already_set& e) {
      e.restore();
      Capture();
      return false;
    }
  }
  return true;
}

bool PythonPoll::PollFraction(double fraction, bool force) { return Poll(force, fraction); }

bool PythonPoll::PollCount(std::size_t done, std::size_t total, bool force) {
  return Poll(force, done, total);
}

void PythonPoll::Rethrow() {
  if (type_ == nullptr) return;
  PyErr_Restore(type_, value_, trace_);
  type_ = value_ = trace_ = nullptr;
  throw py::error_already_set();
}

}  // namespace deploysim::python
