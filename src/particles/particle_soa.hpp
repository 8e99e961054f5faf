#pragma once
// The solver's working copy of a system's particles during one step, one
// float array per coordinate.
//
// Why a copy: ParticleSystem keeps positions as Vec3 (12 bytes) because the
// rest of the engine (metrics, I/O, the World) reads them as vectors. The
// sub-step loop instead streams through them 16 times per step, and the
// coloured distance constraints load 4 or 8 neighbouring particles' x (then
// y, then z) with one SIMD load when the coordinates are separate arrays
// (xpbd_distance.hpp). Loading at the step's start and storing at its end
// costs 2 x 4096 conversions for the 64 x 64 cloth, about 0.3 % of its step.
//
// Displacements, not previous positions (particle_integration.hpp): d holds
// the displacement the prediction gave this sub-step and q the predicted
// position, so the sub-step's full displacement so far is d + (x - q). x - q
// is exact in float (Sterbenz: the two are close), and it is zero for a
// particle no constraint touched, so a free particle's displacement grows by
// exactly a h^2 per sub-step wherever it is.
//
// The arrays keep their capacity between steps: no allocation in steady state.
#include <cstddef>
#include <vector>

#include "particles/particle_system.hpp"

namespace fulcrum::detail {

struct ParticleSoA {
    std::vector<Real> x, y, z;     // x_n: current positions
    std::vector<Real> qx, qy, qz;  // predicted positions of this sub-step (before projection)
    std::vector<Real> dx, dy, dz;  // predicted displacements of this sub-step
    std::vector<Real> w;           // inverse masses (constant within a step)

    std::size_t size() const { return x.size(); }
    Vec3 position(std::size_t i) const { return {x[i], y[i], z[i]}; }
    Vec3 predicted(std::size_t i) const { return {qx[i], qy[i], qz[i]}; }
    Vec3 displacement(std::size_t i) const { return {dx[i], dy[i], dz[i]}; }
    void setPosition(std::size_t i, const Vec3& p) {
        x[i] = p.x;
        y[i] = p.y;
        z[i] = p.z;
    }

    void load(const ParticleSystem& s) {
        const std::size_t n = s.particleCount();
        x.resize(n); y.resize(n); z.resize(n);
        qx.resize(n); qy.resize(n); qz.resize(n);
        dx.resize(n); dy.resize(n); dz.resize(n);
        w.resize(n);
        for (std::size_t i = 0; i < n; ++i) {
            x[i] = qx[i] = s.position[i].x;
            y[i] = qy[i] = s.position[i].y;
            z[i] = qz[i] = s.position[i].z;
            dx[i] = s.displacement[i].x; dy[i] = s.displacement[i].y; dz[i] = s.displacement[i].z;
            w[i] = s.inverseMass[i];
        }
    }
    void store(ParticleSystem& s) const {
        for (std::size_t i = 0; i < x.size(); ++i) {
            s.position[i] = {x[i], y[i], z[i]};
            s.displacement[i] = {dx[i] + (x[i] - qx[i]), dy[i] + (y[i] - qy[i]), dz[i] + (z[i] - qz[i])};
        }
    }
};

}  // namespace fulcrum::detail
