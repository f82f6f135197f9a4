#include "deploysim/model/model.h"

#include <stdexcept>

namespace deploysim::model {

const Configuration& Model::configuration(const std::string& config_name) const {
  for (const Configuration& c : configurations) {
    if (c.name == config_name) return c;
  }
  std::string valid;
  for (const Configuration& c : configurations) {
    valid += (valid.empty() ? "" : ", ") + c.name;
  }
  const std::string where = source.empty() ? "model '" + name + "'" : source;
  throw std::invalid_argument(where + ": configuration '" + config_name +
                              "' does not exist (rule: configuration must be one of: " +
                              (valid.empty() ? std::string("<none>") : valid) + ")");
}

}  // namespace deploysim::model
