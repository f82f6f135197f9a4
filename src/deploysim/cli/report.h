#pragma once

/// Human-readable and JSON reports of a mission (used by `deploysim simulate` and
/// `deploysim analyze`).

#include <string>

#include "deploysim/analysis/coupling_comparison.h"
#include "deploysim/analysis/mission.h"

namespace deploysim::cli {

/// The stability table: one row per stage, then flips, danger windows, invariants.
std::string FormatSummary(const analysis::MissionResult& r);

/// The same content as a JSON document.
std::string FormatJson(const analysis::MissionResult& r, const analysis::CouplingComparison* c);

/// Exact vs quasi-rigid coupling, a few lines.
std::string FormatCouplingComparison(const analysis::CouplingComparison& c);

}  // namespace deploysim::cli
