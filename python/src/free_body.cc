// FreeBody: analysis::FreeBodySolution (the closed-form torque-free motion, docs/design.md 2.3)
// evaluated over numpy arrays of times; each element is the scalar C++ call, bit for bit.

#include <pybind11/numpy.h>
#include <pybind11/stl.h>

#include <vector>

#include "bindings.h"
#include "convert.h"
#include "deploysim/analysis/free_body_solution.h"
#include "deploysim/math/inertia.h"
#include "deploysim/math/quaternion.h"

namespace py = pybind11;

namespace deploysim::python {

namespace {

using analysis::FreeBodySolution;

/// Times as a contiguous float64 array, and the shape of the result before its last axis.
py::array_t<double> Times(const py::handle& t) {
  return py::array_t<double, py::array::c_style | py::array::forcecast>::ensure(t);
}

std::vector<py::ssize_t> ShapeWith(const py::array& t, py::ssize_t last) {
  std::vector<py::ssize_t> shape(t.shape(), t.shape() + t.ndim());
  shape.push_back(last);
  return shape;
}

/// f(t_k, out + k * width) for every element of t (GIL released for large arrays).
template <typename F>
py::array_t<double> Map(const py::object& t_in, py::ssize_t width, F f) {
  py::array_t<double> t = Times(t_in);
  if (!t) throw std::invalid_argument("t: must be a number or an array of numbers [s]");
  py::array_t<double> out(ShapeWith(t, width));
  const double* tt = t.data();
  double* o = out.mutable_data();
  const py::ssize_t n = t.size();
  {
    py::gil_scoped_release release;
    for (py::ssize_t k = 0; k < n; ++k) f(tt[k], o + k * width);
  }
  return out;
}

void Put3(const math::Vec3& v, double* o) {
  o[0] = v[0];
  o[1] = v[1];
  o[2] = v[2];
}

void Put4(const math::Quat& q, double* o) {
  const math::Vec4 wxyz = math::ToWxyz(q);
  for (int k = 0; k < 4; ++k) o[k] = wxyz[k];
}

}  // namespace

void RegisterFreeBody(py::module_& m) {
  py::class_<FreeBodySolution>(
      m, "FreeBody",
      "Closed-form torque-free motion of a rigid body with constant inertia (docs/design.md 2.3;\n"
      "thesis eqs. 2.22-2.64): Jacobi elliptic functions of the complementary parameter,\n"
      "exact near and on the separatrix; the attitude by the third-kind integral.\n\n"
      "FreeBody(J, H0, q0=(1, 0, 0, 0), t0=0.0)\n"
      "  J  : 3x3 inertia tensor [kg m^2] in B (any symmetric valid tensor), or its 3\n"
      "       principal moments (a diagonal tensor, any order)\n"
      "  H0 : H_B(t0), angular momentum in body components [kg m^2/s]\n"
      "  q0 : q_NB(t0), attitude quaternion scalar first (w, x, y, z)\n"
      "  t0 : [s]\n"
      "ValueError for an invalid tensor (the message names the rule) or non-finite input.\n\n"
      "Every method taking t accepts a number or a numpy array of times [s] and returns\n"
      "an array of shape t.shape + (3,) or (4,); element k is the scalar C++ evaluation\n"
      "at t[k], bit for bit.")
      .def(py::init([](const py::object& J, const py::object& H0, const py::object& q0, double t0) {
             const math::InertiaTensor tensor =
                 math::InertiaTensor::FromMatrix(ToMat3(J, "J"), "J");
             const math::Quat q = q0.is_none() ? math::Quat::Identity() : ToQuat(q0, "q0");
             return FreeBodySolution(tensor, ToVec3(H0, "H0"), q, t0);
           }),
           py::arg("J"), py::arg("H0"), py::arg("q0") = py::none(), py::arg("t0") = 0.0)
      .def(
          "H_B",
          [](const FreeBodySolution& s, const py::object& t) {
            return Map(t, 3, [&s](double tk, double* o) { Put3(s.H_B(tk), o); });
          },
          py::arg("t"), "Angular momentum in body components H_B(t) [kg m^2/s].")
      .def(
          "w_NB_B",
          [](const FreeBodySolution& s, const py::object& t) {
            return Map(t, 3, [&s](double tk, double* o) { Put3(s.w_NB_B(tk), o); });
          },
          py::arg("t"), "Angular velocity w_NB_B(t) = J^-1 H_B(t) [rad/s], body components.")
      .def(
          "q_NB",
          [](const FreeBodySolution& s, const py::object& t) {
            return Map(t, 4, [&s](double tk, double* o) { Put4(s.q_NB(tk), o); });
          },
          py::arg("t"), "Attitude q_NB(t), unit quaternion scalar first (w, x, y, z).")
      .def(
          "state",
          [](const FreeBodySolution& s, const py::object& t) {
            py::array_t<double> hq = Map(t, 7, [&s](double tk, double* o) {
              math::Vec3 H;
              math::Quat q;
              s.StateAt(tk, &H, &q);
              Put3(H, o);
              Put4(q, o + 3);
            });
            py::object H = hq[py::make_tuple(py::ellipsis(), py::slice(0, 3, 1))];
            py::object q = hq[py::make_tuple(py::ellipsis(), py::slice(3, 7, 1))];
            return py::make_tuple(H, q);
          },
          py::arg("t"),
          "(H_B(t), q_NB(t)) from one evaluation of the elliptic functions (the same values "
          "as H_B and q_NB, faster).")
      .def("flip_times", &FreeBodySolution::FlipTimes, py::arg("t_begin"), py::arg("t_end"),
           "Times in [t_begin, t_end] [s] at which H_B along the intermediate axis changes "
           "sign (the Dzhanibekov flip), as a list; every T/2 in the periodic regimes.")
      .def_property_readonly("period", &FreeBodySolution::period,
                             "Full period of H_B(t) [s]; inf on the separatrix or when H_B is "
                             "constant.")
      .def_property_readonly("flip_half_period", &FreeBodySolution::flip_half_period,
                             "Time between flips [s] (T/2); inf when it does not flip.")
      .def_property_readonly(
          "regime", [](const FreeBodySolution& s) { return analysis::ToString(s.regime()); },
          "'minor-axis', 'major-axis', 'separatrix', 'intermediate-axis-spin', "
          "'axisymmetric', 'spherical' or 'at-rest'.")
      .def_property_readonly("one_minus_k2", &FreeBodySolution::complementary_parameter,
                             "Complementary parameter 1 - k^2 (0 on the separatrix), formed "
                             "without cancellation.")
      .def_property_readonly("lambda_", &FreeBodySolution::lambda,
                             "Rate of the elliptic argument [rad/s].")
      .def_property_readonly("energy", &FreeBodySolution::energy,
                             "Kinetic energy T = 1/2 H.J^-1 H [J].")
      .def_property_readonly("momentum", &FreeBodySolution::momentum_magnitude, "|H_B| [kg m^2/s].")
      .def_property_readonly("D", &FreeBodySolution::D, "D = |H|^2 / (2T) [kg m^2].")
      .def_property_readonly(
          "principal_moments",
          [](const FreeBodySolution& s) { return Vec(s.principal_axes().moments); },
          "Principal moments as used, ascending [kg m^2].")
      .def_property_readonly(
          "principal_axes", [](const FreeBodySolution& s) { return Mat(s.principal_axes().axes); },
          "Columns: unit principal axes in B (right-handed), in the order of principal_moments.")
      .def_property_readonly("intermediate_axis", &FreeBodySolution::intermediate_axis,
                             "Index (0, 1, 2) of the body axis nearest the intermediate "
                             "principal axis; -1 when two moments are equal.");
}

}  // namespace deploysim::python
