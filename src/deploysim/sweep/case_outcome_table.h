#pragma once

/// A sweep case's outcome (CaseOutcome), described once: per field its name in the
/// files, units, description, type, which sweeps have it, how a case's outcome gives its
/// value and, for a stored field, its place and bytes in the journal's record. Every
/// output of a case outcome is derived from CaseOutcomeTable (docs/design.md 4, "Records
/// described once"): the journal's record (journal.h), the results file's /cases
/// columns and /timing, their CSV (results_file.h) and the Python package's run_sweep
/// columns. A new outcome is one entry here; a stored one also needs its CaseOutcome
/// member and the line of SimulateOutcome that fills it (and, as it changes the
/// journal's record, a new journal layout version).

#include <cstddef>
#include <cstdint>
#include <functional>
#include <string>
#include <vector>

#include "deploysim/sweep/outcome.h"

namespace deploysim::sweep {

/// How a stored field is laid out in the journal's record (native byte order).
struct CaseFieldRecord {
  /// Position in the record: 0, 1, ... (the record's order is its own, frozen: a field
  /// takes the next free slot). -1: not stored (derived from stored fields).
  int slot = -1;
  std::size_t size = 0;                                      ///< bytes
  std::function<void(const CaseOutcome& o, char* out)> put;  ///< writes `size` bytes
  std::function<void(const char* in, CaseOutcome& o)> get;   ///< reads them back into o
};

struct CaseOutcomeField {
  enum class Type { kReal, kInteger, kText };
  /// Where the field is written.
  enum class Place {
    kCases,   ///< a /cases column (role `outcome`), its CSV column and Python column
    kTiming,  ///< /timing/<name> and the CSV's last columns: varies from run to run
    kRecord,  ///< the journal's record only (a part of other columns, e.g. `outcome`)
  };
  std::string name;         ///< dataset, CSV and Python column (journal: the member's name)
  std::string units;        ///< as the HDF5 `units` attribute ("none" for text)
  std::string description;  ///< as the HDF5 `description` attribute
  /// The description in a sweep over a hinge profile, where it differs (empty: the same).
  std::string hinge_description;
  Type type = Type::kReal;
  Place place = Place::kCases;
  bool hinge_only = false;  ///< only sweeps over hinge profiles have it
  /// The case's value, by type (kReal: real, kInteger: integer, kText: text).
  std::function<double(const CaseOutcome& o)> real;
  std::function<std::int64_t(const CaseOutcome& o)> integer;
  std::function<std::string(const CaseOutcome& o)> text;
  CaseFieldRecord record;

  bool stored() const { return record.slot >= 0; }
  /// The description in a sweep over a hinge profile (`hinges`) or a stage profile.
  const std::string& DescriptionFor(bool hinges) const;
  /// Whether a sweep over a hinge profile (`hinges`) or a stage profile has the field.
  bool In(bool hinges) const { return hinges || !hinge_only; }
};

/// The case outcome's fields: the standard ones in /cases column order (the fields that
/// are not /cases columns beside the columns made from them), and Extend (a field added
/// by a test or an extension before any output is written reaches every output).
class CaseOutcomeTable {
 public:
  static const std::vector<CaseOutcomeField>& Fields();
  /// The stored fields in record order (slot 0, 1, ...).
  static const std::vector<const CaseOutcomeField*>& RecordFields();
  /// Bytes of the stored fields (a journal record without its index and checksum).
  static std::size_t RecordPayloadSize();
  /// The fields of `place` in a sweep over a hinge profile (`hinges`) or a stage profile,
  /// in table order.
  static std::vector<const CaseOutcomeField*> Of(CaseOutcomeField::Place place, bool hinges);
  /// Appends a field. Throws std::logic_error for a repeated or empty name, a value
  /// missing for its type, or a stored field that does not take the next slot.
  static void Extend(CaseOutcomeField field);
};

}  // namespace deploysim::sweep
