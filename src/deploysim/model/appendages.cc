#include "deploysim/model/appendages.h"

#include <memory>
#include <stdexcept>
#include <string>
#include <utility>
#include <vector>

#include "deploysim/model/mass_properties.h"

namespace deploysim::model {

std::string AppendageWhere(const std::string& source, std::size_t k) {
  return source + ": appendages[" + std::to_string(k) + "]";
}

Appendage ExpandAppendage(HingedBody& body, const BeamSpec& spec, const std::string& where) {
  Appendage a = AddBeam(body, spec, where);
  a.beam = std::make_shared<const BeamSpec>(spec);
  return a;
}

Appendage ExpandAppendage(HingedBody& body, const SloshSpec& spec, const std::string& where) {
  Appendage a = AddSlosh(body, spec, where);
  a.slosh = std::make_shared<const SloshSpec>(spec);
  return a;
}

void RebuildAppendages(Model& m) {
  const std::string source = m.source.empty() ? "model '" + m.name + "'" : m.source;
  HingedBody body = m.declared;
  std::vector<Appendage> out;
  for (std::size_t k = 0; k < m.appendages.size(); ++k) {
    const Appendage& a = m.appendages[k];
    const std::string where = AppendageWhere(source, k);
    if (a.beam) {
      out.push_back(ExpandAppendage(body, *a.beam, where));
    } else if (a.slosh) {
      out.push_back(ExpandAppendage(body, *a.slosh, where));
    } else {
      throw std::invalid_argument(where + " (" + a.name +
                                  "): has no spec to expand again (rule: appendages made by "
                                  "ExpandAppendage, as the model file reader does)");
    }
  }
  body = ValidatedHingedBody(body, source);
  const std::vector<Panel>& before = m.hinged.panels;
  bool same = body.panels.size() == before.size();
  for (std::size_t i = 0; same && i < before.size(); ++i) {
    same = body.panels[i].name == before[i].name && body.panels[i].parent == before[i].parent;
  }
  if (!same) {
    throw std::invalid_argument(source + ": appendages: expanded again, they give other panels (" +
                                std::to_string(body.panels.size()) + " panels, were " +
                                std::to_string(before.size()) +
                                ") (rule: a changed parameter keeps every appendage's panels)");
  }
  m.hinged = std::move(body);
  m.appendages = std::move(out);
}

}  // namespace deploysim::model
