# Physics through the bindings: closed forms checked on worlds built and stepped from Python.
import math

import numpy as np
import pytest

import rubble


def falling_sphere(integrator="symplectic", dt=0.01, gravity=-9.81, height=50.0):
    return {
        "format": "rubble-scene", "version": 1, "name": "fall",
        "simulation": {"dt": dt, "gravity": [0, gravity, 0], "integrator": integrator},
        "shapes": {"ball": {"type": "sphere", "radius": 0.1}},
        "bodies": [{"name": "ball", "shape": "ball", "mass": 2.0, "position": [0, height, 0]}],
    }


@pytest.mark.parametrize("integrator", ["symplectic", "explicit"])
def test_free_fall_matches_the_closed_form(integrator):
    g, dt, y0, n = 9.81, 0.01, 50.0, 200
    w = rubble.World.load(falling_sphere(integrator, dt))
    w.step(n)
    t = n * dt
    # The world counts time as steps times its float32 dt.
    assert w.step_count == n and w.time == pytest.approx(n * float(np.float32(dt)), rel=1e-12)
    y = float(w.positions[0, 1])
    v = float(w.velocities[0, 1])
    # The continuous answer y0 - g t^2 / 2, and the integrator's first-order offset: symplectic
    # Euler moves with the new velocity (y_n = y0 - g dt^2 n (n + 1) / 2), explicit Euler with
    # the old one (n (n - 1) / 2).
    analytic = y0 - 0.5 * g * t * t
    offset = -0.5 * g * dt * t if integrator == "symplectic" else 0.5 * g * dt * t
    assert y == pytest.approx(analytic + offset, abs=2e-4)
    assert abs(y - analytic) == pytest.approx(0.5 * g * dt * t, rel=1e-3)
    assert v == pytest.approx(-g * t, abs=1e-4)
    # Nothing moved sideways, nothing turned.
    assert np.all(w.positions[0, [0, 2]] == 0)
    np.testing.assert_array_equal(w.orientations[0], [1, 0, 0, 0])


def test_pendulum_period_matches_the_amplitude_corrected_formula():
    # scenes/pendulum.json: a 1 m pendulum on a ball joint released at 10 degrees, 240 Hz.
    w = rubble.World.load(rubble.example_scene("pendulum"))
    pivot = w.positions[w.find_body("pivot")].astype(np.float64)
    bob = w.find_body("bob")
    start = w.positions[bob].astype(np.float64) - pivot
    length = float(np.linalg.norm(start))
    theta = math.atan2(start[0], -start[1])
    assert length == pytest.approx(1.0, abs=1e-6)
    assert math.degrees(theta) == pytest.approx(10.0, abs=1e-4)
    crossings, last_x, last_t, stretch = [], float(start[0]), 0.0, 0.0
    for _ in range(int(round(12.0 / w.dt))):
        w.step()
        x = w.positions[bob].astype(np.float64) - pivot
        if last_x > 0.0 >= x[0]:  # downward through the vertical, interpolated
            crossings.append(last_t + (w.time - last_t) * last_x / (last_x - x[0]))
        last_x, last_t = float(x[0]), w.time
        stretch = max(stretch, abs(float(np.linalg.norm(x)) - length))
    assert len(crossings) >= 5
    period = (crossings[-1] - crossings[0]) / (len(crossings) - 1)
    # T = 2 pi sqrt(L / g) (1 + theta^2 / 16 + 11 theta^4 / 3072): 2.0102 s at 10 degrees.
    expected = 2 * math.pi * math.sqrt(length / 9.81) * (1 + theta ** 2 / 16 + 11 * theta ** 4 / 3072)
    assert period == pytest.approx(expected, rel=1e-3)  # measured: 7e-5
    assert stretch < 1e-3  # the joint holds the rod's length


def test_explosion_added_at_run_time_gives_the_radial_impulse():
    scene = falling_sphere(gravity=0.0, height=0.0)
    scene["bodies"].append({"name": "far", "shape": "ball", "mass": 1.0, "position": [5, 0, 0]})
    w = rubble.World.load(scene, dt=0.01)
    w.step(3)
    # ball 1 m from the centre, inside the 4 m radius: impulse 8 * (1 - 1/4) = 6 N s on 2 kg.
    w.explode([0, -1, 0], impulse=8.0, radius=4.0)
    w.step()
    np.testing.assert_allclose(w.velocities[0], [0, 3.0, 0], atol=1e-6)
    np.testing.assert_array_equal(w.velocities[1], [0, 0, 0])  # 5.1 m away: untouched
    with pytest.raises(rubble.SceneError, match="radius"):
        w.explode([0, 0, 0], impulse=1.0, radius=0.0)


def test_set_velocity_moves_and_spins_a_free_body():
    w = rubble.World.load(falling_sphere(gravity=0.0, height=0.0), dt=0.01)
    w.set_velocity("ball", [1.0, -2.0, 0.5], angular=[0.0, 3.0, 0.0])
    w.step(100)
    np.testing.assert_allclose(w.positions[0], [1.0, -2.0, 0.5], atol=1e-5)
    np.testing.assert_allclose(w.angular_velocities[0], [0, 3.0, 0], atol=1e-5)
    # A sphere turning at 3 rad/s about y: each step turns it by exactly |w| dt (the exponential
    # map), so 100 steps turn it 3 rad about y. The first-order update q += dt/2 (0, w) q turned it
    # 2 atan(|w| dt / 2) a step, 1.1e-4 rad short in all, which this tolerance would see.
    angle = 100 * 3.0 * 0.01
    np.testing.assert_allclose(w.orientations[0], [math.cos(angle / 2), 0, math.sin(angle / 2), 0],
                               atol=2e-6)
    m = w.metrics()
    assert m["kinetic_energy"] == pytest.approx(
        0.5 * 2.0 * (1 + 4 + 0.25) + 0.5 * (0.4 * 2.0 * 0.01) * 9.0, rel=1e-5)


def test_metrics_and_contacts_of_a_resting_box():
    w = rubble.World.load(rubble.example_scene("box_rest"))
    w.step(5)
    c = w.contacts()
    m = w.metrics()
    assert c.dtype.names == ("a", "b", "point", "normal", "depth")
    assert len(c) == m["contacts"] == 4  # the box's bottom face on the floor
    np.testing.assert_allclose(np.linalg.norm(c["normal"], axis=1), 1.0, rtol=1e-6)
    np.testing.assert_allclose(np.abs(c["normal"][:, 1]), 1.0, rtol=1e-6)
    np.testing.assert_allclose(c["point"][:, 1], 0.0, atol=0.01)
    assert np.all(c["depth"] < 0.01)
    # At rest on the floor: its weight's potential energy, no motion left; asleep a while later.
    assert m["kinetic_energy"] < 1e-6
    assert m["potential_energy"] == pytest.approx(9.81 * 1.0 * 0.5, rel=2e-3)
    assert m["dynamic_bodies"] == 1 and m["bodies"] == 2
    w.step(115)
    assert w.metrics()["asleep_bodies"] == 1


def test_masses_past_the_stated_ratio_warn_and_run():
    scene = falling_sphere(gravity=0.0, height=0.0)
    scene["bodies"] = [
        {"name": "light", "shape": "ball", "mass": 1e-9, "position": [0, 0, 0]},
        {"name": "heavy", "shape": "ball", "mass": 1e9, "position": [1, 0, 0]},
    ]
    w = rubble.World.load(scene)
    assert len(w.warnings) == 1
    assert "bodies[0] and bodies[1]: the masses of dynamic bodies light (1e-09 kg) and heavy " \
           "(1e+09 kg) differ 1:1e+18; stacks stand up to 1:100" in w.warnings[0]
    w.step()
    assert rubble.World.load(falling_sphere()).warnings == []


def test_capsule_loads_and_a_kinematic_target_carries_it():
    # A capsule lying on a kinematic deck that the host moves 1 cm a step along x.
    scene = {
        "format": "rubble-scene", "version": 1, "name": "deck",
        "simulation": {"dt": 0.01},
        "materials": {"default": {"friction": 0.8}},
        "shapes": {"deck": {"type": "box", "half_extents": [2, 0.1, 2]},
                   "pill": {"type": "capsule", "radius": 0.1, "half_height": 0.3}},
        "bodies": [{"name": "deck", "shape": "deck", "kinematic": True},
                   {"name": "pill", "shape": "pill", "mass": 1.0, "position": [0, 0.2, 0],
                    "orientation": [0.70710678, 0, 0, -0.70710678]}],
    }
    w = rubble.World.load(scene)
    w.step(20)
    for i in range(1, 101):
        w.set_kinematic_target("deck", [0.01 * i, 0, 0])
        w.step()
        if i == 50:  # the capsule has caught up with the deck by now
            start = w.positions[1].copy()
    np.testing.assert_array_equal(w.positions[0], np.float32([1.0, 0, 0]))
    # Carried along its axis for the last 0.5 s without slipping.
    np.testing.assert_allclose(w.positions[1] - start, [0.5, 0, 0], atol=1e-3)
    with pytest.raises(rubble.SceneError):
        w.set_kinematic_target("pill", [0, 0, 0])
