#pragma once

/// One rule for turning a model's appendages (model.h Appendage) into panels: the model
/// file reader expands each appendage with ExpandAppendage, and a sweep case that changes
/// an appendage's parameters (docs/sweeps.md: bending_stiffness, damping_ratio,
/// fill_fraction) expands them all again with RebuildAppendages, from the same specs and
/// the same declared body, so that a case's model is the one its model file would give.

#include <cstddef>
#include <string>

#include "deploysim/model/flexible_beam.h"
#include "deploysim/model/model.h"
#include "deploysim/model/slosh.h"

namespace deploysim::model {

/// "<source>: appendages[k]": where the messages about appendage k of a model file point
/// (`source` is the model's file, or "model '<name>'" for one made in code).
std::string AppendageWhere(const std::string& source, std::size_t k);

/// Appends the beam's panels to `body` (AddBeam) and returns its Appendage with the spec
/// kept (Appendage::beam). Throws as AddBeam.
Appendage ExpandAppendage(HingedBody& body, const BeamSpec& spec, const std::string& where);

/// Appends the slosh pendulum to `body` (AddSlosh) and returns its Appendage with the spec
/// kept (Appendage::slosh). Throws as AddSlosh.
Appendage ExpandAppendage(HingedBody& body, const SloshSpec& spec, const std::string& where);

/// Expands m's appendages again, in order, from the specs they keep onto m.declared, and
/// sets m.hinged (validated: ValidatedHingedBody) and m.appendages. For a model whose
/// specs were changed. The panels must come out as before, in number, names and parents
/// (profiles' hinge plans and configurations index them): a change that alters them is
/// refused. Throws std::invalid_argument "<source>: appendages[k]...: <rule>" for a spec
/// outside its ranges, such a change, or an appendage without a spec (made in code).
void RebuildAppendages(Model& m);

}  // namespace deploysim::model
