#include "deploysim/analysis/hinge_events.h"

namespace deploysim::analysis {

std::string ToString(HingeEvent::Kind kind) {
  switch (kind) {
    case HingeEvent::Kind::kRelease:
      return "release";
    case HingeEvent::Kind::kLatch:
      return "latch";
    case HingeEvent::Kind::kJam:
      return "jam";
    case HingeEvent::Kind::kStop:
      return "stop";
    case HingeEvent::Kind::kRest:
      return "rest";
    case HingeEvent::Kind::kLiftOff:
      return "lift-off";
    case HingeEvent::Kind::kStick:
      return "stick";
    case HingeEvent::Kind::kSlip:
      return "slip";
  }
  return "unknown";
}

}  // namespace deploysim::analysis
