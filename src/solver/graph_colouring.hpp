#pragma once
// Greedy graph colouring of constraints, shared by the contact and joint
// solvers (Box2D v3's "graph colouring" solver sets): within one colour no two
// constraints write the same body, so a colour's constraints can be solved in
// any order, in SIMD lanes or on several threads, with the same result.
#include <bit>
#include <cstddef>
#include <cstdint>
#include <vector>

namespace fulcrum::detail {

// The two solver bodies a constraint writes, and whether each can move:
// static and kinematic ends (infinite mass) are never written, so they take
// no colour slot.
struct ConstraintEnds {
    std::uint32_t a = 0, b = 0;
    bool dynamicA = false, dynamicB = false;
    bool operator==(const ConstraintEnds&) const = default;
};

// The ends of a constraint with solver-body indices bodyA, bodyB into
// `bodies` (anything with invMass): dynamic when the body has mass.
template <class Constraint, class Body>
ConstraintEnds constraintEnds(const Constraint& k, const Body* bodies) {
    return {k.bodyA, k.bodyB, bodies[k.bodyA].invMass > 0, bodies[k.bodyB].invMass > 0};
}

// Constraint i (ends(i) -> ConstraintEnds) takes the first of `Colours`
// colours in which neither of its dynamic bodies is used yet, in index order
// (deterministic); one that finds none goes to the overflow colour `Colours`,
// solved one constraint after another. Fills colourOf[i], and colourStart so
// that colour c holds [colourStart[c], colourStart[c + 1]) for c = 0..Colours.
// `used` holds one mask per body of the colours it already has (Colours <= 64),
// so a constraint's colour is the lowest zero bit of its two bodies' masks ORed:
// one test instead of up to Colours (the former layout, one bitset per colour,
// tested colour by colour and read up to 2 x Colours cache lines: the colouring
// was 0.9 % of a 10,000-sphere pile's collapse, serial). The same colours.
// No allocation once the vectors have their capacity (used: one word per body).
template <std::uint32_t Colours, class Ends>
void colourGreedily(std::size_t count, std::size_t bodyCount, Ends&& ends, std::vector<std::uint64_t>& used,
                    std::vector<std::uint32_t>& colourOf, std::vector<std::uint32_t>& colourStart) {
    static_assert(Colours >= 1 && Colours <= 64, "one 64-bit mask per body");
    constexpr std::uint64_t kAllColours = Colours == 64 ? ~std::uint64_t{0} : (std::uint64_t{1} << Colours) - 1;
    used.assign(bodyCount, 0);
    colourOf.resize(count);
    std::uint32_t counts[Colours + 1] = {};
    for (std::size_t i = 0; i < count; ++i) {
        const ConstraintEnds e = ends(i);
        const std::uint64_t taken = (e.dynamicA ? used[e.a] : 0) | (e.dynamicB ? used[e.b] : 0);
        const std::uint64_t free = ~taken & kAllColours;
        std::uint32_t c = Colours;
        if (free != 0) {
            c = static_cast<std::uint32_t>(std::countr_zero(free));
            const std::uint64_t bit = std::uint64_t{1} << c;
            if (e.dynamicA) used[e.a] |= bit;
            if (e.dynamicB) used[e.b] |= bit;
        }
        colourOf[i] = c;
        ++counts[c];
    }
    colourStart.assign(Colours + 2, 0);
    for (std::uint32_t c = 0; c <= Colours; ++c) colourStart[c + 1] = colourStart[c] + counts[c];
}

}  // namespace fulcrum::detail
