#pragma once

/// What the record tables (HingeEventTable, StageTable, DangerWindowTable) share: a column
/// added by name, once.

#include <stdexcept>
#include <string>
#include <utility>
#include <vector>

namespace deploysim::run {

/// Appends `column` to `table` (named `what` in the message): std::logic_error if a
/// column of its name exists.
template <typename Column>
void AppendColumn(std::vector<Column>& table, Column column, const std::string& what) {
  for (const Column& c : table) {
    if (c.name == column.name) {
      throw std::logic_error(what + ": a column '" + column.name + "' exists");
    }
  }
  table.push_back(std::move(column));
}

}  // namespace deploysim::run
