#include "deploysim/dynamics/shape_system.h"

namespace deploysim::dynamics {

std::vector<double> ShapeSystem::Breakpoints(double /*t0*/, double /*t1*/) const { return {}; }

}  // namespace deploysim::dynamics
