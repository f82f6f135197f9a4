#include "deploysim/crosscheck/crosscheck_file.h"

#include <cstdio>
#include <string>
#include <vector>

#include "deploysim/io/hdf5_writer.h"
#include "deploysim/math/number_format.h"
#include "deploysim/math/quaternion.h"

#ifndef DEPLOYSIM_VERSION
#define DEPLOYSIM_VERSION "unknown"
#endif

namespace deploysim::crosscheck {

namespace {

/// The project's number formatting (math/number_format.h) under a short local name.
constexpr auto& Num = math::FormatNumber;

void Vectors(io::Hdf5Writer& w,
             const std::string& name,
             const std::vector<math::Vec3>& v,
             const std::string& units,
             const std::string& description) {
  std::vector<double> flat;
  for (const math::Vec3& x : v) flat.insert(flat.end(), {x[0], x[1], x[2]});
  w.Doubles(name, {v.size(), 3}, flat, units, description);
}

void Quats(io::Hdf5Writer& w, const std::string& name, const std::vector<math::Quat>& q) {
  std::vector<double> flat;
  for (const math::Quat& x : q) {
    const math::Vec4 wxyz = math::ToWxyz(x);
    flat.insert(flat.end(), {wxyz[0], wxyz[1], wxyz[2], wxyz[3]});
  }
  w.Doubles(name, {q.size(), 4}, flat, "1", "hub attitude q_NB, scalar first (w, x, y, z)");
}

void Rows(io::Hdf5Writer& w,
          const std::string& name,
          const std::vector<Eigen::VectorXd>& rows,
          const std::string& units,
          const std::string& description) {
  const std::size_t cols = rows.empty() ? 0 : static_cast<std::size_t>(rows.front().size());
  std::vector<double> flat;
  for (const Eigen::VectorXd& r : rows) flat.insert(flat.end(), r.data(), r.data() + r.size());
  w.Doubles(name, {rows.size(), cols}, flat, units, description);
}

void Scalars(io::Hdf5Writer& w,
             const std::string& name,
             const std::vector<double>& v,
             const std::string& units,
             const std::string& description) {
  w.Doubles(name, {v.size()}, v, units, description);
}

}  // namespace

void WriteCrosscheckFile(const std::string& path, const CrosscheckResult& r) {
  io::Hdf5Writer w(path);  // atomic: nothing is left at `path` unless Commit() succeeds
  const schedule::Profile& p = r.profile;
  const run::Trajectory& tr = r.reduced.trajectory;
  const SimbodyTrajectory& sb = r.simbody.trajectory;
  Scalars(w, "/time", tr.time, "s", "output grid");

  Vectors(w, "/reduced/H_B", tr.H_B, "kg m^2/s", "total angular momentum about the system CoM, B");
  Vectors(w, "/reduced/h_N", tr.h_N, "kg m^2/s", "total angular momentum, N");
  Vectors(w, "/reduced/w_NB_B", tr.w_NB_B, "rad/s", "hub angular velocity, B");
  Quats(w, "/reduced/q_NB", tr.q_NB);
  Scalars(w, "/reduced/flip_time", r.reduced.flip_times, "s", "located Dzhanibekov flips");

  Vectors(w, "/simbody/H_B", sb.H_B, "kg m^2/s", "system central angular momentum, B");
  Vectors(w, "/simbody/h_N", sb.h_N, "kg m^2/s", "system central angular momentum, N (Ground)");
  Vectors(w, "/simbody/w_NB_B", sb.w_NB_B, "rad/s", "hub angular velocity, B");
  Quats(w, "/simbody/q_NB", sb.q_NB);
  Scalars(w, "/simbody/flip_time", r.simbody.flip_times, "s", "located Dzhanibekov flips");
  if (p.mode == schedule::Mode::kGeometry) {
    Rows(w, "/simbody/hinge_angles", sb.hinge_angles, "rad",
         "pin coordinates, one column per panel");
    Rows(w, "/simbody/hinge_rates", sb.hinge_rates, "rad/s", "pin speeds, one column per panel");
  }

  Scalars(w, "/difference/H_B_relative", r.difference.H_B_relative, "1",
          "|H_B reduced - H_B simbody| / |H_B(t0)|");
  Scalars(w, "/difference/attitude", r.difference.attitude, "rad",
          "angle of q_reduced^-1 q_simbody");
  Scalars(w, "/difference/w_NB_B", r.difference.w, "rad/s", "|w reduced - w simbody|");
  if (r.has_analytic) {
    Scalars(w, "/analytic/flip_time", r.analytic_flip_times, "s", "closed-form flip times");
  }

  w.Attribute("/", "deploysim_version", DEPLOYSIM_VERSION);
  w.Attribute("/", "schema", "deploysim-crosscheck 1");
  w.Attribute("/", "profile_name", p.name);
  w.Attribute("/", "profile_source", p.source);
  w.Attribute("/", "profile_text", p.text);
  w.Attribute("/", "accuracy", Num(r.accuracy));
  w.Attribute(
      "/", "reduced_integrator",
      p.integrator.method + " rtol=" + Num(p.integrator.rtol) + " atol=" + Num(p.integrator.atol));
  w.Attribute("/", "max_H_B_relative_difference", Num(r.difference.max_H_B_relative));
  w.Attribute("/", "max_attitude_difference", Num(r.difference.max_attitude));
  w.Attribute("/", "max_w_difference", Num(r.difference.max_w));
  w.Attribute("/", "max_flip_time_difference", Num(r.max_flip_difference));
  w.Attribute("/", "simbody_momentum_drift", Num(r.simbody.max_momentum_drift));
  w.Attribute("/", "reduced_momentum_drift", Num(r.reduced.max_h_N_drift));
  w.Attribute("/", "reduced_wall_seconds", Num(r.reduced.wall_seconds));
  w.Attribute("/", "simbody_wall_seconds", Num(r.simbody.stats.wall_seconds));
  w.Commit();
}

}  // namespace deploysim::crosscheck
