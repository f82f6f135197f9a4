// CSV trajectories (WriteTrajectoryCsv in trajectory_file.h).

#include <cerrno>
#include <cstdint>
#include <cstring>
#include <fstream>
#include <stdexcept>
#include <string>
#include <vector>

#include "deploysim/io/atomic_file.h"
#include "deploysim/io/trajectory_file.h"
#include "deploysim/math/number_format.h"
#include "deploysim/math/quaternion.h"

namespace deploysim::io {

namespace {

using math::FormatNumber;

std::vector<std::string> Header(std::size_t hinge_columns) {
  std::vector<std::string> h = {"time [s]"};
  auto add = [&h](const std::string& name, const std::vector<std::string>& components,
                  const std::string& unit) {
    for (const std::string& c : components) h.push_back(name + "_" + c + " [" + unit + "]");
  };
  const std::vector<std::string> xyz = {"x", "y", "z"};
  add("H_B", xyz, "kg m^2/s");
  add("w_NB_B", xyz, "rad/s");
  add("q_NB", {"w", "x", "y", "z"}, "1");
  add("J_B", {"xx", "yy", "zz", "xy", "xz", "yz"}, "kg m^2");
  add("principal_moments", {"1", "2", "3"}, "kg m^2");
  add("h_rel_B", xyz, "kg m^2/s");
  add("h_N", xyz, "kg m^2/s");
  h.push_back("energy [J]");
  h.push_back("energy_rigid [J]");
  add("euler_313", {"precession", "nutation", "spin"}, "rad");
  h.push_back("spin_axis_angle [rad]");
  for (std::size_t k = 0; k < hinge_columns; ++k) {
    h.push_back("hinge_angle_" + std::to_string(k) + " [rad]");
  }
  // The free-hinge columns come after the older ones, which keep their positions.
  h.push_back("energy_spring [J]");
  h.push_back("energy_total [J]");
  for (std::size_t k = 0; k < hinge_columns; ++k) {
    h.push_back("hinge_rate_" + std::to_string(k) + " [rad/s]");
  }
  return h;
}

void Check(const std::string& path, const analysis::Trajectory& t, std::size_t& hinge_columns) {
  const std::size_t n = t.time.size();
  const std::size_t sizes[] = {t.H_B.size(),
                               t.w_NB_B.size(),
                               t.q_NB.size(),
                               t.J_B.size(),
                               t.principal_moments.size(),
                               t.h_rel_B.size(),
                               t.h_N.size(),
                               t.energy.size(),
                               t.energy_rigid.size(),
                               t.energy_spring.size(),
                               t.euler_313.size(),
                               t.spin_axis_angle.size()};
  for (std::size_t s : sizes) {
    if (s != n) {
      throw std::invalid_argument(path + ": trajectory arrays have " + std::to_string(s) + " and " +
                                  std::to_string(n) +
                                  " samples (rule: one sample per output time)");
    }
  }
  hinge_columns = 0;
  if (!t.hinge_angles.empty()) {
    if (t.hinge_angles.size() != n) {
      throw std::invalid_argument(path + ": trajectory.hinge_angles has " +
                                  std::to_string(t.hinge_angles.size()) + " samples, time has " +
                                  std::to_string(n) + " (rule: one sample per output time)");
    }
    hinge_columns = static_cast<std::size_t>(t.hinge_angles.front().size());
    for (const Eigen::VectorXd& h : t.hinge_angles) {
      if (static_cast<std::size_t>(h.size()) != hinge_columns) {
        throw std::invalid_argument(path + ": trajectory.hinge_angles rows differ in length");
      }
    }
    if (t.hinge_rates.size() != n) {
      throw std::invalid_argument(path + ": trajectory.hinge_rates has " +
                                  std::to_string(t.hinge_rates.size()) + " samples, time has " +
                                  std::to_string(n) +
                                  " (rule: hinge rates wherever there are hinge angles)");
    }
    for (const Eigen::VectorXd& h : t.hinge_rates) {
      if (static_cast<std::size_t>(h.size()) != hinge_columns) {
        throw std::invalid_argument(path + ": trajectory.hinge_rates rows have " +
                                    std::to_string(h.size()) + " rates, hinge_angles rows " +
                                    std::to_string(hinge_columns) +
                                    " angles (rule: one rate per hinge angle)");
      }
    }
  }
}

}  // namespace

struct TrajectoryCsvWriter::Impl {
  Impl(const std::string& p, std::size_t hinge) : path(p), hinge_columns(hinge), file(p) {
    out.open(file.temporary_path(), std::ios::trunc);
    if (!out) Fail();
    const std::vector<std::string> header = Header(hinge_columns);
    std::string line;
    for (std::size_t i = 0; i < header.size(); ++i) line += (i ? "," : "") + header[i];
    line += '\n';
    Write(line);
  }
  [[noreturn]] void Fail() {
    const int err = errno;
    throw std::runtime_error(path +
                             ": cannot write: " + (err != 0 ? std::strerror(err) : "output error"));
  }
  // Writes `text` after checking that the file may grow by it (AtomicFile::Reserve: a
  // full disk or the size limit is reported here, by name, not as a stream state).
  void Write(const std::string& text) {
    written += text.size();
    file.Reserve(written);
    errno = 0;
    out.write(text.data(), static_cast<std::streamsize>(text.size()));
    if (!out) Fail();
  }
  std::string path;
  std::size_t hinge_columns;
  AtomicFile file;
  std::ofstream out;
  std::uint64_t written = 0;
  bool finished = false;
};

TrajectoryCsvWriter::TrajectoryCsvWriter(const std::string& path, std::size_t hinge_columns)
    : impl_(std::make_unique<Impl>(path, hinge_columns)) {}

TrajectoryCsvWriter::~TrajectoryCsvWriter() = default;

void TrajectoryCsvWriter::Append(const analysis::Trajectory& t) {
  if (impl_->finished) throw std::logic_error(impl_->path + ": Append after Finish");
  std::size_t hinge_columns = 0;
  Check(impl_->path, t, hinge_columns);
  if (t.size() > 0 && hinge_columns != impl_->hinge_columns) {
    throw std::invalid_argument(impl_->path + ": trajectory.hinge_angles rows have " +
                                std::to_string(hinge_columns) + " angles, the header " +
                                std::to_string(impl_->hinge_columns));
  }
  std::string text;
  for (std::size_t k = 0; k < t.size(); ++k) {
    std::string line;
    auto put = [&line](double x) {
      if (!line.empty()) line += ',';
      line += FormatNumber(x);
    };
    put(t.time[k]);
    for (int i = 0; i < 3; ++i) put(t.H_B[k][i]);
    for (int i = 0; i < 3; ++i) put(t.w_NB_B[k][i]);
    const math::Vec4 q = math::ToWxyz(t.q_NB[k]);
    for (int i = 0; i < 4; ++i) put(q[i]);
    const math::Mat3& J = t.J_B[k];
    for (double x : {J(0, 0), J(1, 1), J(2, 2), J(0, 1), J(0, 2), J(1, 2)}) put(x);
    for (int i = 0; i < 3; ++i) put(t.principal_moments[k][i]);
    for (int i = 0; i < 3; ++i) put(t.h_rel_B[k][i]);
    for (int i = 0; i < 3; ++i) put(t.h_N[k][i]);
    put(t.energy[k]);
    put(t.energy_rigid[k]);
    for (int i = 0; i < 3; ++i) put(t.euler_313[k][i]);
    put(t.spin_axis_angle[k]);
    for (std::size_t i = 0; i < hinge_columns; ++i) {
      put(t.hinge_angles[k][static_cast<Eigen::Index>(i)]);
    }
    put(t.energy_spring[k]);
    put(t.energy[k] + t.energy_spring[k]);
    for (std::size_t i = 0; i < hinge_columns; ++i) {
      put(t.hinge_rates[k][static_cast<Eigen::Index>(i)]);
    }
    text += line;
    text += '\n';
  }
  impl_->Write(text);
}

void TrajectoryCsvWriter::Finish() {
  errno = 0;
  impl_->out.close();
  if (!impl_->out) impl_->Fail();
  impl_->file.ReleaseReserve();
  impl_->finished = true;
}

void TrajectoryCsvWriter::Commit() {
  if (!impl_->finished) throw std::logic_error(impl_->path + ": Commit before Finish");
  impl_->file.Commit();
}

void WriteTrajectoryCsv(const std::string& path, const analysis::Trajectory& t) {
  std::size_t hinge_columns = 0;
  Check(path, t, hinge_columns);
  TrajectoryCsvWriter w(path, hinge_columns);  // atomic: nothing at `path` unless Commit()
  w.Append(t);
  w.Finish();
  w.Commit();
}

}  // namespace deploysim::io
