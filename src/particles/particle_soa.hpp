#pragma once
// The solver's working copy of a system's particles during one step, one
// float array per coordinate (x, y, z of the current and previous positions).
//
// Why a copy: ParticleSystem keeps positions as Vec3 (12 bytes) because the
// rest of the engine (metrics, I/O, the World) reads them as vectors. The
// sub-step loop instead streams through them 16 times per step, and the
// coloured distance constraints load 4 neighbouring particles' x (then y,
// then z) with one SIMD load when the coordinates are separate arrays
// (xpbd_distance.hpp). Loading at the step's start and storing at its end
// costs 2 x 4096 conversions for the 64 x 64 cloth, about 0.3 % of its step.
//
// The arrays keep their capacity between steps: no allocation in steady state.
#include <cstddef>
#include <vector>

#include "particles/particle_system.hpp"

namespace fulcrum::detail {

struct ParticleSoA {
    std::vector<Real> x, y, z;     // x_n
    std::vector<Real> px, py, pz;  // x_{n-1}
    std::vector<Real> w;           // inverse masses (constant within a step)

    std::size_t size() const { return x.size(); }
    Vec3 position(std::size_t i) const { return {x[i], y[i], z[i]}; }
    Vec3 previousPosition(std::size_t i) const { return {px[i], py[i], pz[i]}; }
    void setPosition(std::size_t i, const Vec3& p) {
        x[i] = p.x;
        y[i] = p.y;
        z[i] = p.z;
    }

    void load(const ParticleSystem& s) {
        const std::size_t n = s.particleCount();
        x.resize(n); y.resize(n); z.resize(n);
        px.resize(n); py.resize(n); pz.resize(n);
        w.resize(n);
        for (std::size_t i = 0; i < n; ++i) {
            x[i] = s.position[i].x; y[i] = s.position[i].y; z[i] = s.position[i].z;
            px[i] = s.previousPosition[i].x; py[i] = s.previousPosition[i].y; pz[i] = s.previousPosition[i].z;
            w[i] = s.inverseMass[i];
        }
    }
    void store(ParticleSystem& s) const {
        for (std::size_t i = 0; i < x.size(); ++i) {
            s.position[i] = {x[i], y[i], z[i]};
            s.previousPosition[i] = {px[i], py[i], pz[i]};
        }
    }
};

}  // namespace fulcrum::detail
