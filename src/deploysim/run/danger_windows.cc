#include "deploysim/run/danger_windows.h"

#include <stdexcept>
#include <utility>

#include "deploysim/run/record_table.h"

namespace deploysim::run {

namespace {

DangerWindowColumn Member(double DangerWindow::*m, std::string name, std::string description) {
  DangerWindowColumn c;
  c.name = std::move(name);
  c.units = "s";
  c.description = std::move(description);
  c.value = [m](const DangerWindow& w) { return w.*m; };
  c.set = [m](DangerWindow& w, double v) { w.*m = v; };
  return c;
}

std::vector<DangerWindowColumn>& DangerWindowColumns() {
  static std::vector<DangerWindowColumn> table = {
      Member(&DangerWindow::t_begin, "t_begin",
             "first output time at which the spin axis is the intermediate axis"),
      Member(&DangerWindow::t_end, "t_end", "last output time of the window at which it still is"),
  };
  return table;
}

}  // namespace

const std::vector<DangerWindowColumn>& DangerWindowTable::Columns() {
  return DangerWindowColumns();
}

void DangerWindowTable::Extend(DangerWindowColumn column) {
  AppendColumn(DangerWindowColumns(), std::move(column), "DangerWindowTable");
}

}  // namespace deploysim::run
