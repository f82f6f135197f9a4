// io::LoadProfile, ApplyOverrides and the run-setting rules that need the integrator
// registry (docs/file_formats.md, "Deployment profiles"). Reading the file itself is
// io_yaml's (ReadProfile, yaml_profile.cc).

#include "deploysim/io/yaml_loader.h"

#include <cmath>
#include <stdexcept>
#include <string>
#include <vector>

#include "deploysim/analysis/exact_flow.h"
#include "deploysim/analysis/work_estimate.h"
#include "deploysim/math/number_format.h"

namespace deploysim::io {

namespace {

std::string Where(const schedule::Profile& p) {
  return p.source.empty() ? "profile '" + p.name + "'" : p.source;
}

void CheckRunSettings(const schedule::Profile& p) {
  run::CheckRunSettings(p);
  analysis::CheckWork(p, analysis::EstimateWork(p));
}

void Validate(const schedule::Profile& p) {
  schedule::ValidateProfile(p);
  CheckRunSettings(p);
}

}  // namespace

schedule::Profile LoadProfile(const std::string& path) {
  schedule::Profile p = ReadProfile(path);
  CheckRunSettings(p);
  return p;
}

schedule::Profile LoadProfileText(const std::string& text,
                                  const std::string& source,
                                  const std::string& base_dir,
                                  const model::Model* model) {
  schedule::Profile p = ReadProfileText(text, source, base_dir, model);
  CheckRunSettings(p);
  return p;
}

namespace {

/// Ends a stage profile at `until` (ProfileOverrides::until).
void EndStagesAt(schedule::Profile& p, double until, const std::string& where) {
  const auto refuse = [&](const std::string& rule) {
    throw std::invalid_argument(where + ": until = " + math::FormatNumber(until) +
                                " (override): " + rule);
  };
  std::vector<schedule::Stage>& st = p.stages;
  if (!(until > st.front().t_begin)) {
    refuse("must be > the start (" + math::FormatNumber(st.front().t_begin) + " s)");
  }
  if (until > st.back().t_end) {
    if (st.back().is_hold()) {
      st.back().t_end = until;
    } else {
      schedule::Stage hold;
      hold.name = "hold to the end";
      hold.from = hold.to = st.back().to;
      hold.t_begin = st.back().t_end;
      hold.t_end = until;
      st.push_back(hold);
    }
    return;
  }
  std::size_t k = 0;
  while (st[k].t_end < until) ++k;
  if (st[k].t_end != until && !st[k].is_hold()) {
    refuse("inside the move stage '" + st[k].name + "' (" + math::FormatNumber(st[k].t_begin) +
           " to " + math::FormatNumber(st[k].t_end) +
           " s): a stage profile ends in a hold stage or at a stage end");
  }
  st.resize(k + 1);
  st.back().t_end = until;
}

/// The overrides applied to `p`, unchecked (the caller validates the result).
void Override(schedule::Profile& p, const ProfileOverrides& o) {
  const std::string where = Where(p);
  if (o.method) p.integrator.method = *o.method;
  if (o.rtol) p.integrator.rtol = *o.rtol;
  if (o.atol) p.integrator.atol = *o.atol;
  if (o.step) p.integrator.step = *o.step;
  if (o.output_dt) p.output.dt = *o.output_dt;
  if (o.until) {
    if (p.is_hinge_profile()) {
      p.until = *o.until;
    } else {
      EndStagesAt(p, *o.until, where);
    }
  }
  if (o.mode) {
    const std::optional<schedule::Mode> m = FindMode(*o.mode);
    if (!m) {
      throw std::invalid_argument(where + ": mode = " + *o.mode +
                                  " (override): unknown mode (valid: " + ModeNames() + ")");
    }
    p.mode = *m;
  }
  if (o.coupling) {
    const std::optional<schedule::Coupling> c = FindCoupling(*o.coupling);
    if (!c) {
      throw std::invalid_argument(where + ": coupling = " + *o.coupling +
                                  " (override): unknown coupling (valid: " + CouplingNames() + ")");
    }
    p.coupling = *c;
  }
}

}  // namespace

void ApplyOverrides(schedule::Profile& profile, const ProfileOverrides& o) {
  schedule::Profile p = profile;
  Override(p, o);
  Validate(p);
  profile = std::move(p);
}

std::shared_ptr<const run::CompiledRun> LoadRun(const std::string& path,
                                                     const ProfileOverrides& o) {
  schedule::Profile p = ParseProfile(path);
  Override(p, o);
  return run::CompiledRun::Compile(std::move(p));
}

}  // namespace deploysim::io
