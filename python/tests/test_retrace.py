"""funnel.retrace against an independent pure-Python wedge billiard and against the command line."""

import math

import numpy as np
import pytest

import funnel


# ---------------------------------------------------------------------------------------------
# An independent calculation: a point in the wedge y >= |x| tan(theta) (the centre lines; the
# origin where they meet), released at rest at height y0, reflecting elastically without friction.

def _walls(theta):
    s, c = math.sin(theta), math.cos(theta)
    # name: (inward normal, tangent up the wall)
    return {"L": (np.array([s, c]), np.array([-c, s])), "R": (np.array([-s, c]), np.array([c, s]))}


def _next_collision(r, v, last, theta, walls):
    c = math.cos(theta)
    best = None
    for name, (n, _) in walls.items():
        d0 = 0.0 if name == last else float(n @ r)
        p = float(n @ v)
        disc = p * p + 2.0 * d0 * c
        if disc < 0.0:
            continue
        root = math.sqrt(disc)
        t = (p + root) / c if p >= 0.0 else 2.0 * d0 / (root - p)
        if t > 0.0 and (best is None or t < best[0]):
            best = (t, name)
    t, name = best
    n, tau = walls[name]
    r = r + v * t + np.array([0.0, -0.5 * t * t])
    v = v + np.array([0.0, -t])
    r = r - float(n @ r) * n
    return r, v, name, t


def _collisions(fraction, theta, y0, k):
    """(walls, incidence angles, times, states after) of the first k collisions from rest."""
    walls = _walls(theta)
    r, v, last, time = np.array([fraction * y0 / math.tan(theta), y0]), np.zeros(2), None, 0.0
    out = []
    for _ in range(k):
        r, v, last, t = _next_collision(r, v, last, theta, walls)
        time += t
        n, tau = walls[last]
        p, q = float(n @ v), float(tau @ v)
        v = v - 2.0 * p * n
        out.append((last, math.atan2(q, -p), time, r.copy(), v.copy()))
    return out


def independent_orbits(theta_deg, y0, k_max=4, n=800):
    """Wall-turn orbits released on the left half: {(sequence, rounded x0/L): (x0/L, period)}."""
    theta = math.radians(theta_deg)
    grid = -1.0 + (np.arange(n) + 0.5) / n
    runs = [_collisions(f, theta, y0, k_max) for f in grid]
    found = {}
    for k in range(2, k_max + 1):
        for i in range(n - 1):
            a, b = runs[i], runs[i + 1]
            seq = "".join(c[0] for c in a[:k])
            if seq != "".join(c[0] for c in b[:k]) or a[k - 1][1] * b[k - 1][1] > 0:
                continue
            lo, hi, flo = grid[i], grid[i + 1], a[k - 1][1]
            for _ in range(60):  # bisection
                mid = 0.5 * (lo + hi)
                fm = _collisions(mid, theta, y0, k)[k - 1][1]
                lo, hi, flo = (lo, mid, flo) if fm * flo <= 0.0 else (mid, hi, fm)
            run = _collisions(lo, theta, y0, k)
            if "".join(c[0] for c in run) != seq or abs(run[-1][1]) > 1e-8:
                continue
            if any(abs(c[1]) < 1e-6 for c in run[:-1]):
                continue  # a repetition of a shorter orbit
            found[(seq, round(lo, 9))] = (lo, 2.0 * run[-1][2])
    return found


# ---------------------------------------------------------------------------------------------

@pytest.mark.parametrize("theta", [47.3, 58.6, 67.9])
def test_wall_turn_orbits_match_an_independent_calculation(theta):
    r = funnel.retrace(theta, max_bounces=4)
    y0 = 1.0 - 0.01 / math.cos(math.radians(theta))  # closed funnel: release height above the vertex
    ref = independent_orbits(theta, y0)
    o = r["orbits"]
    left = o["release"] < 0
    ours = {(s, round(x, 9)): (x, t) for s, x, t in zip(o["sequence"][left], o["release"][left], o["period"][left])}
    assert set(ours) == set(ref)
    assert len(ref) >= 1
    for key, (x, period) in ref.items():
        assert ours[key][0] == pytest.approx(x, abs=1e-12)
        assert ours[key][1] == pytest.approx(period, rel=1e-12)
    # Every orbit comes back to rest at its release after one period in the engine.
    assert np.all(o["return_position_error"] <= 1e-12) and np.all(o["return_speed"] <= 1e-12)


def test_result_matches_the_command_line(cli):
    r = funnel.retrace("60:62:1", turns="wall,rest", scan_points=400)
    j = cli("retrace", "--theta", "60:62:1", "--turns", "wall,rest", "--scan-points", "400")
    assert len(j["orbits"]) == len(r["orbits"]["theta"])
    for i, orbit in enumerate(j["orbits"]):
        assert orbit["sequence"] == r["orbits"]["sequence"][i]
        assert orbit["turn"] == r["orbits"]["turn"][i]
        assert orbit["release"] == r["orbits"]["release"][i]
        assert orbit["period"] == r["orbits"]["period"][i]
        assert orbit["stable"] == bool(r["orbits"]["stable"][i])
    assert [w["sequence"] for w in j["windows"]] == list(r["windows"]["sequence"])


def test_stability_is_the_trace_criterion_and_windows_follow_it():
    r = funnel.retrace("59:63:0.5", turns="wall,rest", scan_points=300)
    o = r["orbits"]
    np.testing.assert_array_equal(o["stable"], np.abs(o["trace"]) < 2.0)
    w = r["windows"]
    stable_lr = (w["sequence"] == "LRLR") & (w["turn"] == "wall") & (w["window"] == "stable")
    assert np.any(stable_lr)
    for a, b in zip(w["theta_from"][stable_lr], w["theta_to"][stable_lr]):
        inside = (o["theta"] >= a) & (o["theta"] <= b) & (o["sequence"] == "LRLR") & (o["turn"] == "wall")
        assert np.all(o["stable"][inside])


def test_invalid_input_raises_value_error_naming_the_parameter():
    with pytest.raises(ValueError, match="theta"):
        funnel.retrace(95)
    with pytest.raises(ValueError, match="max_bounces"):
        funnel.retrace(60, max_bounces=0)
    with pytest.raises(ValueError, match="turns"):
        funnel.retrace(60, turns="sideways")
    with pytest.raises(ValueError, match="gap"):
        funnel.retrace(60, gap=0.01)


def test_ctrl_c_interrupts_a_long_retrace_scan(ctrl_c):
    # 5001 angles with up to 12 bounces take minutes: Ctrl-C skips the angles not yet begun
    # (the scan ran to its end before raising).
    ctrl_c(lambda: funnel.retrace("30:80:0.01", max_bounces=12, threads=2))


def test_a_grid_of_more_than_1e5_angles_is_refused_as_by_the_command_line():
    with pytest.raises(ValueError, match=r"^invalid theta: 176001 angles; valid range is at most 100000 angles"):
        funnel.retrace("1:89:0.0005")
