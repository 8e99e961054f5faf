#pragma once
// Greedy graph colouring of constraints, shared by the contact and joint
// solvers (Box2D v3's "graph colouring" solver sets): within one colour no two
// constraints write the same body, so a colour's constraints can be solved in
// any order, in SIMD lanes or on several threads, with the same result.
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
};

// Constraint i (ends(i) -> ConstraintEnds) takes the first of `Colours`
// colours in which neither of its dynamic bodies is used yet, in index order
// (deterministic); one that finds none goes to the overflow colour `Colours`,
// solved one constraint after another. Fills colourOf[i], and colourStart so
// that colour c holds [colourStart[c], colourStart[c + 1]) for c = 0..Colours.
// No allocation once the vectors have their capacity (bits: Colours words per
// 64 bodies).
template <std::uint32_t Colours, class Ends>
void colourGreedily(std::size_t count, std::size_t bodyCount, Ends&& ends, std::vector<std::uint64_t>& bits,
                    std::vector<std::uint32_t>& colourOf, std::vector<std::uint32_t>& colourStart) {
    const std::size_t words = (bodyCount + 63) / 64;
    bits.assign(Colours * words, 0);
    colourOf.resize(count);
    std::uint32_t counts[Colours + 1] = {};
    for (std::size_t i = 0; i < count; ++i) {
        const ConstraintEnds e = ends(i);
        std::uint32_t c = Colours;
        for (std::uint32_t col = 0; col < Colours; ++col) {
            std::uint64_t* used = bits.data() + col * words;
            const bool usedA = e.dynamicA && (used[e.a >> 6] >> (e.a & 63) & 1u);
            const bool usedB = e.dynamicB && (used[e.b >> 6] >> (e.b & 63) & 1u);
            if (usedA || usedB) continue;
            if (e.dynamicA) used[e.a >> 6] |= std::uint64_t{1} << (e.a & 63);
            if (e.dynamicB) used[e.b >> 6] |= std::uint64_t{1} << (e.b & 63);
            c = col;
            break;
        }
        colourOf[i] = c;
        ++counts[c];
    }
    colourStart.assign(Colours + 2, 0);
    for (std::uint32_t c = 0; c <= Colours; ++c) colourStart[c + 1] = colourStart[c] + counts[c];
}

}  // namespace fulcrum::detail
