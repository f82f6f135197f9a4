#pragma once

/// Model files (YAML) -> validated model::Model, by the strict rules of yaml_reader.h.

#include <string>

#include "deploysim/model/model.h"

namespace deploysim::io {

/// Reads a model file (`kind: tensors` or `kind: hinged`). Model::source = path,
/// Model::text = the file's text.
/// Hinged models have their hinge axes normalized (model::ValidatedHingedBody).
model::Model LoadModel(const std::string& path);

/// LoadModel of a text that is no file (a document built in memory, e.g. from Python
/// dicts by the deploysim Python package): the same rules and the same one-line messages,
/// with `source` where a file's messages name the file. Model::source = source,
/// Model::text = text.
model::Model ReadModelText(const std::string& text, const std::string& source);

}  // namespace deploysim::io
