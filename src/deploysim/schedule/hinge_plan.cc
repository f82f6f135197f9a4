#include "deploysim/schedule/hinge_plan.h"

namespace deploysim::schedule {

std::string ToString(HingePlan::Kind kind) {
  switch (kind) {
    case HingePlan::Kind::kLocked:
      return "locked";
    case HingePlan::Kind::kPrescribed:
      return "prescribed";
    case HingePlan::Kind::kFree:
      return "free";
  }
  return "unknown";
}

}  // namespace deploysim::schedule
