"""Physics through Python against analytic results, with the tolerances of the
C++ suite (each test names the C++ test it mirrors)."""
import math

import numpy as np
import pytest

import fulcrum

DT = 1 / 60
G = 9.81
INTEGRATORS = ["explicit_euler", "semi_implicit_euler", "verlet"]


def point_mass(w, mass=1.0, position=(0, 0, 0), velocity=(0, 0, 0), name=""):
    return w.create_body(shape=fulcrum.Sphere(0.1), mass=mass, position=position, linear_velocity=velocity, name=name)


# ---- tests/dynamics/free_fall_test.cpp, ErrorMatchesEachIntegratorsOrder
def projectile(integrator, hz):
    w = fulcrum.World(integrator=integrator, substeps=1)
    ball = point_mass(w, 1, (0, 2, 0), (5, 10, -3))
    w.step(1 / hz, steps=hz)
    return ball.position, ball.linear_velocity


@pytest.mark.parametrize("integrator", INTEGRATORS)
def test_projectile_error_matches_the_integrators_order(integrator):
    t = 1.0
    exact_y = 2 + 10 * t - 0.5 * G * t * t
    p60, v60 = projectile(integrator, 60)
    p120, _ = projectile(integrator, 120)
    assert p60[0] == pytest.approx(5 * t, abs=1e-5)   # no horizontal acceleration: exact
    assert p60[2] == pytest.approx(-3 * t, abs=1e-5)
    assert v60[1] == pytest.approx(10 - G * t, abs=1e-4)
    err60, err120 = p60[1] - exact_y, p120[1] - exact_y
    if integrator == "verlet":
        assert abs(err60) < 5e-5 and abs(err120) < 5e-5  # exact for constant acceleration
    else:
        sign = 1 if integrator == "explicit_euler" else -1  # -/+ g h t / 2
        assert err60 == pytest.approx(sign * G * (1 / 60) * t / 2, abs=0.005 * G / 120)
        assert err120 == pytest.approx(sign * G * (1 / 120) * t / 2, abs=0.005 * G / 240)
        assert err60 / err120 == pytest.approx(2.0, abs=0.02)  # first order


# ---- tests/joints/pendulum_test.cpp, SmallAmplitudePeriod / NinetyDegreePeriod
def elliptic_k(k):
    a, b = 1.0, math.sqrt(1 - k * k)
    for _ in range(40):
        if abs(a - b) <= 1e-15 * a:
            break
        a, b = 0.5 * (a + b), math.sqrt(a * b)
    return math.pi / (2 * a)


def pendulum_period(length, theta0):
    return 4 * math.sqrt(length / G) * elliptic_k(math.sin(theta0 / 2))


def measure_period(w, signal, crossings, max_steps):
    prev, first, last, count = signal(), -1.0, -1.0, 0
    for i in range(max_steps):
        if count >= crossings:
            break
        w.step(DT)
        now = signal()
        if prev < 0 <= now:
            t = (i + prev / (prev - now)) * DT
            first = t if count == 0 else first
            last = t
            count += 1
        prev = now
    return (last - first) / (count - 1)


@pytest.mark.parametrize("length,theta0_deg,crossings", [(1.0, 5, 6), (2.0, 90, 5)])
def test_rod_pendulum_period(length, theta0_deg, crossings):
    theta0 = math.radians(theta0_deg)
    w = fulcrum.World(substeps=4, sleeping=False)
    p = (length * math.sin(theta0), -length * math.cos(theta0), 0)
    bob = w.create_body(shape=fulcrum.Sphere(0.1), mass=1, position=p)
    rod = w.create_distance_joint(None, bob, anchor_a=(0, 0, 0), anchor_b=p)
    period = measure_period(w, lambda: bob.position[0], crossings, 2000)
    assert period / pendulum_period(length, theta0) == pytest.approx(1, abs=0.01)
    assert rod.error < 1e-3


def test_hinge_pendulum_period():
    # A sphere on a hinge is a compound pendulum: equivalent length (L^2 + 2/5 r^2) / L
    # (tests/joints/pendulum_test.cpp, BallJointCompoundPendulum, with a hinge about z).
    length, r, theta0 = 1.0, 0.2, math.radians(4)
    w = fulcrum.World(substeps=4, sleeping=False)
    p = (length * math.sin(theta0), -length * math.cos(theta0), 0)
    bob = w.create_body(shape=fulcrum.Sphere(r), mass=2, position=p)
    hinge = w.create_hinge_joint(None, bob, anchor=(0, 0, 0), axis=(0, 0, 1))
    period = measure_period(w, lambda: bob.position[0], 6, 2000)
    assert period / pendulum_period((length ** 2 + 0.4 * r * r) / length, theta0) == pytest.approx(1, abs=0.01)
    assert hinge.error < 1e-3


# ---- tests/contacts/restitution_test.cpp, BounceHeightsFollowESquared
@pytest.mark.parametrize("e", [1.0, 0.8, 0.5])
def test_restitution_apex_heights(e):
    h0, r = 2.0, 0.1
    bounces = 5 if e == 1 else 3
    w = fulcrum.World(sleeping=False)
    w.create_body(shape=fulcrum.Box((50, 0.5, 50)), type="static", position=(0, -0.5, 0), friction=0.6,
                  restitution=e, name="ground")
    ball = w.create_body(shape=fulcrum.Sphere(r), mass=1, position=(0, h0 + r, 0), restitution=e)
    apex, prev_vy = [], 0.0
    for _ in range(60 * 20):
        if len(apex) >= bounces:
            break
        w.step(DT)
        vy = ball.linear_velocity[1]
        if prev_vy > 0 >= vy:
            apex.append(ball.position[1] - r + vy * vy / (2 * G))
        prev_vy = vy
    assert len(apex) == bounces
    previous = h0
    for n, h in enumerate(apex, start=1):
        assert h == pytest.approx(e * e * previous, abs=0.02 * previous + 0.005)
        assert h <= previous
        assert h == pytest.approx(h0 * e ** (2 * n), abs=0.035 * h0 * n)
        previous = h


# ---- tests/contacts/friction_test.cpp, BoxHoldsBelowFrictionAngle / BoxSlidesAtCoulombAcceleration
def quat_z(angle):
    return (math.cos(angle / 2), 0, 0, math.sin(angle / 2))


def rotate_z(angle, v):
    c, s = math.cos(angle), math.sin(angle)
    return np.array([c * v[0] - s * v[1], s * v[0] + c * v[1], v[2]])


def slide_distance(theta_deg, mu, seconds, settle_steps=0):
    w = fulcrum.World(sleeping=False)
    theta = math.radians(theta_deg)
    w.create_body(shape=fulcrum.Box((40, 0.5, 10)), type="static", orientation=quat_z(theta),
                  position=rotate_z(theta, (0, -0.5, 0)), friction=mu)
    down = rotate_z(theta, (-1, 0, 0))
    box = w.create_body(shape=fulcrum.Box((0.25, 0.25, 0.25)), mass=1, friction=mu, orientation=quat_z(theta),
                        position=rotate_z(theta, (0, 0.25, 0)))
    w.step(DT, steps=settle_steps)
    start = box.position
    w.step(DT, steps=round(seconds * 60))
    return float(np.dot(box.position - start, down))


def test_incline_holds_below_the_friction_angle():
    assert abs(slide_distance(20, 0.5, 10, 30)) < 0.001


def test_incline_slides_at_the_coulomb_acceleration():
    theta = math.pi / 6
    expected = 0.5 * G * (math.sin(theta) - 0.5 * math.cos(theta)) * 4
    assert slide_distance(30, 0.5, 2) == pytest.approx(expected, rel=0.03)


# ---- tests/dynamics/spring_mass_test.cpp, PeriodAndAmplitude (and energy growth of explicit Euler)
@pytest.mark.parametrize("integrator", INTEGRATORS)
def test_spring_period_per_integrator(integrator):
    k, rest, amplitude = 4 * math.pi ** 2, 1.0, 0.1   # m = 1 kg: period 1 s
    w = fulcrum.World(integrator=integrator, substeps=4, gravity=(0, 0, 0))
    body = point_mass(w, 1, (rest + amplitude, 0, 0))
    w.create_spring(None, body, anchor_a=(0, 0, 0), anchor_b=(rest + amplitude, 0, 0), rest_length=rest, stiffness=k)
    crossings, max_disp = [], 0.0
    prev, prev_t = body.position[0] - rest, 0.0
    for _ in range(600):
        w.step(DT)
        d, t = body.position[0] - rest, w.time
        if prev < 0 <= d:
            crossings.append(prev_t + (t - prev_t) * (-prev) / (d - prev))
        max_disp = max(max_disp, abs(d))
        prev, prev_t = d, t
    assert len(crossings) >= 9
    period = (crossings[-1] - crossings[0]) / (len(crossings) - 1)
    assert period == pytest.approx(1.0, abs=1e-3)
    if integrator == "explicit_euler":
        # Explicit Euler gains energy every step: the amplitude grows (x (1 + (w h)^2)^(n/2)).
        assert max_disp > 1.05 * amplitude
    else:
        assert max_disp == pytest.approx(amplitude, abs=0.02 * amplitude)


# ---- tests/dynamics/rigid_rotation_test.cpp, TorqueFreeAsymmetricBoxConservesAndFlips / Verlet...
def rotate_inverse(q, v):
    w, x, y, z = q
    u = np.array([-x, -y, -z])
    t = 2 * np.cross(u, v)
    return v + w * t + np.cross(u, t)


@pytest.mark.parametrize("integrator,substeps,max_dl,max_de", [("semi_implicit_euler", 5, 0.01, 0.02),
                                                               ("verlet", 1, 1e-4, 1e-3)])
def test_torque_free_spin_conserves_angular_momentum(integrator, substeps, max_dl, max_de):
    w = fulcrum.World(integrator=integrator, substeps=substeps, gravity=(0, 0, 0))
    box = w.create_body(shape=fulcrum.Box((0.1, 0.2, 0.4)), mass=2, angular_velocity=(0.005, 5, 0.005), name="tumbler")
    l0, e0 = np.linalg.norm(w.angular_momentum()), w.energy()["total"]
    dl = de = 0.0
    flips, prev_sign = 0, 1
    for _ in range(2400):
        w.step(1 / 240)
        dl = max(dl, abs(np.linalg.norm(w.angular_momentum()) / l0 - 1))
        de = max(de, abs(w.energy()["total"] / e0 - 1))
        sign = 1 if rotate_inverse(box.orientation, box.angular_velocity)[1] >= 0 else -1
        flips += sign != prev_sign
        prev_sign = sign
    assert dl < max_dl
    assert de < max_de
    assert flips >= 2  # the Dzhanibekov flip about the intermediate axis, and back


# ---- tests/dynamics/orbit_test.cpp, ForceCallbackSeesTheWorldTime
def test_force_callback_sees_the_world_time():
    # F = t (N) on 1 kg from rest: v = t^2 / 2, x = t^3 / 6 (1e-4 tolerance).
    w = fulcrum.World(gravity=(0, 0, 0), integrator="verlet", substeps=4)
    b = point_mass(w)
    b.set_force_callback(lambda k: ((k.time * k.mass, 0, 0), (0, 0, 0)))
    w.step(DT, steps=60)
    assert b.linear_velocity[0] == pytest.approx(0.5, abs=1e-4)
    assert b.position[0] == pytest.approx(1 / 6, abs=1e-4)
