#include "engine/seed_solver.h"

#include "engine/error.h"

namespace napkin::engine {

Kinematics SolveSeed(const ArrayGeometry&, const TestSignals&, const InitialState&) {
  throw InputError("the seed solver is not implemented yet.");
}

}  // namespace napkin::engine
