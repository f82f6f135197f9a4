#include "deploysim/run/trajectory_schema.h"

#include <stdexcept>
#include <utility>

#include "deploysim/math/quaternion.h"

namespace deploysim::run {

namespace {

/// How a member type's entries become flat values and back.
template <class T>
struct Flat;

template <>
struct Flat<double> {
  static constexpr ColumnShape kShape = ColumnShape::kScalar;
  static std::size_t Width(double /*x*/) { return 1; }
  static void Write(double x, double* row) { row[0] = x; }
  static double Read(const double* row, std::size_t /*width*/) { return row[0]; }
};

template <>
struct Flat<math::Vec3> {
  static constexpr ColumnShape kShape = ColumnShape::kVector3;
  static std::size_t Width(const math::Vec3& /*x*/) { return 3; }
  static void Write(const math::Vec3& x, double* row) {
    for (int i = 0; i < 3; ++i) row[i] = x[i];
  }
  static math::Vec3 Read(const double* row, std::size_t /*width*/) {
    return math::Vec3(row[0], row[1], row[2]);
  }
};

template <>
struct Flat<math::Quat> {
  static constexpr ColumnShape kShape = ColumnShape::kQuaternion;
  static std::size_t Width(const math::Quat& /*q*/) { return 4; }
  static void Write(const math::Quat& q, double* row) {
    const math::Vec4 wxyz = math::ToWxyz(q);
    for (int i = 0; i < 4; ++i) row[i] = wxyz[i];
  }
  static math::Quat Read(const double* row, std::size_t /*width*/) {
    return math::FromWxyz(math::Vec4(row[0], row[1], row[2], row[3]));
  }
};

template <>
struct Flat<math::Mat3> {
  static constexpr ColumnShape kShape = ColumnShape::kMatrix3;
  static std::size_t Width(const math::Mat3& /*M*/) { return 9; }
  static void Write(const math::Mat3& M, double* row) {
    for (int i = 0; i < 3; ++i) {
      for (int j = 0; j < 3; ++j) row[3 * i + j] = M(i, j);
    }
  }
  static math::Mat3 Read(const double* row, std::size_t /*width*/) {
    math::Mat3 M;
    for (int i = 0; i < 3; ++i) {
      for (int j = 0; j < 3; ++j) M(i, j) = row[3 * i + j];
    }
    return M;
  }
};

template <>
struct Flat<Eigen::VectorXd> {
  static constexpr ColumnShape kShape = ColumnShape::kPerPanel;
  static std::size_t Width(const Eigen::VectorXd& x) { return static_cast<std::size_t>(x.size()); }
  static void Write(const Eigen::VectorXd& x, double* row) {
    for (Eigen::Index i = 0; i < x.size(); ++i) row[i] = x[i];
  }
  static Eigen::VectorXd Read(const double* row, std::size_t width) {
    return Eigen::Map<const Eigen::VectorXd>(row, static_cast<Eigen::Index>(width));
  }
};

template <class T>
class MemberStorage final : public ColumnStorage {
 public:
  explicit MemberStorage(std::vector<T> Trajectory::*member) : m_(member) {}
  std::size_t size(const Trajectory& t) const override { return (t.*m_).size(); }
  std::size_t width(const Trajectory& t, std::size_t k) const override {
    return Flat<T>::Width((t.*m_)[k]);
  }
  void clear(Trajectory& t) const override { (t.*m_).clear(); }
  void append(Trajectory& to, const Trajectory& from) const override {
    (to.*m_).insert((to.*m_).end(), (from.*m_).begin(), (from.*m_).end());
  }
  void keep(Trajectory& to, const Trajectory& from, std::size_t k) const override {
    (to.*m_).clear();
    if (k < (from.*m_).size()) (to.*m_).push_back((from.*m_)[k]);
  }
  void push(Trajectory& t, const double* row, std::size_t width) const override {
    (t.*m_).push_back(Flat<T>::Read(row, width));
  }

 private:
  std::vector<T> Trajectory::*m_;
};

const std::vector<std::string> kXyz = {"x", "y", "z"};

/// A column stored in `member`; CSV components x, y, z (vectors), w, x, y, z
/// (quaternions) unless given.
template <class T>
TrajectoryColumn Stored(std::vector<T> Trajectory::*member,
                        std::string name,
                        std::string units,
                        std::string description,
                        std::vector<std::string> components = {}) {
  TrajectoryColumn c;
  c.name = std::move(name);
  c.units = std::move(units);
  c.description = std::move(description);
  c.shape = Flat<T>::kShape;
  c.csv_prefix = c.name;
  if (c.shape == ColumnShape::kVector3 && components.empty()) components = kXyz;
  if (c.shape == ColumnShape::kQuaternion) components = {"w", "x", "y", "z"};
  c.csv_components = std::move(components);
  for (std::size_t i = 0; i < c.csv_components.size(); ++i) {
    c.csv_indices.push_back(static_cast<int>(i));
  }
  c.values = [member](const Trajectory& t, std::size_t k, double* row) {
    Flat<T>::Write((t.*member)[k], row);
  };
  c.storage = std::make_shared<MemberStorage<T>>(member);
  return c;
}

TrajectoryColumn HingeOutput(TrajectoryColumn c) {
  c.free_hinge_output = true;
  return c;
}

/// A column of the energy ledger (mission.h, WorkLedger): work done on the system since
/// the start by one source, so that /energy_total = its first value + the columns' sum.
TrajectoryColumn Ledger(std::vector<double> Trajectory::*member,
                        const std::string& source,
                        const std::string& what) {
  TrajectoryColumn c = Stored(member, "work_" + source, "J",
                              "energy ledger: work done on the system since the start by " + what);
  c.ledger_output = true;
  return c;
}

/// Per-panel columns: "<prefix>_<panel> [units]" in CSV.
TrajectoryColumn CsvPrefix(TrajectoryColumn c, std::string prefix) {
  c.csv_prefix = std::move(prefix);
  return c;
}

/// J_B in CSV: its six distinct entries (the tensor is symmetric).
TrajectoryColumn SymmetricCsv(TrajectoryColumn c) {
  c.csv_components = {"xx", "yy", "zz", "xy", "xz", "yz"};
  c.csv_indices = {0, 4, 8, 1, 2, 5};
  return c;
}

TrajectoryColumn EnergyTotal() {
  TrajectoryColumn c;
  c.name = "energy_total";
  c.csv_prefix = c.name;
  c.units = "J";
  c.description =
      "/energy + /energy_spring: constant without dampers, motors and friction except for the "
      "steps down at latches, jams and stop impacts";
  c.free_hinge_output = true;
  c.values = [](const Trajectory& t, std::size_t k, double* row) {
    row[0] = t.energy[k] + t.energy_spring[k];
  };
  return c;
}

TrajectorySchema MakeStandard() {
  using T = Trajectory;
  TrajectorySchema s;
  for (TrajectoryColumn& c : std::vector<TrajectoryColumn>{
           Stored(&T::time, "time", "s", "output grid"),
           Stored(&T::H_B, "H_B", "kg m^2/s",
                  "total angular momentum about the system centre of mass, body (B) components"),
           Stored(&T::w_NB_B, "w_NB_B", "rad/s", "angular velocity of B in N, B components"),
           Stored(&T::q_NB, "q_NB", "1",
                  "attitude quaternion q_NB (v_N = q_NB v_B), Hamilton, scalar first (w, x, y, z)"),
           SymmetricCsv(Stored(
               &T::J_B, "J_B", "kg m^2",
               "inertia tensor about the system centre of mass, B components; J_B[n][i][j]")),
           Stored(&T::principal_moments, "principal_moments", "kg m^2",
                  "eigenvalues of J_B, ascending", {"1", "2", "3"}),
           Stored(&T::h_rel_B, "h_rel_B", "kg m^2/s",
                  "momentum of the panels' motion relative to B, B components"),
           Stored(&T::h_N, "h_N", "kg m^2/s",
                  "total angular momentum, inertial (N) components (constant in exact "
                  "arithmetic)"),
           Stored(&T::energy, "energy", "J",
                  "total kinetic energy about the system centre of mass, 1/2 w.J_B w + "
                  "w.h_rel_B + T_rel (T_rel: kinetic energy of the panels' motion relative to "
                  "B; h_rel_B and T_rel are 0 under quasi-rigid coupling)"),
           Stored(&T::energy_rigid, "energy_rigid", "J",
                  "rigid-body part 1/2 w.J_B w of /energy (equal to it when nothing moves "
                  "relative to B)"),
           Stored(&T::euler_313, "euler_313", "rad",
                  "3-1-3 Euler angles (precession, nutation, spin) of B relative to a frame "
                  "whose third axis is h_N",
                  {"precession", "nutation", "spin"}),
           Stored(&T::spin_axis_angle, "spin_axis_angle", "rad",
                  "angle between the initial spin axis (fixed in B) and h_N"),
           CsvPrefix(Stored(&T::hinge_angles, "hinge_angles", "rad",
                            "hinge angle of each panel, in panel order (geometry mode)"),
                     "hinge_angle"),
           HingeOutput(Stored(&T::energy_spring, "energy_spring", "J",
                              "energy stored in the free hinges' torsion springs, sum of 1/2 k "
                              "(theta - theta_rest)^2 - preload (theta - theta_rest) over every "
                              "hinge with a free plan, held and latched ones included; 0 for "
                              "stage profiles")),
           EnergyTotal(),
           CsvPrefix(HingeOutput(Stored(&T::hinge_rates, "hinge_rates", "rad/s",
                                        "hinge rate (time derivative of the hinge angle) of "
                                        "each panel, in panel order (geometry mode)")),
                     "hinge_rate"),
           Ledger(&T::work_damper, "damper", "the free hinges' dampers (<= 0)"),
           Ledger(&T::work_friction, "friction", "the free hinges' friction (<= 0)"),
           Ledger(&T::work_motor, "motor", "the free hinges' motors and servos"),
           Ledger(&T::work_drive, "drive",
                  "the drives that hold the prescribed hinge motions and stage laws, their "
                  "impulses at events included"),
           Ledger(&T::work_impacts, "impacts",
                  "the impulses at latches, jams and stop impacts: minus the energy they "
                  "dissipate"),
       }) {
    s.Add(std::move(c));
  }
  return s;
}

}  // namespace

std::size_t Width(const TrajectoryColumn& c, std::size_t panels) {
  switch (c.shape) {
    case ColumnShape::kScalar:
      return 1;
    case ColumnShape::kVector3:
      return 3;
    case ColumnShape::kQuaternion:
      return 4;
    case ColumnShape::kMatrix3:
      return 9;
    case ColumnShape::kPerPanel:
      break;
  }
  return panels;
}

std::vector<std::size_t> RowShape(const TrajectoryColumn& c, std::size_t panels) {
  switch (c.shape) {
    case ColumnShape::kScalar:
      return {};
    case ColumnShape::kMatrix3:
      return {3, 3};
    default:
      return {Width(c, panels)};
  }
}

const TrajectorySchema& TrajectorySchema::Standard() {
  static const TrajectorySchema standard = MakeStandard();
  return standard;
}

void TrajectorySchema::Add(TrajectoryColumn c) {
  auto fail = [&c](const std::string& rule) {
    throw std::invalid_argument("trajectory column '" + c.name + "': " + rule);
  };
  if (c.name.empty()) fail("a column needs a name");
  for (const TrajectoryColumn& x : columns_) {
    if (x.name == c.name) fail("the name is taken (rule: one column per name)");
  }
  if (!c.values) fail("no values (rule: every column says how its values are computed)");
  if (c.csv_prefix.empty()) c.csv_prefix = c.name;
  if (c.shape == ColumnShape::kPerPanel || c.shape == ColumnShape::kScalar) {
    if (!c.csv_components.empty()) fail("CSV components for a scalar or per-panel column");
  } else if (c.csv_components.size() != c.csv_indices.size() || c.csv_components.empty()) {
    fail("CSV components and indices differ in number (rule: one index per component)");
  }
  for (int i : c.csv_indices) {
    if (i < 0 || static_cast<std::size_t>(i) >= Width(c, 0)) fail("CSV index out of the row");
  }
  columns_.push_back(std::move(c));
}

std::vector<const TrajectoryColumn*> TrajectorySchema::Written(bool per_panel) const {
  std::vector<const TrajectoryColumn*> out;
  for (const TrajectoryColumn& c : columns_) {
    if (per_panel || c.shape != ColumnShape::kPerPanel) out.push_back(&c);
  }
  return out;
}

void TrajectorySchema::Check(const std::string& what,
                             const Trajectory& t,
                             std::size_t panels) const {
  const std::size_t n = t.time.size();
  for (const TrajectoryColumn& c : columns_) {
    if (!c.storage) continue;
    const bool per_panel = c.shape == ColumnShape::kPerPanel;
    if (per_panel && panels == 0) continue;
    const std::size_t size = c.storage->size(t);
    if (size != n) {
      throw std::invalid_argument(what + ": trajectory." + c.name + " has " + std::to_string(size) +
                                  " samples, time has " + std::to_string(n) +
                                  " (rule: one sample per output time)");
    }
    for (std::size_t k = 0; per_panel && k < n; ++k) {
      const std::size_t width = c.storage->width(t, k);
      if (width != panels) {
        throw std::invalid_argument(what + ": trajectory." + c.name + "[" + std::to_string(k) +
                                    "] has " + std::to_string(width) + " entries, not " +
                                    std::to_string(panels) + " (rule: one per panel)");
      }
    }
  }
}

void TrajectorySchema::Clear(Trajectory& t) const {
  for (const TrajectoryColumn& c : columns_) {
    if (c.storage) c.storage->clear(t);
  }
}

void TrajectorySchema::Append(Trajectory& to, const Trajectory& from) const {
  for (const TrajectoryColumn& c : columns_) {
    if (c.storage) c.storage->append(to, from);
  }
}

Trajectory TrajectorySchema::Row(const Trajectory& from, std::size_t k) const {
  Trajectory row;
  for (const TrajectoryColumn& c : columns_) {
    if (c.storage) c.storage->keep(row, from, k);
  }
  return row;
}

std::size_t PanelCount(const Trajectory& t) {
  return t.hinge_angles.empty() ? 0 : static_cast<std::size_t>(t.hinge_angles.front().size());
}

}  // namespace deploysim::run
