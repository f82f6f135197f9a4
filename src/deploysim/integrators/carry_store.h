#pragma once

/// For stepper implementations (the integrators' and analysis::ExactFlowStepper's
/// workspaces), not for users of the steppers: values (rounding carries, relative
/// attitudes) keyed on the exact bits of the state they belong to (the keying rule of
/// StepperWorkspace).

#include "deploysim/integrators/stepper.h"

namespace deploysim::integrators {

template <class T>
class CarryStore {
 public:
  /// The value that belongs to exactly y (the last proposal, the accepted state or the
  /// one accepted before it), or nullptr.
  const T* Find(const State& y) const {
    for (const Slot* s : {&last_, &committed_, &previous_}) {
      if (s->valid && SameBits(s->key, y)) return &s->value;
    }
    return nullptr;
  }
  /// The value of a step's result (not yet accepted).
  void Propose(const State& result, const T& value) { last_ = {true, result, value}; }
  /// The driver accepted the last proposal as y1 (time possibly snapped).
  void Accept(const State& y1) {
    previous_ = committed_;
    committed_ = {last_.valid, y1, last_.value};
  }

 private:
  struct Slot {
    bool valid = false;
    State key;
    T value{};
  };
  Slot last_, committed_, previous_;
};

}  // namespace deploysim::integrators
