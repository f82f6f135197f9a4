// The Simbody cross-check from Python (where the module is built with it): the run of
// `deploysim crosscheck`, its trajectories and differences as numpy arrays.

#include <pybind11/stl.h>

#include <optional>
#include <utility>

#include "bindings.h"
#include "convert.h"
#ifdef DEPLOYSIM_HAVE_CROSSCHECK
#include "deploysim/crosscheck/crosscheck.h"
#include "deploysim/crosscheck/free_hinge_crosscheck.h"
#endif

namespace py = pybind11;

namespace deploysim::python {

#ifdef DEPLOYSIM_HAVE_CROSSCHECK
namespace {

py::dict Side(std::vector<double>&& flips,
              std::vector<math::Vec3>&& H_B,
              std::vector<math::Vec3>&& h_N,
              std::vector<math::Vec3>&& w,
              const std::vector<math::Quat>& q) {
  py::dict d;
  d["H_B"] = Vec3s(std::move(H_B));
  d["h_N"] = Vec3s(std::move(h_N));
  d["w_NB_B"] = Vec3s(std::move(w));
  d["q_NB"] = Quats(q);
  d["flip_time"] = Doubles(std::move(flips));
  return d;
}

py::dict ResultDict(crosscheck::CrosscheckResult&& r) {
  py::dict d;
  run::Trajectory& a = r.reduced.trajectory;
  crosscheck::SimbodyTrajectory& b = r.simbody.trajectory;
  d["time"] = DoublesCopy(a.time);
  d["reduced"] = Side(std::move(r.reduced.flip_times), std::move(a.H_B), std::move(a.h_N),
                      std::move(a.w_NB_B), a.q_NB);
  d["simbody"] = Side(std::move(r.simbody.flip_times), std::move(b.H_B), std::move(b.h_N),
                      std::move(b.w_NB_B), b.q_NB);
  py::dict diff;
  diff["H_B_relative"] = Doubles(std::move(r.difference.H_B_relative));
  diff["attitude"] = Doubles(std::move(r.difference.attitude));
  diff["w_NB_B"] = Doubles(std::move(r.difference.w));
  d["difference"] = diff;
  d["max_H_B_relative"] = r.difference.max_H_B_relative;
  d["max_attitude"] = r.difference.max_attitude;
  d["max_w_NB_B"] = r.difference.max_w;
  d["max_flip_difference"] = r.max_flip_difference;
  d["simbody_max_momentum_drift"] = r.simbody.max_momentum_drift;
  d["reduced_max_h_N_drift"] = r.reduced.max_h_N_drift;
  d["accuracy"] = r.accuracy;
  d["analytic_flip_time"] = DoublesCopy(r.analytic_flip_times);
  return d;
}

}  // namespace
#endif

void RegisterCrosscheck(py::module_& m) {
#ifdef DEPLOYSIM_HAVE_CROSSCHECK
  m.attr("HAVE_CROSSCHECK") = true;
  m.def(
      "_crosscheck",
      [](const schedule::Profile& profile, std::optional<double> accuracy,
         std::optional<double> until, std::optional<double> dt, double own_error) {
        std::optional<crosscheck::CrosscheckResult> r;
        {
          py::gil_scoped_release release;
          if (profile.is_hinge_profile()) {
            crosscheck::FreeHingeCrosscheckOptions o;
            if (accuracy) o.accuracy = *accuracy;
            o.own_error_accuracy = own_error;
            o.t_end = until;
            o.output_dt = dt;
            r = crosscheck::AsCrosscheckResult(crosscheck::RunFreeHingeCrosscheck(profile, o));
          } else {
            if (own_error > 0.0) {
              throw std::invalid_argument(profile.source + ": own_error is for hinge profiles");
            }
            crosscheck::CrosscheckOptions o;
            if (accuracy) o.accuracy = *accuracy;
            o.t_end = until;
            o.output_dt = dt;
            r = crosscheck::RunCrosscheck(profile, o);
          }
        }
        return ResultDict(std::move(*r));
      },
      py::arg("profile"), py::arg("accuracy") = py::none(), py::arg("until") = py::none(),
      py::arg("dt") = py::none(), py::arg("own_error") = 0.0);
#else
  m.attr("HAVE_CROSSCHECK") = false;
#endif
}

}  // namespace deploysim::python
