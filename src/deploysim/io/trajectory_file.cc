// HDF5 trajectory files (docs/file_formats.md, "Trajectory files").

#include "deploysim/io/trajectory_file.h"

#include <cerrno>
#include <cstring>
#include <fstream>
#include <stdexcept>
#include <string>
#include <vector>

#include "deploysim/io/hdf5_common.h"
#include "deploysim/io/hdf5_writer.h"
#include "deploysim/io/number_format.h"
#include "deploysim/math/quaternion.h"

#ifndef DEPLOYSIM_VERSION
#define DEPLOYSIM_VERSION "unknown"
#endif

namespace deploysim::io {

namespace {

using analysis::Trajectory;
using internal::FormatNumber;

using hdf5::QuietErrors;
using hdf5::TextType;

std::vector<double> Flatten(const std::vector<math::Vec3>& v) {
  std::vector<double> flat;
  flat.reserve(3 * v.size());
  for (const math::Vec3& x : v) flat.insert(flat.end(), {x[0], x[1], x[2]});
  return flat;
}

std::vector<double> FlattenWxyz(const std::vector<math::Quat>& q) {
  std::vector<double> flat;
  flat.reserve(4 * q.size());
  for (const math::Quat& x : q) {
    const math::Vec4 wxyz = math::ToWxyz(x);
    flat.insert(flat.end(), {wxyz[0], wxyz[1], wxyz[2], wxyz[3]});
  }
  return flat;
}

std::vector<double> FlattenRowMajor(const std::vector<math::Mat3>& J) {
  std::vector<double> flat;
  flat.reserve(9 * J.size());
  for (const math::Mat3& M : J) {
    for (int i = 0; i < 3; ++i) {
      for (int j = 0; j < 3; ++j) flat.push_back(M(i, j));
    }
  }
  return flat;
}

std::vector<double> FlattenRows(const std::vector<Eigen::VectorXd>& rows) {
  std::vector<double> flat;
  for (const Eigen::VectorXd& r : rows) flat.insert(flat.end(), r.data(), r.data() + r.size());
  return flat;
}

/// Number of hinge angles per sample written for r (0: no /hinge_angles dataset).
std::size_t HingeColumns(const analysis::MissionResult& r) {
  if (r.profile.mode != schedule::Mode::kGeometry) return 0;
  return r.profile.model.hinged.panels.size();
}

/// Every per-sample array of t has one entry per output time; in geometry mode one row
/// of `panels` hinge angles per time.
void CheckSamples(const std::string& path, const Trajectory& t, bool geometry, std::size_t panels) {
  const std::size_t n = t.time.size();
  auto require = [&](const char* name, std::size_t size) {
    if (size != n) {
      throw std::invalid_argument(path + ": trajectory." + name + " has " + std::to_string(size) +
                                  " samples, time has " + std::to_string(n) +
                                  " (rule: one sample per output time)");
    }
  };
  require("H_B", t.H_B.size());
  require("w_NB_B", t.w_NB_B.size());
  require("q_NB", t.q_NB.size());
  require("J_B", t.J_B.size());
  require("principal_moments", t.principal_moments.size());
  require("h_rel_B", t.h_rel_B.size());
  require("h_N", t.h_N.size());
  require("energy", t.energy.size());
  require("energy_rigid", t.energy_rigid.size());
  require("euler_313", t.euler_313.size());
  require("spin_axis_angle", t.spin_axis_angle.size());
  if (geometry) {
    require("hinge_angles", t.hinge_angles.size());
    for (std::size_t k = 0; k < n; ++k) {
      if (static_cast<std::size_t>(t.hinge_angles[k].size()) != panels) {
        throw std::invalid_argument(path + ": trajectory.hinge_angles[" + std::to_string(k) +
                                    "] has " + std::to_string(t.hinge_angles[k].size()) +
                                    " angles, the model has " + std::to_string(panels) +
                                    " panels (rule: one angle per panel)");
      }
    }
  }
}

/// The analysis of r fits its profile: one report per stage, ordered danger windows.
void CheckAnalysis(const std::string& path, const analysis::MissionResult& r) {
  if (r.stages.size() != r.profile.stages.size()) {
    throw std::invalid_argument(path + ": " + std::to_string(r.stages.size()) +
                                " stage reports for " + std::to_string(r.profile.stages.size()) +
                                " profile stages (rule: one report per stage)");
  }
  for (const analysis::DangerWindow& d : r.danger_windows) {
    if (!(d.t_begin <= d.t_end)) {
      throw std::invalid_argument(path + ": danger window [" + FormatNumber(d.t_begin) + ", " +
                                  FormatNumber(d.t_end) + "] (rule: t_begin <= t_end)");
    }
  }
}

std::string IntegratorSettings(const schedule::Profile& p) {
  const schedule::IntegratorSpec& s = p.integrator;
  return "rtol=" + FormatNumber(s.rtol) + ", atol=" + FormatNumber(s.atol) +
         ", step=" + FormatNumber(s.step) + ", max_step=" + FormatNumber(s.max_step) +
         ", output_dt=" + FormatNumber(p.output.dt);
}

std::string StatisticsText(const integrators::Statistics& s) {
  return "steps=" + std::to_string(s.steps) + ", rejected=" + std::to_string(s.rejected) +
         ", evaluations=" + std::to_string(s.evaluations) +
         ", dense_steps=" + std::to_string(s.dense_steps);
}

/// The /stages table: one row per profile stage, its definition and its analysis
/// (analysis::StageReport; CheckAnalysis ensured one report per stage).
void WriteStageTable(Hdf5Writer& w, const analysis::MissionResult& r) {
  const schedule::Profile& p = r.profile;
  std::vector<double> t_begin, t_end, moments, one_minus_k2, separatrix, half_period, max_diff;
  std::vector<long long> index, rigid, predicted, observed;
  std::vector<std::string> names, laws, from, to, roles, regimes;
  for (std::size_t i = 0; i < p.stages.size(); ++i) {
    const schedule::Stage& s = p.stages[i];
    const analysis::StageReport& a = r.stages[i];
    index.push_back(static_cast<long long>(i));
    t_begin.push_back(s.t_begin);
    t_end.push_back(s.t_end);
    names.push_back(s.name);
    laws.push_back(s.is_hold() ? "hold" : schedule::ToString(s.law));
    from.push_back(s.from);
    to.push_back(s.to);
    rigid.push_back(a.rigid ? 1 : 0);
    moments.insert(moments.end(), {a.moments_end[0], a.moments_end[1], a.moments_end[2]});
    roles.push_back(analysis::ToString(a.spin_axis_end));
    regimes.push_back(a.regime);
    one_minus_k2.push_back(a.one_minus_k2);
    separatrix.push_back(a.separatrix_distance);
    half_period.push_back(a.predicted_flip_half_period);
    predicted.push_back(static_cast<long long>(a.predicted_flips.size()));
    observed.push_back(static_cast<long long>(a.observed_flips.size()));
    max_diff.push_back(a.max_flip_time_difference);
  }
  const std::size_t count = p.stages.size();
  w.Integers("/stages/index", index, "1", "position of the stage in the profile, from 0");
  w.Doubles("/stages/t_begin", {count}, t_begin, "s", "stage start time");
  w.Doubles("/stages/t_end", {count}, t_end, "s", "stage end time");
  w.Strings("/stages/name", names, "stage name");
  w.Strings("/stages/law", laws, "interpolation law (hold for a hold)");
  w.Strings("/stages/from", from, "configuration at the stage start");
  w.Strings("/stages/to", to, "configuration at the stage end");
  w.Integers("/stages/rigid", rigid, "1",
             "1 if J_B is constant and h_rel_B = 0 over the stage (closed form applies), else 0");
  w.Doubles("/stages/moments_end", {count, 3}, moments, "kg m^2",
            "principal moments of J_B at the stage end, ascending");
  w.Strings("/stages/spin_axis_role", roles,
            "role of the spin axis in J_B at the stage end: minor, intermediate, major or "
            "degenerate (two equal moments)");
  w.Strings("/stages/regime", regimes,
            "rigid stages: the closed-form regime of the free body; empty otherwise");
  w.Doubles("/stages/one_minus_k2", {count}, one_minus_k2, "1",
            "rigid stages: complementary parameter 1 - k^2 of the closed form (0 on the "
            "separatrix); 0 otherwise");
  w.Doubles("/stages/separatrix_distance", {count}, separatrix, "1",
            "(D - I2) / (I3 - I1) at the stage end, D = |H|^2 / (w.J w): 0 on the separatrix, "
            "< 0 on the minor-axis side");
  w.Doubles("/stages/predicted_flip_half_period", {count}, half_period, "s",
            "rigid stages with the spin axis intermediate: closed-form time between flips; "
            "inf otherwise");
  w.Integers("/stages/predicted_flip_count", predicted, "1",
             "closed-form flips within the stage (rigid stages only; 0 otherwise)");
  w.Integers("/stages/observed_flip_count", observed, "1",
             "flips located by the integrator within [t_begin, t_end)");
  w.Doubles("/stages/max_flip_time_difference", {count}, max_diff, "s",
            "max |observed - nearest predicted flip time| within the stage (0 if none)");
}

/// /danger_windows: the intervals of the output grid in which the spin axis is the
/// intermediate principal axis of J_B(t) (flips possible).
void WriteDangerWindows(Hdf5Writer& w, const analysis::MissionResult& r) {
  std::vector<double> t_begin, t_end;
  for (const analysis::DangerWindow& d : r.danger_windows) {
    t_begin.push_back(d.t_begin);
    t_end.push_back(d.t_end);
  }
  const std::size_t count = t_begin.size();
  w.Doubles("/danger_windows/t_begin", {count}, t_begin, "s",
            "first output time at which the spin axis is the intermediate axis");
  w.Doubles("/danger_windows/t_end", {count}, t_end, "s",
            "last output time of the window at which it still is");
}

/// The per-sample datasets, in file order: rows grow as blocks of samples arrive.
enum Column : std::size_t {
  kTime,
  kHB,
  kW,
  kQ,
  kJ,
  kMoments,
  kHRel,
  kHN,
  kEnergy,
  kEnergyRigid,
  kEuler,
  kSpinAngle,
  kHinge,
  kColumns
};

struct ColumnSpec {
  const char* path;
  std::vector<std::size_t> trailing;
  const char* units;
  const char* description;
};

std::vector<ColumnSpec> Columns(std::size_t panels) {
  return {
      {"/time", {}, "s", "output grid"},
      {"/H_B",
       {3},
       "kg m^2/s",
       "total angular momentum about the system centre of mass, body (B) components"},
      {"/w_NB_B", {3}, "rad/s", "angular velocity of B in N, B components"},
      {"/q_NB",
       {4},
       "1",
       "attitude quaternion q_NB (v_N = q_NB v_B), Hamilton, scalar first (w, x, y, z)"},
      {"/J_B",
       {3, 3},
       "kg m^2",
       "inertia tensor about the system centre of mass, B components; J_B[n][i][j]"},
      {"/principal_moments", {3}, "kg m^2", "eigenvalues of J_B, ascending"},
      {"/h_rel_B", {3}, "kg m^2/s", "momentum of the panels' motion relative to B, B components"},
      {"/h_N",
       {3},
       "kg m^2/s",
       "total angular momentum, inertial (N) components (constant in exact arithmetic)"},
      {"/energy",
       {},
       "J",
       "total kinetic energy about the system centre of mass, 1/2 w.J_B w + w.h_rel_B + "
       "T_rel (T_rel: kinetic energy of the panels' motion relative to B; h_rel_B and "
       "T_rel are 0 under quasi-rigid coupling)"},
      {"/energy_rigid",
       {},
       "J",
       "rigid-body part 1/2 w.J_B w of /energy (equal to it when nothing moves "
       "relative to B)"},
      {"/euler_313",
       {3},
       "rad",
       "3-1-3 Euler angles (precession, nutation, spin) of B relative to a frame whose "
       "third axis is h_N"},
      {"/spin_axis_angle", {}, "rad", "angle between the initial spin axis (fixed in B) and h_N"},
      {"/hinge_angles",
       {panels},
       "rad",
       "hinge angle of each panel, in panel order (geometry mode)"},
  };
}

/// Column c of the samples of t, flattened row-major.
std::vector<double> Flat(const Trajectory& t, std::size_t c) {
  switch (c) {
    case kTime:
      return t.time;
    case kHB:
      return Flatten(t.H_B);
    case kW:
      return Flatten(t.w_NB_B);
    case kQ:
      return FlattenWxyz(t.q_NB);
    case kJ:
      return FlattenRowMajor(t.J_B);
    case kMoments:
      return Flatten(t.principal_moments);
    case kHRel:
      return Flatten(t.h_rel_B);
    case kHN:
      return Flatten(t.h_N);
    case kEnergy:
      return t.energy;
    case kEnergyRigid:
      return t.energy_rigid;
    case kEuler:
      return Flatten(t.euler_313);
    case kSpinAngle:
      return t.spin_axis_angle;
    default:
      return FlattenRows(t.hinge_angles);
  }
}

/// Everything but the per-sample datasets: events, stages, danger windows, attributes.
void WriteAnalysis(Hdf5Writer& w, const analysis::MissionResult& r) {
  w.Doubles("/events/flip_time", {r.flip_times.size()}, r.flip_times, "s",
            "located flips: sign changes of H_B along the tracked spin axis while it is the "
            "intermediate principal axis (docs/file_formats.md, Flips)");
  std::vector<double> predicted;
  for (const analysis::StageReport& a : r.stages) {
    predicted.insert(predicted.end(), a.predicted_flips.begin(), a.predicted_flips.end());
  }
  w.Doubles("/events/predicted_flip_time", {predicted.size()}, predicted, "s",
            "closed-form flip times of the rigid stages, in stage order");
  WriteStageTable(w, r);
  WriteDangerWindows(w, r);

  const schedule::Profile& p = r.profile;
  w.Attribute("/", "deploysim_version", DEPLOYSIM_VERSION);
  w.Attribute("/", "schema_version", std::to_string(kTrajectorySchemaVersion));
  w.Attribute("/", "profile_name", p.name);
  w.Attribute("/", "profile_source", p.source);
  w.Attribute("/", "profile_text", p.text);
  w.Attribute("/", "model_name", p.model.name);
  w.Attribute("/", "model_source", p.model.source);
  w.Attribute("/", "model_text", p.model.text);
  w.Attribute("/", "integrator", p.integrator.method);
  w.Attribute("/", "integrator_settings", IntegratorSettings(p));
  w.Attribute("/", "mode", schedule::ToString(p.mode));
  w.Attribute("/", "coupling", schedule::ToString(p.coupling));
  w.Attribute("/", "termination", integrators::ToString(r.termination));
  w.Attribute("/", "termination_message", r.message);
  w.Attribute("/", "statistics", StatisticsText(r.stats));
  w.Attribute("/", "max_h_N_drift", FormatNumber(r.max_h_N_drift));
}

// ---- reading ----

/// Reads one dataset of doubles whose shape is {any, trailing...}; returns the data and
/// sets `rows`. Records its units attribute under its absolute path.
std::vector<double> ReadDoubles(const std::string& path,
                                const H5::Group& group,
                                const std::string& group_path,
                                const std::string& name,
                                const std::vector<hsize_t>& trailing,
                                hsize_t& rows,
                                TrajectoryFile& out) {
  const std::string full = group_path + "/" + name;
  if (!group.nameExists(name)) throw std::runtime_error(path + ": " + full + ": missing dataset");
  const H5::DataSet ds = group.openDataSet(name);
  if (ds.getTypeClass() != H5T_FLOAT) {
    throw std::runtime_error(path + ": " + full + ": expected floating-point data");
  }
  const H5::DataSpace space = ds.getSpace();
  const int rank = space.getSimpleExtentNdims();
  std::vector<hsize_t> dims(static_cast<std::size_t>(rank));
  space.getSimpleExtentDims(dims.data());
  bool ok = dims.size() == trailing.size() + 1;
  for (std::size_t i = 0; ok && i < trailing.size(); ++i) {
    ok = trailing[i] == 0 || dims[i + 1] == trailing[i];
  }
  if (!ok) throw std::runtime_error(path + ": " + full + ": unexpected shape");
  std::vector<double> data(static_cast<std::size_t>(space.getSimpleExtentNpoints()));
  if (!data.empty()) ds.read(data.data(), H5::PredType::NATIVE_DOUBLE);
  rows = dims[0];
  if (!ds.attrExists("units")) {
    throw std::runtime_error(path + ": " + full + ": missing units attribute");
  }
  std::string units;
  const H5::Attribute a = ds.openAttribute("units");
  a.read(a.getStrType(), units);
  out.units[full] = units;
  return data;
}

/// Reads a 1-D dataset of integers and records its units attribute.
std::vector<long long> ReadIntegers(const std::string& path,
                                    const H5::Group& group,
                                    const std::string& group_path,
                                    const std::string& name,
                                    TrajectoryFile& out) {
  const std::string full = group_path + "/" + name;
  if (!group.nameExists(name)) throw std::runtime_error(path + ": " + full + ": missing dataset");
  const H5::DataSet ds = group.openDataSet(name);
  if (ds.getTypeClass() != H5T_INTEGER) {
    throw std::runtime_error(path + ": " + full + ": expected integer data");
  }
  const H5::DataSpace space = ds.getSpace();
  if (space.getSimpleExtentNdims() != 1) {
    throw std::runtime_error(path + ": " + full + ": unexpected shape");
  }
  std::vector<long long> data(static_cast<std::size_t>(space.getSimpleExtentNpoints()));
  if (!data.empty()) ds.read(data.data(), H5::PredType::NATIVE_LLONG);
  if (!ds.attrExists("units")) {
    throw std::runtime_error(path + ": " + full + ": missing units attribute");
  }
  std::string units;
  const H5::Attribute a = ds.openAttribute("units");
  a.read(a.getStrType(), units);
  out.units[full] = units;
  return data;
}

std::vector<std::string> ReadStrings(const std::string& path,
                                     const H5::Group& group,
                                     const std::string& group_path,
                                     const std::string& name,
                                     TrajectoryFile& out) {
  const std::string full = group_path + "/" + name;
  if (!group.nameExists(name)) throw std::runtime_error(path + ": " + full + ": missing dataset");
  const H5::DataSet ds = group.openDataSet(name);
  if (ds.getTypeClass() != H5T_STRING || !ds.getStrType().isVariableStr()) {
    throw std::runtime_error(path + ": " + full + ": expected variable-length strings");
  }
  const H5::DataSpace space = ds.getSpace();
  const H5::StrType type = TextType();
  std::vector<char*> buffer(static_cast<std::size_t>(space.getSimpleExtentNpoints()), nullptr);
  std::vector<std::string> values;
  if (!buffer.empty()) {
    ds.read(buffer.data(), type);
    for (char* s : buffer) values.emplace_back(s == nullptr ? "" : s);
    H5::DataSet::vlenReclaim(buffer.data(), type, space);
  }
  std::string units;
  const H5::Attribute a = ds.openAttribute("units");
  a.read(a.getStrType(), units);
  out.units[full] = units;
  return values;
}

template <typename T, typename Make>
std::vector<T> Rows(const std::vector<double>& flat, hsize_t rows, std::size_t width, Make make) {
  std::vector<T> v;
  v.reserve(rows);
  for (std::size_t k = 0; k < rows; ++k) v.push_back(make(&flat[k * width]));
  return v;
}

std::vector<math::Vec3> Vec3Rows(const std::vector<double>& flat, hsize_t rows) {
  return Rows<math::Vec3>(flat, rows, 3,
                          [](const double* x) { return math::Vec3(x[0], x[1], x[2]); });
}

H5::Group OpenGroup(const std::string& path, const H5::Group& parent, const std::string& name) {
  if (!parent.nameExists(name)) throw std::runtime_error(path + ": /" + name + ": missing group");
  return parent.openGroup(name);
}

TrajectoryFile ReadContents(const std::string& path) {
  TrajectoryFile out;
  {
    std::ifstream probe(path, std::ios::binary);
    if (!probe) throw std::runtime_error(path + ": cannot read: " + std::strerror(errno));
  }
  if (H5Fis_hdf5(path.c_str()) <= 0) {
    throw std::runtime_error(path + ": not an HDF5 file");
  }
  const H5::H5File file(path, H5F_ACC_RDONLY);

  for (int i = 0; i < file.getNumAttrs(); ++i) {
    const H5::Attribute a = file.openAttribute(static_cast<unsigned>(i));
    if (a.getTypeClass() != H5T_STRING) continue;
    std::string value;
    a.read(a.getStrType(), value);
    out.attributes[a.getName()] = value;
  }
  const auto version = out.attributes.find("schema_version");
  if (version == out.attributes.end() ||
      version->second != std::to_string(kTrajectorySchemaVersion)) {
    throw std::runtime_error(
        path + ": schema_version = " +
        (version == out.attributes.end() ? std::string("(missing)") : version->second) +
        ": this deploysim reads schema_version " + std::to_string(kTrajectorySchemaVersion));
  }

  Trajectory& t = out.trajectory;
  hsize_t n = 0;
  t.time = ReadDoubles(path, file, "", "time", {}, n, out);
  auto read_rows = [&](const std::string& name, const std::vector<hsize_t>& trailing) {
    hsize_t rows = 0;
    std::vector<double> flat = ReadDoubles(path, file, "", name, trailing, rows, out);
    if (rows != n) {
      throw std::runtime_error(path + ": /" + name + ": has " + std::to_string(rows) +
                               " rows, /time has " + std::to_string(n));
    }
    return flat;
  };
  t.H_B = Vec3Rows(read_rows("H_B", {3}), n);
  t.w_NB_B = Vec3Rows(read_rows("w_NB_B", {3}), n);
  t.q_NB = Rows<math::Quat>(read_rows("q_NB", {4}), n, 4, [](const double* x) {
    return math::FromWxyz(math::Vec4(x[0], x[1], x[2], x[3]));
  });
  t.J_B = Rows<math::Mat3>(read_rows("J_B", {3, 3}), n, 9, [](const double* x) {
    math::Mat3 M;
    for (int i = 0; i < 3; ++i) {
      for (int j = 0; j < 3; ++j) M(i, j) = x[3 * i + j];
    }
    return M;
  });
  t.principal_moments = Vec3Rows(read_rows("principal_moments", {3}), n);
  t.h_rel_B = Vec3Rows(read_rows("h_rel_B", {3}), n);
  t.h_N = Vec3Rows(read_rows("h_N", {3}), n);
  t.energy = read_rows("energy", {});
  t.energy_rigid = read_rows("energy_rigid", {});
  t.euler_313 = Vec3Rows(read_rows("euler_313", {3}), n);
  t.spin_axis_angle = read_rows("spin_axis_angle", {});
  if (file.nameExists("hinge_angles")) {
    const std::vector<double> flat = read_rows("hinge_angles", {0});
    const std::size_t width = n == 0 ? 0 : flat.size() / n;
    for (std::size_t k = 0; k < n; ++k) {
      t.hinge_angles.push_back(
          Eigen::Map<const Eigen::VectorXd>(&flat[k * width], static_cast<Eigen::Index>(width)));
    }
  }

  hsize_t rows = 0;
  const H5::Group events = OpenGroup(path, file, "events");
  out.flip_times = ReadDoubles(path, events, "/events", "flip_time", {}, rows, out);

  out.predicted_flip_times =
      ReadDoubles(path, events, "/events", "predicted_flip_time", {}, rows, out);

  const H5::Group stages = OpenGroup(path, file, "stages");
  const std::string sp = "/stages";
  hsize_t stage_count = 0;
  const std::vector<double> t_begin =
      ReadDoubles(path, stages, sp, "t_begin", {}, stage_count, out);
  const std::size_t count = static_cast<std::size_t>(stage_count);
  auto doubles = [&](const std::string& name, const std::vector<hsize_t>& trailing) {
    std::vector<double> v = ReadDoubles(path, stages, sp, name, trailing, rows, out);
    if (rows != stage_count) {
      throw std::runtime_error(path + ": /stages/" + name + ": has " + std::to_string(rows) +
                               " rows, /stages/t_begin has " + std::to_string(stage_count));
    }
    return v;
  };
  auto strings = [&](const std::string& name) {
    std::vector<std::string> v = ReadStrings(path, stages, sp, name, out);
    if (v.size() != count) {
      throw std::runtime_error(path + ": /stages/" + name + ": columns of different lengths");
    }
    return v;
  };
  auto integers = [&](const std::string& name) {
    std::vector<long long> v = ReadIntegers(path, stages, sp, name, out);
    if (v.size() != count) {
      throw std::runtime_error(path + ": /stages/" + name + ": columns of different lengths");
    }
    return v;
  };
  const std::vector<long long> index = integers("index");
  const std::vector<double> t_end = doubles("t_end", {});
  const std::vector<std::string> names = strings("name");
  const std::vector<std::string> laws = strings("law");
  const std::vector<std::string> from = strings("from");
  const std::vector<std::string> to = strings("to");
  const std::vector<long long> rigid = integers("rigid");
  const std::vector<double> moments = doubles("moments_end", {3});
  const std::vector<std::string> roles = strings("spin_axis_role");
  const std::vector<std::string> regimes = strings("regime");
  const std::vector<double> one_minus_k2 = doubles("one_minus_k2", {});
  const std::vector<double> separatrix = doubles("separatrix_distance", {});
  const std::vector<double> half_period = doubles("predicted_flip_half_period", {});
  const std::vector<long long> predicted = integers("predicted_flip_count");
  const std::vector<long long> observed = integers("observed_flip_count");
  const std::vector<double> max_diff = doubles("max_flip_time_difference", {});
  for (std::size_t i = 0; i < count; ++i) {
    StageRow row;
    row.index = static_cast<int>(index[i]);
    row.name = names[i];
    row.law = laws[i];
    row.from = from[i];
    row.to = to[i];
    row.t_begin = t_begin[i];
    row.t_end = t_end[i];
    row.rigid = rigid[i] != 0;
    row.moments_end = math::Vec3(moments[3 * i], moments[3 * i + 1], moments[3 * i + 2]);
    row.spin_axis_role = roles[i];
    row.regime = regimes[i];
    row.one_minus_k2 = one_minus_k2[i];
    row.separatrix_distance = separatrix[i];
    row.predicted_flip_half_period = half_period[i];
    row.predicted_flip_count = predicted[i];
    row.observed_flip_count = observed[i];
    row.max_flip_time_difference = max_diff[i];
    out.stages.push_back(row);
  }

  const H5::Group windows = OpenGroup(path, file, "danger_windows");
  hsize_t window_count = 0;
  const std::vector<double> w_begin =
      ReadDoubles(path, windows, "/danger_windows", "t_begin", {}, window_count, out);
  const std::vector<double> w_end =
      ReadDoubles(path, windows, "/danger_windows", "t_end", {}, rows, out);
  if (rows != window_count) {
    throw std::runtime_error(path + ": /danger_windows: columns of different lengths");
  }
  for (std::size_t i = 0; i < w_begin.size(); ++i) {
    out.danger_windows.push_back({w_begin[i], w_end[i]});
  }
  return out;
}

}  // namespace

struct TrajectoryFileWriter::Impl {
  Impl(const std::string& p, const schedule::Profile& profile)
      : path(p),
        geometry(profile.mode == schedule::Mode::kGeometry),
        panels(geometry ? profile.model.hinged.panels.size() : 0),
        writer(p) {
    const std::vector<ColumnSpec> columns = Columns(panels);
    const std::size_t used = geometry ? kColumns : kHinge;
    for (std::size_t c = 0; c < used; ++c) {
      handles.push_back(writer.GrowingDoubles(columns[c].path, columns[c].trailing,
                                              columns[c].units, columns[c].description));
    }
  }
  std::string path;
  bool geometry;
  std::size_t panels;
  Hdf5Writer writer;
  std::vector<std::size_t> handles;
  bool finished = false;
};

TrajectoryFileWriter::TrajectoryFileWriter(const std::string& path,
                                           const schedule::Profile& profile)
    : impl_(std::make_unique<Impl>(path, profile)) {}

TrajectoryFileWriter::~TrajectoryFileWriter() = default;

void TrajectoryFileWriter::Append(const Trajectory& block) {
  if (impl_->finished) throw std::logic_error(impl_->path + ": Append after Finish");
  CheckSamples(impl_->path, block, impl_->geometry, impl_->panels);
  for (std::size_t c = 0; c < impl_->handles.size(); ++c) {
    impl_->writer.AppendRows(impl_->handles[c], Flat(block, c), block.size());
  }
}

void TrajectoryFileWriter::Finish(const analysis::MissionResult& r) {
  CheckAnalysis(impl_->path, r);
  WriteAnalysis(impl_->writer, r);
  impl_->writer.Close();
  impl_->finished = true;
}

void TrajectoryFileWriter::Commit() {
  if (!impl_->finished) throw std::logic_error(impl_->path + ": Commit before Finish");
  impl_->writer.Commit();
}

void WriteTrajectoryFile(const std::string& path, const analysis::MissionResult& r) {
  CheckSamples(path, r.trajectory, r.profile.mode == schedule::Mode::kGeometry, HingeColumns(r));
  CheckAnalysis(path, r);
  TrajectoryFileWriter w(path, r.profile);  // atomic: nothing is left at `path` unless Commit()
  w.Append(r.trajectory);
  w.Finish(r);
  w.Commit();
}

TrajectoryOutputs::TrajectoryOutputs(const std::string& h5_path,
                                     const std::string& csv_path,
                                     const schedule::Profile& profile)
    : h5_(h5_path, profile) {
  if (!csv_path.empty()) {
    csv_.emplace(csv_path, profile.mode == schedule::Mode::kGeometry
                               ? profile.model.hinged.panels.size()
                               : std::size_t{0});
  }
}

void TrajectoryOutputs::Append(const Trajectory& block) {
  h5_.Append(block);
  if (csv_) csv_->Append(block);
}

void TrajectoryOutputs::Finish(const analysis::MissionResult& r) {
  h5_.Finish(r);
  if (csv_) csv_->Finish();
}

void TrajectoryOutputs::Commit() {
  h5_.Commit();
  if (csv_) csv_->Commit();
}

TrajectoryFile ReadTrajectoryFile(const std::string& path) {
  const QuietErrors quiet;
  // As in WriteTrajectoryFile: translate HDF5's exceptions to std::runtime_error.
  try {
    return ReadContents(path);
  } catch (const H5::Exception& e) {
    hdf5::Throw(path, e);
  }
}

}  // namespace deploysim::io
