// CSV trajectories (trajectory_csv.h).

#include "deploysim/io/trajectory_csv.h"

#include <cerrno>
#include <cstdint>
#include <cstring>
#include <fstream>
#include <iterator>
#include <stdexcept>
#include <string>
#include <vector>

#include "deploysim/io/atomic_file.h"
#include "deploysim/io/trajectory_file.h"
#include "deploysim/math/number_format.h"

namespace deploysim::io {

namespace {

using math::FormatNumber;

/// "name [units]" for a scalar, "<prefix>_<component> [units]" for each component of
/// the others (per panel: the panel index).
std::vector<std::string> Header(const run::TrajectorySchema& schema, std::size_t panels) {
  std::vector<std::string> h;
  for (const run::TrajectoryColumn& c : schema.columns()) {
    const std::string units = " [" + c.units + "]";
    if (c.shape == run::ColumnShape::kScalar) {
      h.push_back(c.name + units);
    } else if (c.shape == run::ColumnShape::kPerPanel) {
      for (std::size_t k = 0; k < panels; ++k) {
        h.push_back(c.csv_prefix + "_" + std::to_string(k) + units);
      }
    } else {
      for (const std::string& component : c.csv_components) {
        h.push_back(c.csv_prefix + "_" + component + units);
      }
    }
  }
  return h;
}

/// Sample k of t as one CSV line (with its newline).
std::string Line(const run::TrajectorySchema& schema,
                 const run::Trajectory& t,
                 std::size_t k,
                 std::size_t panels) {
  std::string line;
  auto put = [&line](double x) {
    if (!line.empty()) line += ',';
    line += FormatNumber(x);
  };
  double row[16];
  std::vector<double> wide;
  for (const run::TrajectoryColumn& c : schema.columns()) {
    const std::size_t width = run::Width(c, panels);
    if (width == 0) continue;
    double* values = row;
    if (width > std::size(row)) {
      wide.resize(width);
      values = wide.data();
    }
    c.values(t, k, values);
    if (c.csv_indices.empty()) {
      for (std::size_t i = 0; i < width; ++i) put(values[i]);
    } else {
      for (int i : c.csv_indices) put(values[i]);
    }
  }
  line += '\n';
  return line;
}

}  // namespace

struct TrajectoryCsvWriter::Impl {
  Impl(const std::string& p, std::size_t hinge, const run::TrajectorySchema& s)
      : path(p), hinge_columns(hinge), schema(s), file(p) {
    out.open(file.temporary_path(), std::ios::trunc);
    if (!out) Fail();
    const std::vector<std::string> header = Header(schema, hinge_columns);
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
  const run::TrajectorySchema& schema;
  AtomicFile file;
  std::ofstream out;
  std::uint64_t written = 0;
  bool finished = false;
};

TrajectoryCsvWriter::TrajectoryCsvWriter(const std::string& path,
                                         std::size_t hinge_columns,
                                         const run::TrajectorySchema& schema)
    : impl_(std::make_unique<Impl>(path, hinge_columns, schema)) {}

TrajectoryCsvWriter::~TrajectoryCsvWriter() = default;

void TrajectoryCsvWriter::Append(const run::Trajectory& t) {
  if (impl_->finished) throw std::logic_error(impl_->path + ": Append after Finish");
  const std::size_t hinge_columns = run::PanelCount(t);
  impl_->schema.Check(impl_->path, t, hinge_columns);
  if (t.size() > 0 && hinge_columns != impl_->hinge_columns) {
    throw std::invalid_argument(impl_->path + ": trajectory.hinge_angles rows have " +
                                std::to_string(hinge_columns) + " angles, the header " +
                                std::to_string(impl_->hinge_columns));
  }
  std::string text;
  for (std::size_t k = 0; k < t.size(); ++k) text += Line(impl_->schema, t, k, hinge_columns);
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

void WriteTrajectoryCsv(const std::string& path,
                        const run::Trajectory& t,
                        const run::TrajectorySchema& schema) {
  const std::size_t hinge_columns = run::PanelCount(t);
  schema.Check(path, t, hinge_columns);
  TrajectoryCsvWriter w(path, hinge_columns, schema);  // atomic: nothing at `path` unless Commit()
  w.Append(t);
  w.Finish();
  w.Commit();
}

}  // namespace deploysim::io
