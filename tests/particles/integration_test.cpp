// Position Verlet against the analytic free fall, near and far from the
// origin (particle_integration.hpp: why displacements are stored).
#include <gtest/gtest.h>


#include "particles/particle_world.hpp"

using namespace fulcrum;

namespace {

constexpr Real kDt = Real(1) / 60;

}  // namespace

// A free particle released from rest at height y0 falls g t^2 / 2 after
// t = 1 s (60 steps, the default 16 sub-steps), and its velocity over the
// last sub-step is g (t - h / 2) (the mean over that sub-step, exact for a
// constant acceleration): both within 0.1 %, at y0 = 0, 10 and 1000 m. In
// float the spacing of positions near 1000 m (6.1e-5 m) is larger than the
// fall of a sub-step's gravity term (g h^2 = 1.1e-5 m), so a Verlet that
// recomputes the velocity from two rounded positions loses most of it.
// Measured with x_prev stored (and x_{-1} = x_0 at rest): fall +0.157 % at
// y0 = 0 (the start's extra g h / 2 of speed), -1.35 % at 10, and at 1000 the
// particle never moved. Now: -8e-7, -6e-7 and -7e-6, speed -9e-6.
TEST(Integration, FreeFallIsExactFarFromTheOrigin) {
    for (const Real y0 : {Real(0), Real(10), Real(1000)}) {
        ParticleWorld world;
        ParticleSystem s;
        s.name = "p";
        addParticle(s, {Real(-1000), y0, Real(500)}, Real(0.1), Real(0.01));
        const ParticleSystemId id = world.add(std::move(s));
        const int steps = 60;
        for (int i = 0; i < steps; ++i) world.step(kDt);
        const ParticleSystem& p = world.system(id);
        const double t = steps * static_cast<double>(kDt);
        const double g = 9.81;
        const double h = static_cast<double>(kDt) / world.settings().substeps;
        const double fall = static_cast<double>(y0) - static_cast<double>(p.position[0].y);
        const double speed = -static_cast<double>(p.velocity(0).y);
        EXPECT_NEAR(fall / (0.5 * g * t * t), 1.0, 1e-3) << "at y0 = " << y0;
        EXPECT_NEAR(speed / (g * (t - h / 2)), 1.0, 1e-3) << "at y0 = " << y0;
        EXPECT_EQ(p.position[0].x, Real(-1000)) << "no sideways drift";
        EXPECT_EQ(p.position[0].z, Real(500));
    }
}
