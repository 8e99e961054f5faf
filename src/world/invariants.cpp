// The FULCRUM_VALIDATE checks (invariants.hpp; docs/validation.md).
//
// Each check reads the world and the subsystems through their const
// accessors and reports the first broken invariant. The order matters: the
// body store's maps are checked first, so every later check may follow a
// slot to its dense index (and name the body) without going out of bounds.
#include "world/invariants.hpp"

#include <cstdlib>
#include <vector>

#include "world/world_impl.hpp"

namespace fulcrum::detail {

namespace {

// Scratch that grows to the largest world seen on this thread and is then
// reused: the checks allocate nothing per step (tests/allocation runs with them).
template <class T>
std::vector<T>& cleared(std::vector<T>& v, std::size_t size) {
    v.assign(size, T{});
    return v;
}
thread_local std::vector<std::uint8_t> tBodyMarks;
thread_local std::vector<std::uint64_t> tColourMasks;

class Checker {
public:
    Checker(const WorldImpl& w, StepPhase phase) : w_(w), phase_(phase) {}

    void run() {
        // Scratch for the most it can need (a solver body per body, plus the
        // static stand-in; a constraint per joint), sized in the first
        // step, so later steps allocate nothing when more bodies wake.
        tBodyMarks.reserve(bodyCount());
        tColourMasks.reserve(bodyCount() + 1);
        tJointColours.reserve(w_.joints.size());
        bodyStore();
        awakeList();
        staticBodies();
        if (phase_ == StepPhase::StepStart) finiteAwakeStates();
        contactGraph();
        islands();
        if (phase_ == StepPhase::AfterCollide || phase_ == StepPhase::AfterSleep) noAwakeBodyTouchesASleeper();
        if (phase_ == StepPhase::AfterPrepare || phase_ == StepPhase::AfterSubsteps) {
            solverBodies();
            contactColours();
            jointColours();
        }
    }

private:
    [[noreturn]] void fail(const char* area, const std::string& what) const {
        throw InvariantError(std::string("FULCRUM_VALIDATE: invariant broken ") + phaseName(phase_) + ": " + area +
                             ": " + what);
    }
    static std::string num(std::size_t n) { return std::to_string(n); }
    std::string body(std::uint32_t dense) const { return w_.describeBody(dense) + " (dense " + num(dense) + ")"; }
    std::size_t bodyCount() const { return w_.motion.size(); }
    std::uint32_t denseOfSlot(std::uint32_t slot) const { return w_.bodySlots[slot].dense; }
    bool isStatic(std::uint32_t dense) const { return w_.params[dense].type == BodyType::Static; }

    // Slots <-> dense indices, and every per-body array the same length.
    void bodyStore() const {
        const std::size_t n = bodyCount();
        const auto sameLength = [&](std::size_t size, const char* name) {
            if (size != n) fail("body store", std::string(name) + " holds " + num(size) + " entries for " + num(n) + " bodies");
        };
        sameLength(w_.forces.size(), "forces");
        sameLength(w_.applied.size(), "applied");
        sameLength(w_.params.size(), "params");
        sameLength(w_.cold.size(), "cold");
        sameLength(w_.previous.size(), "previous");
        sameLength(w_.denseToSlot.size(), "denseToSlot");
        sameLength(w_.scratch.size(), "scratch");
        for (std::uint32_t d = 0; d < n; ++d) {
            const std::uint32_t slot = w_.denseToSlot[d];
            if (slot >= w_.bodySlots.size()) {
                fail("body store", "denseToSlot[" + num(d) + "] = " + num(slot) + " is past the " + num(w_.bodySlots.size()) + " slots");
            }
            if (w_.bodySlots[slot].dense != d) {
                fail("body store", "denseToSlot[" + num(d) + "] = " + num(slot) + " but that slot maps to dense " +
                                       num(w_.bodySlots[slot].dense));
            }
        }
        std::size_t live = 0;
        for (std::uint32_t s = 0; s < w_.bodySlots.size(); ++s) {
            const std::uint32_t d = w_.bodySlots[s].dense;
            if (d == kNoIndex) continue;
            ++live;
            if (d >= n) fail("body store", "slot " + num(s) + " maps to dense " + num(d) + ", past the " + num(n) + " bodies");
            if (w_.denseToSlot[d] != s) {
                fail("body store", "slot " + num(s) + " maps to dense " + num(d) + " but denseToSlot[" + num(d) + "] = " +
                                       num(w_.denseToSlot[d]));
            }
        }
        if (live != n) fail("body store", num(live) + " live slots for " + num(n) + " bodies");
        if (w_.freeBodySlots.size() != w_.bodySlots.size() - live) {
            fail("body store", num(w_.freeBodySlots.size()) + " free slots listed, " + num(w_.bodySlots.size() - live) + " free");
        }
        for (const std::uint32_t s : w_.freeBodySlots) {
            if (s >= w_.bodySlots.size() || w_.bodySlots[s].dense != kNoIndex) {
                fail("body store", "free slot list holds slot " + num(s) + ", which is not free");
            }
        }
    }

    // awakeBodies: ascending, awake, non-static and complete, once the
    // updates queued since the last refresh (wokenBodies, sleepers, a
    // rebuild) are taken into account; with none queued, exactly the awake
    // non-static bodies.
    void awakeList() const {
        const bool exact = phase_ == StepPhase::AfterCollide || phase_ == StepPhase::AfterPrepare;
        if (exact && (w_.awakeListRebuild || w_.awakeListHasSleepers || !w_.wokenBodies.empty())) {
            fail("awake list", "not refreshed: the sub-steps would walk a stale list");
        }
        if (w_.awakeListRebuild) return;  // rebuilt from the bodies at the next refresh
        const std::size_t n = bodyCount();
        if (w_.inAwakeList.size() != n) fail("awake list", "inAwakeList holds " + num(w_.inAwakeList.size()) + " flags for " + num(n) + " bodies");
        std::size_t flagged = 0;
        for (std::uint32_t d = 0; d < n; ++d) flagged += w_.inAwakeList[d] != 0 ? 1 : 0;
        if (flagged != w_.awakeBodies.size()) {
            fail("awake list", num(w_.awakeBodies.size()) + " bodies listed, " + num(flagged) + " flagged inAwakeList");
        }
        for (std::size_t k = 0; k < w_.awakeBodies.size(); ++k) {
            const std::uint32_t d = w_.awakeBodies[k];
            if (d >= n) fail("awake list", "entry " + num(k) + " = " + num(d) + " is past the " + num(n) + " bodies");
            if (k > 0 && d <= w_.awakeBodies[k - 1]) fail("awake list", "not ascending at entry " + num(k));
            if (w_.inAwakeList[d] == 0) fail("awake list", body(d) + " is listed but not flagged inAwakeList");
            if (isStatic(d)) fail("awake list", body(d) + " is static");
            if (!w_.awakeListHasSleepers && !w_.params[d].awake) fail("awake list", body(d) + " is listed but asleep");
        }
        std::vector<std::uint8_t>& queued = cleared(tBodyMarks, n);
        for (const std::uint32_t d : w_.wokenBodies) {
            if (d >= n) fail("awake list", "woken body " + num(d) + " is past the " + num(n) + " bodies");
            queued[d] = 1;
        }
        for (std::uint32_t d = 0; d < n; ++d) {
            if (isStatic(d) || !w_.params[d].awake) continue;
            if (w_.inAwakeList[d] == 0 && queued[d] == 0) fail("awake list", body(d) + " is awake but neither listed nor queued");
        }
    }

    // Static bodies have no mass: every constraint and integrator skips them
    // on that alone. (Kinematic bodies have none either.)
    void staticBodies() const {
        for (std::uint32_t d = 0; d < bodyCount(); ++d) {
            if (w_.params[d].type == BodyType::Dynamic) continue;
            const BodyMotion& m = w_.motion[d];
            if (m.invMass != 0 || !(m.invInertiaWorld == Mat3::zero())) {
                fail("body store", body(d) + " is not dynamic but has a non-zero inverse mass or inertia");
            }
            if (isStatic(d) && w_.params[d].awake) fail("body store", body(d) + " is static and flagged awake");
        }
    }

    // The state the step starts from is finite (input validation keeps NaN
    // out; a NaN born in a step is World::step's NumericalError, which
    // refuses the next step until it is gone). Not checked after the start:
    // a NaN made by a step must reach that error, not this one.
    void finiteAwakeStates() const {
        for (std::uint32_t d = 0; d < bodyCount(); ++d) {
            if (isStatic(d) || !w_.params[d].awake) continue;
            const BodyMotion& m = w_.motion[d];
            if (!isFinite(m.com) || !isFinite(m.q) || !isFinite(m.v) || !isFinite(m.w)) {
                fail("body store", body(d) + " is awake with a non-finite state");
            }
        }
    }

    // Contacts reference live bodies, never two static ones; the per-body
    // contact lists hold exactly the live contacts, each in both its bodies'
    // lists, with consistent links; the free list holds exactly the others.
    void contactGraph() const {
        const ContactManager& cm = w_.contactManager;
        const ContactArray& contacts = cm.contacts();
        std::size_t alive = 0;
        for (std::uint32_t i = 0; i < contacts.size(); ++i) {
            const Contact& c = contacts[i];
            if (!c.alive) continue;
            ++alive;
            for (const std::uint32_t slot : {c.slotA, c.slotB}) {
                if (slot >= w_.bodySlots.size() || denseOfSlot(slot) == kNoIndex) {
                    fail("contact graph", "contact " + num(i) + " references slot " + num(slot) + ", not a live body");
                }
            }
            if (c.slotA == c.slotB) fail("contact graph", "contact " + num(i) + " joins " + body(denseOfSlot(c.slotA)) + " to itself");
            if (isStatic(denseOfSlot(c.slotA)) && isStatic(denseOfSlot(c.slotB))) {
                fail("contact graph", "contact " + num(i) + " joins two static bodies, " + body(denseOfSlot(c.slotA)) + " and " +
                                          body(denseOfSlot(c.slotB)));
            }
            if (c.proxyA != cm.proxyOfSlot(c.slotA) || c.proxyB != cm.proxyOfSlot(c.slotB)) {
                fail("contact graph", "contact " + num(i) + "'s proxies are not its bodies' proxies");
            }
        }
        // The live count is kept with the lists (recounted when they are rebuilt).
        if (cm.contactListsBuilt() && alive != cm.liveContactCount()) {
            fail("contact graph", num(alive) + " live contacts, the manager counts " + num(cm.liveContactCount()));
        }
        std::size_t free = 0;
        for (std::uint32_t i = cm.firstFreeContact(); i != UINT32_MAX; i = contacts[i].nextFree) {
            if (i >= contacts.size() || contacts[i].alive || ++free > contacts.size()) {
                fail("contact graph", "the free list holds contact " + num(i) + " (live, out of range or a cycle)");
            }
        }
        if (alive + free != contacts.size()) {
            fail("contact graph", num(alive) + " live and " + num(free) + " free contacts of " + num(contacts.size()));
        }
        if (!cm.contactListsBuilt()) return;  // built at the next update
        if (cm.contactListCount() < w_.bodySlots.size()) {
            fail("contact graph", num(cm.contactListCount()) + " contact lists for " + num(w_.bodySlots.size()) + " body slots");
        }
        // Every listed key is a live contact's end at this slot, linked both
        // ways; the lists then hold each live contact's two ends exactly once
        // iff they hold 2 x alive keys in all.
        std::size_t keys = 0;
        for (std::uint32_t slot = 0; slot < cm.contactListCount(); ++slot) {
            std::uint32_t previous = UINT32_MAX;
            for (std::uint32_t key = cm.firstContactKey(slot); key != UINT32_MAX; key = cm.nextContactKey(key)) {
                const std::uint32_t i = key >> 1;
                if (i >= contacts.size() || !contacts[i].alive) {
                    fail("contact graph", "slot " + num(slot) + "'s contact list holds contact " + num(i) + ", not live");
                }
                const std::uint32_t end = (key & 1) == 0 ? contacts[i].slotA : contacts[i].slotB;
                if (end != slot) fail("contact graph", "slot " + num(slot) + "'s contact list holds contact " + num(i) + " of slot " + num(end));
                if (cm.previousContactKey(key) != previous) {
                    fail("contact graph", "contact " + num(i) + "'s back link in slot " + num(slot) + "'s list is wrong");
                }
                if (++keys > 2 * alive) fail("contact graph", "the per-body contact lists hold more than 2 x " + num(alive) + " entries (a cycle?)");
                previous = key;
            }
        }
        if (keys != 2 * alive) {
            fail("contact graph", "the per-body contact lists hold " + num(keys) + " entries for " + num(alive) +
                                      " live contacts (each must be in both its bodies' lists)");
        }
    }

    // A sleeping island is asleep as a whole: a body tagged with an island
    // is asleep and not static (waking one body wakes and untags them all).
    void islands() const {
        for (std::uint32_t d = 0; d < bodyCount(); ++d) {
            const BodyParams& p = w_.params[d];
            if (p.sleepIsland == 0) continue;
            if (p.awake) fail("islands", body(d) + " is awake but tagged with sleeping island " + num(p.sleepIsland));
            if (isStatic(d)) fail("islands", body(d) + " is static but tagged with island " + num(p.sleepIsland));
        }
    }

    // After a wake pass, no awake body touches a sleeping one: the contact
    // manager wakes the sleeper's island on contact, and an island sleeps
    // only with everything it touches.
    void noAwakeBodyTouchesASleeper() const {
        for (const Contact& c : w_.contactManager.contacts()) {
            if (!c.alive || c.sensor || !c.touching) continue;
            const std::uint32_t a = denseOfSlot(c.slotA), b = denseOfSlot(c.slotB);
            if (isStatic(a) || isStatic(b) || w_.params[a].awake == w_.params[b].awake) continue;
            const std::uint32_t sleeper = w_.params[a].awake ? b : a;
            fail("islands", body(w_.params[a].awake ? a : b) + " is awake and touches " + body(sleeper) +
                                ", asleep (island " + num(w_.params[sleeper].sleepIsland) + ")");
        }
    }

    // The solver bodies: entry 0 the static stand-in, then awake non-static
    // bodies, each mapped back to its solver index.
    void solverBodies() const {
        const BodyStore& s = w_;  // the awake set (body_store.hpp)
        const std::vector<std::uint32_t>& denseOf = s.denseOfSolver;
        if (s.state.size() != denseOf.size()) fail("solver bodies", num(s.state.size()) + " bodies, " + num(denseOf.size()) + " dense indices");
        for (std::uint32_t i = 1; i < denseOf.size(); ++i) {
            const std::uint32_t d = denseOf[i];
            if (d >= bodyCount()) fail("solver bodies", "solver body " + num(i) + " maps to dense " + num(d) + ", past the bodies");
            if (isStatic(d) || !w_.params[d].awake) fail("solver bodies", body(d) + " is a solver body but static or asleep");
            if (s.solverIndexOf(d) != i) fail("solver bodies", body(d) + " is solver body " + num(i) + " but maps to " + num(s.solverIndexOf(d)));
        }
        if (!s.state.empty() && s.state[0].invMass != 0) fail("solver bodies", "the static stand-in (entry 0) has mass");
        // And no other body maps to one: beginStep clears only the last
        // step's entries of the map, so a stale one would make a sleeping or
        // static body a solver body's alias.
        std::size_t mapped = 0;
        for (std::uint32_t d = 0; d < bodyCount(); ++d) mapped += s.solverIndexOf(d) != 0 ? 1 : 0;
        if (!denseOf.empty() && mapped != denseOf.size() - 1) {
            fail("solver bodies", num(mapped) + " bodies map to a solver body, but there are " + num(denseOf.size() - 1));
        }
    }

    // Colour c's constraints (but the overflow's, solved in order) share no
    // dynamic body: that is what lets a colour run in SIMD lanes and across
    // threads with the serial bits. `dynamicEnds(i, a, b)` gives constraint
    // i's solver bodies that can move (kNoIndex: none).
    template <class Ends>
    void coloursShareNoBody(const char* area, std::size_t colours, const std::vector<std::uint32_t>* colourOf,
                            std::size_t constraints, std::size_t solverBodies, Ends&& ends) const {
        if (colours == 0) {
            if (constraints != 0) fail(area, num(constraints) + " constraints and no colours");
            return;
        }
        std::vector<std::uint64_t>& masks = cleared(tColourMasks, solverBodies);
        for (std::size_t i = 0; i < constraints; ++i) {
            const std::size_t colour = colourOf != nullptr ? (*colourOf)[i] : 0;
            if (colour >= colours) fail(area, "constraint " + num(i) + " has colour " + num(colour) + " of " + num(colours));
            if (colour + 1 == colours) continue;  // the overflow colour
            std::uint32_t bodies[2];
            ends(i, bodies[0], bodies[1]);
            for (const std::uint32_t b : bodies) {
                if (b == kNoIndex) continue;
                if (b >= solverBodies) fail(area, "constraint " + num(i) + " references solver body " + num(b) + " of " + num(solverBodies));
                const std::uint64_t bit = std::uint64_t{1} << colour;
                if ((masks[b] & bit) != 0) {
                    fail(area, "colour " + num(colour) + " holds two constraints on solver body " + num(b) + " (dynamic), constraint " +
                                   num(i) + " and an earlier one");
                }
                masks[b] |= bit;
            }
        }
    }

    void contactColours() const {
        const ContactSolver& s = w_.contactSolver;
        const auto& pairs = s.pairs();
        const auto& colourOf = s.constraintColours();
        const std::size_t colours = s.colourCount();
        if (pairs.empty()) return;
        if (colourOf.size() != pairs.size()) fail("contact colours", num(colourOf.size()) + " colours for " + num(pairs.size()) + " constraints");
        const auto& bodies = w_.state;
        coloursShareNoBody("contact colours", colours, &colourOf, pairs.size(), bodies.size(),
                           [&](std::size_t i, std::uint32_t& a, std::uint32_t& b) {
                               a = pairs[i].bodyA < bodies.size() && bodies[pairs[i].bodyA].invMass > 0 ? pairs[i].bodyA : kNoIndex;
                               b = pairs[i].bodyB < bodies.size() && bodies[pairs[i].bodyB].invMass > 0 ? pairs[i].bodyB : kNoIndex;
                           });
        // The colour-ordered slots the passes walk: colour c's range holds its constraints.
        const auto& pendingOfSlot = s.pendingOfSlot();
        if (s.colourStart(colours) != pairs.size() || pendingOfSlot.size() != pairs.size()) {
            fail("contact colours", "the colour ranges cover " + num(s.colourStart(colours)) + " slots for " + num(pairs.size()) + " constraints");
        }
        for (std::uint32_t c = 0; c < colours; ++c) {
            for (std::uint32_t slot = s.colourStart(c); slot < s.colourStart(c + 1); ++slot) {
                const std::uint32_t i = pendingOfSlot[slot];
                if (i >= pairs.size() || colourOf[i] != c) fail("contact colours", "slot " + num(slot) + " of colour " + num(c) + " holds a constraint of another colour");
            }
        }
    }

    void jointColours() const {
        const JointSolver& j = w_.jointSolver;
        const auto constraints = j.constraints();
        const std::size_t colours = j.colourCount();
        if (constraints.empty()) return;
        const auto& bodies = w_.state;
        if (j.colourStart(colours) != constraints.size()) {
            fail("joint colours", "the colour ranges cover " + num(j.colourStart(colours)) + " of " + num(constraints.size()) + " joints");
        }
        // Constraints are stored in colour order: colour c is [colourStart(c), colourStart(c + 1)).
        std::vector<std::uint32_t>& colourOf = tJointColours;
        colourOf.resize(constraints.size());
        for (std::uint32_t c = 0; c < colours; ++c) {
            for (std::uint32_t k = j.colourStart(c); k < j.colourStart(c + 1); ++k) colourOf[k] = c;
        }
        coloursShareNoBody("joint colours", colours, &colourOf, constraints.size(), bodies.size(),
                           [&](std::size_t i, std::uint32_t& a, std::uint32_t& b) {
                               const JointConstraint& k = constraints[i];
                               a = k.bodyA < bodies.size() && bodies[k.bodyA].invMass > 0 ? k.bodyA : kNoIndex;
                               b = k.bodyB < bodies.size() && bodies[k.bodyB].invMass > 0 ? k.bodyB : kNoIndex;
                           });
    }

    static thread_local std::vector<std::uint32_t> tJointColours;
    const WorldImpl& w_;
    StepPhase phase_;
};

thread_local std::vector<std::uint32_t> Checker::tJointColours;

}  // namespace

const char* phaseName(StepPhase phase) {
    switch (phase) {
        case StepPhase::StepStart: return "at the step's start";
        case StepPhase::AfterCollide: return "after collide";
        case StepPhase::AfterPrepare: return "after prepare";
        case StepPhase::AfterSubsteps: return "after the sub-steps";
        case StepPhase::AfterStore: return "after store";
        case StepPhase::AfterContinuous: return "after continuous collision";
        case StepPhase::AfterSleep: return "after sleep";
        case StepPhase::StepEnd: return "at the step's end";
    }
    return "at an unknown phase";
}

void checkInvariants(const WorldImpl& w, StepPhase phase) { Checker(w, phase).run(); }

bool stepValidation() {
#ifdef FULCRUM_VALIDATE
    static const bool on = [] {
        const char* value = std::getenv("FULCRUM_VALIDATE");
        return value == nullptr || value[0] != '0';
    }();
    return on;
#else
    return false;
#endif
}

}  // namespace fulcrum::detail
