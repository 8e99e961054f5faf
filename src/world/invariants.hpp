#pragma once
// The FULCRUM_VALIDATE build (docs/validation.md): the engine's internal
// invariants checked at every phase boundary of the step.
//
// checkInvariants(w, phase) walks the body store, the contact graph, the
// islands and the solvers' colourings, and throws InvariantError naming the
// phase and the first broken invariant. It is always compiled (tests call it
// directly on a world they corrupted); the step calls it through
// FULCRUM_VALIDATE_PHASE, which compiles to nothing unless the library is
// built with the CMake option FULCRUM_VALIDATE (on in the sanitizer pass of
// scripts/test.sh). In such a build, FULCRUM_VALIDATE=0 in the environment
// skips the checks at run time (to measure what they cost).
//
// Every check is linear in the bodies, contacts and constraints, and reads
// only: no allocation once its scratch has grown (tests/allocation runs
// with it on).
#include <cstdint>
#include <stdexcept>
#include <string>

namespace fulcrum {
struct WorldImpl;
}

namespace fulcrum::detail {

// A broken internal invariant: a bug in the engine, not bad input, so not a
// fulcrum::Error (code that handles bad input must not swallow it).
class InvariantError : public std::logic_error {
public:
    explicit InvariantError(const std::string& what) : std::logic_error(what) {}
};

// The phase boundaries of WorldImpl::step, in step order. Which invariants
// hold depends on the phase: the awake list is exact only after a refresh,
// the colourings exist only between the prepare and the end of the step,
// and "no awake body touches a sleeping one" holds only after a wake pass.
enum class StepPhase : std::uint8_t {
    StepStart,        // before anything: the world as the user left it
    AfterCollide,     // broad and narrow phase done, their wakes applied to the awake list
    AfterPrepare,     // contact and joint constraints built and coloured
    AfterSubsteps,    // the sub-steps' integration and solver passes done
    AfterStore,       // restitution, impulses stored, joints stored (and maybe broken)
    AfterContinuous,  // time of impact (and the joints' projection after it)
    AfterSleep,       // islands built, resting ones asleep (particles stepped before)
    StepEnd,          // the step's last state, before the non-finite check throws
};

const char* phaseName(StepPhase phase);

// Throws InvariantError if an invariant that must hold at `phase` is broken.
void checkInvariants(const WorldImpl& w, StepPhase phase);

// Whether the step runs the checks: built with FULCRUM_VALIDATE and not
// turned off by the environment (FULCRUM_VALIDATE=0).
bool stepValidation();

}  // namespace fulcrum::detail

#ifdef FULCRUM_VALIDATE
#define FULCRUM_VALIDATE_PHASE(world, phase)                                                \
    do {                                                                                    \
        if (::fulcrum::detail::stepValidation())                                            \
            ::fulcrum::detail::checkInvariants(world, ::fulcrum::detail::StepPhase::phase); \
    } while (false)
#else
#define FULCRUM_VALIDATE_PHASE(world, phase) \
    do {                                     \
    } while (false)
#endif
