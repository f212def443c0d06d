"""funnel.motion: the motion between logged events agrees with the engine's events and with the
physics of each phase (parabolas, motion along a face, arcs about an edge, spin)."""

import math
from pathlib import Path

import numpy as np
import pytest

import funnel
from funnel import motion, trajectory


def _run(release, **model):
    r = funnel.simulate(release=release, events=True, **model)
    return r, dict(funnel.geometry(**model), release=release)


def test_flights_end_at_the_next_event_and_spin_advances_by_omega_dt():
    r, g = _run(0.3, theta=60.0)
    ev = r["events"]
    x, y, phi = motion.state_at(g, ev, ev["time"])
    # The parabola of each flight, from the engine's state after an event, reaches the next event.
    np.testing.assert_allclose(x, ev["x"], rtol=0, atol=1e-11)
    np.testing.assert_allclose(y, ev["y"], rtol=0, atol=1e-11)
    # In flight the spin is constant: the angle advances by omega * dt, exactly.
    turn = ev["omega_after"][:-1] * np.diff(ev["time"])
    np.testing.assert_allclose(np.diff(phi), turn, rtol=1e-12, atol=1e-12)
    # Between events the energy (u^2 + v^2)/2 + y of the centre is that of the flight's start.
    t_mid = 0.5 * (ev["time"][:-1] + ev["time"][1:])
    xm, ym, _ = motion.state_at(g, ev, t_mid)
    h = 1e-6
    xp, yp, _ = motion.state_at(g, ev, t_mid + h)
    xn, yn, _ = motion.state_at(g, ev, t_mid - h)
    energy = 0.5 * (((xp - xn) / (2 * h)) ** 2 + ((yp - yn) / (2 * h)) ** 2) + ym
    start = 0.5 * (ev["u_after"][:-1] ** 2 + ev["v_after"][:-1] ** 2) + ev["y"][:-1]
    np.testing.assert_allclose(energy, start, rtol=1e-6)


def test_release_is_a_fall_from_rest():
    r, g = _run(0.3, theta=60.0)
    x, y, phi = motion.state_at(g, r["events"], [0.0, 0.5])
    assert x[0] == x[1] == pytest.approx(r["x0"], abs=1e-15)
    assert y[0] == r["y0"] and y[1] == pytest.approx(r["y0"] - 0.125, abs=1e-14)
    assert phi.tolist() == [0.0, 0.0]


def test_a_sustained_contact_stays_on_the_face():
    r, g = _run(0.5, theta=30.0, e=0.3)
    ev = r["events"]
    k = int(np.flatnonzero(ev["kind"] == "contact_start")[0])
    assert ev["kind"][k + 1] == "contact_end" and ev["wall"][k] == "right"
    t = np.linspace(ev["time"][k], ev["time"][k + 1], 25)
    x, y, _ = motion.state_at(g, ev, t)
    s, c = math.sin(math.radians(30.0)), math.cos(math.radians(30.0))
    np.testing.assert_allclose(x * s - y * c, 0.0, atol=1e-12)  # the right centre line y = x tan(theta)
    assert np.all(np.diff(y) < 0)  # it slides/rolls down
    px, py, _ = motion.trajectory_path(g, ev, samples_per_arc=9, window=(k, k + 1))
    np.testing.assert_allclose(px * s - py * c, 0.0, atol=1e-12)


def _edge_events(g, wall, angles, omegas):
    """Synthetic events: an edge contact from angle angles[0] to angles[1] about the edge point,
    then a flight to the exit; positions on the circle of radius a."""
    ex = (-1 if wall == "left" else 1) * g["half_gap"]
    ey, a = g["y_bottom"], g["radius"]
    pts = [(ex + a * math.cos(t), ey + a * math.sin(t)) for t in angles]
    speed = 0.2
    tangent = [(-math.sin(t) * speed, math.cos(t) * speed) for t in angles]
    sign = 1 if angles[1] > angles[0] else -1
    return {"time": np.array([1.0, 1.0, 1.3, 1.35]),
            "kind": np.array(["face", "edge_contact_start", "edge_contact_end", "exit"]),
            "wall": np.array([wall, wall, wall, "none"]),
            "x": np.array([pts[0][0], pts[0][0], pts[1][0], pts[1][0] + 0.01]),
            "y": np.array([pts[0][1], pts[0][1], pts[1][1], ey - 0.001]),
            "u_before": np.array([0.0, 0.0, sign * tangent[1][0], 0.0]),
            "v_before": np.array([-1.0, 0.0, sign * tangent[1][1], 0.0]),
            "omega_before": np.array([0.0, omegas[0], omegas[1], omegas[1]]),
            "u_after": np.array([0.0, sign * tangent[0][0], sign * tangent[1][0], 0.0]),
            "v_after": np.array([0.0, sign * tangent[0][1], sign * tangent[1][1], 0.0]),
            "omega_after": np.array([omegas[0], omegas[0], omegas[1], omegas[1]])}


@pytest.mark.parametrize("wall,angles", [("right", (2.0, 1.2)), ("left", (1.2, 2.0)), ("left", (3.0, -3.0))])
def test_an_edge_contact_moves_on_the_circle_about_the_edge_point(wall, angles):
    g = dict(funnel.geometry(theta=50.0), release=0.2)
    ev = _edge_events(g, wall, angles, (10.0, 30.0))
    ex = (-1 if wall == "left" else 1) * g["half_gap"]
    px, py, pt = motion.trajectory_path(g, ev, samples_per_arc=33, window=(1, 2))
    np.testing.assert_allclose(np.hypot(px - ex, py - g["y_bottom"]), g["radius"], rtol=1e-12)
    assert (px[0], py[0]) == pytest.approx((ev["x"][1], ev["y"][1]), abs=1e-15)
    assert (px[-1], py[-1]) == pytest.approx((ev["x"][2], ev["y"][2]), abs=1e-15)
    # The short way round: the arc turns by the smaller angle (3 -> -3 crosses pi, 0.28 rad).
    alpha = np.unwrap(np.arctan2(py - g["y_bottom"], px - ex))
    expected = (angles[1] - angles[0] + math.pi) % (2 * math.pi) - math.pi
    assert alpha[-1] - alpha[0] == pytest.approx(expected, abs=1e-12)
    t = np.linspace(1.0, 1.3, 17)
    x, y, phi = motion.state_at(g, ev, t)
    # (At t = 1 exactly the time belongs to the synthetic flight that ends at the first event.)
    np.testing.assert_allclose(np.hypot(x - ex, y - g["y_bottom"])[1:], g["radius"], rtol=1e-12)
    # The spin goes linearly from 10 to 30 over 0.3: the angle is its integral.
    tau = t - 1.0
    np.testing.assert_allclose(phi - phi[0], 10.0 * tau + 0.5 * (20.0 / 0.3) * tau ** 2, rtol=1e-12)


def test_segments_classify_the_motion_after_each_event():
    g = dict(funnel.geometry(theta=50.0), release=0.2)
    seg = motion.Segments(g, _edge_events(g, "right", (2.0, 1.2), (0.0, 0.0)))
    assert seg.kind.tolist() == [motion.FLIGHT, motion.FLIGHT, motion.EDGE_CONTACT, motion.FLIGHT]
    assert seg.ex.tolist() == [0.0, 0.0, g["half_gap"], 0.0]


def test_alternating_run():
    kinds = np.array(["release", "face", "face", "face", "face", "edge", "face", "face"])
    walls = np.array(["none", "left", "left", "right", "left", "right", "left", "right"])
    assert motion.alternating_run({"kind": kinds, "wall": walls}) == (2, 5)
    assert motion.alternating_run({"kind": kinds[:2], "wall": walls[:2]}) is None


LINED = Path(__file__).resolve().parents[2] / "examples" / "geometry" / "lined.toml"


@pytest.mark.parametrize("model", [
    {"theta_left": 50.0},  # an asymmetric V: the release line's middle is not x = 0
    {"geometry": str(LINED)},
    {"release_u": 0.5, "release_v": 0.3},
    {"release_u": -0.2, "release_spin": 3.0},
], ids=["asymmetric", "geometry-file", "velocity", "spin"])
def test_the_first_flight_starts_from_the_engines_release_state(model):
    # The first flight was drawn from release * half_width at rest: off the release point of an
    # asymmetric V or a geometry file, and a fall from rest whatever the release velocity and spin,
    # so that it did not reach the first collision.
    r, g = trajectory.simulate_for_plot(0.3, **model)
    ev = r["events"]
    x, y, phi = motion.state_at(g, ev, [0.0, ev["time"][0]])
    assert (x[0], y[0], phi[0]) == (r["x0"], r["y0"], 0.0)
    assert (x[1], y[1]) == pytest.approx((ev["x"][0], ev["y"][0]), abs=1e-12)
    assert phi[1] == pytest.approx(r["omega0"] * ev["time"][0], rel=1e-14, abs=1e-300)
    px, py, _ = motion.trajectory_path(g, ev, samples_per_arc=9)
    assert (px[0], py[0]) == (r["x0"], r["y0"])
    assert (px[8], py[8]) == pytest.approx((ev["x"][0], ev["y"][0]), abs=1e-12)
    # Without the result's state, a release at rest is still on the engine's release line.
    if not any(k.startswith("release_") for k in model):
        rest = {k: v for k, v in g.items() if k not in motion.RELEASE_STATE}
        assert motion.release_state(rest, ev) == pytest.approx((r["x0"], r["y0"], 0.0, 0.0, 0.0), abs=1e-15)


def test_bad_windows_events_and_geometries_are_value_errors():
    # An IndexError, a KeyError, or a window silently empty or reaching before the first event.
    r, g = _run(0.3, theta=60.0)
    ev, n = r["events"], len(r["events"]["time"])
    for window in ((0, 10**6), (20, 10), (-1, 5), (3, 3), (0, n)):
        with pytest.raises(ValueError, match=rf"^invalid window = \({window[0]}, {window[1]}\): valid range is "
                                             rf"0 <= first < last <= {n - 1}"):
            motion.trajectory_path(g, ev, window=window)
    with pytest.raises(ValueError, match=r"^invalid window = \(1\.5, 3\): valid windows are two integer"):
        motion.trajectory_path(g, ev, window=(1.5, 3))
    assert len(motion.trajectory_path(g, ev, samples_per_arc=3, window=(0, n - 1))[0]) == 3 * (n - 1)
    ev3 = funnel.simulate(release=0.3, events=True, space="3d")["events"]
    for tool in (lambda: motion.state_at(g, ev3, [0.0]), lambda: motion.trajectory_path(g, ev3),
                 lambda: motion.alternating_run(ev3), lambda: motion.collision_points(ev3)):
        with pytest.raises(ValueError, match="^invalid events: a 3D run's event log"):
            tool()
    with pytest.raises(ValueError, match="^invalid events: no columns 'x', 'y'; valid events have time, kind, x, y"):
        motion.state_at(g, {"time": [1.0], "kind": ["face"]}, [0.0])
    with pytest.raises(ValueError, match="^invalid geometry: no release height"):
        motion.state_at({"release": 0.3}, ev, [0.0])


def test_edge_contacts_turn_about_their_own_walls_corner():
    # An asymmetric V: each wall ends at its own height; a geometry file: edges at any convex
    # corner. The drawn arc of an edge contact keeps the centre a from the edge point it turns
    # about (it was drawn about (+-half_gap, y_bottom), the V of theta's edges).
    # Shallow walls (sustained contacts slide over the edges): the left wall's edge lies lower
    # than the V of theta's, and a spout's edges lie 0.05 H below the walls' lower ends.
    for kwargs in ({"theta_left": 10.0, "theta": 15.0, "e": 0.3, "mu": 0.5},
                   {"theta": 10.0, "theta_right": 14.0, "spout_length": 0.05, "e": 0.3, "mu": 0.5}):
        g = funnel.geometry(**kwargs)
        contacts = 0
        for release in np.linspace(-0.95, 0.95, 39):
            r = funnel.simulate(float(release), events=True, **kwargs)
            seg = motion.Segments(g, r["events"])
            edge = seg.kind == motion.EDGE_CONTACT
            for x, y in ((seg.x0, seg.y0), (seg.x1, seg.y1)):
                assert np.allclose(np.hypot(x[edge] - seg.ex[edge], y[edge] - seg.ey[edge]), g["radius"],
                                   rtol=0, atol=1e-12), (kwargs, release)
            contacts += int(np.sum(edge))
        assert contacts >= 5, kwargs


def test_a_v_with_both_wall_angles_equal_is_that_angles_v():
    g = funnel.geometry(theta_left=45.0, theta_right=45.0)
    h = funnel.geometry(theta=45.0)
    for key in ("theta", "sin_t", "y_bottom", "half_width", "x_face_end"):
        assert g[key] == h[key], key
    assert g["walls"] == h["walls"]
