"""A small synthetic dataset in the schema of ``funnel paper``, one figure of every kind.

The numbers are made up (smooth shapes with a jump at 45 degrees) except the trajectories,
which come from a frictionless point bouncing between the two centre lines, so that each
recorded flight really ends at the next event.
"""

import csv
import json
import math
from pathlib import Path

import numpy as np

SWEEP_PARAMS = ("theta", "e", "mu", "beta0", "radius", "gap", "inertia", "t_max", "max_collisions")
OBSERVABLES = ("duration", "impulse", "normal_impulse", "energy_loss", "collisions", "edge_collisions",
               "contact_time")
SWEEP_COLUMNS = (SWEEP_PARAMS + ("release_dist", "samples")
                 + tuple(f"{o}_{s}" for o in OBSERVABLES for s in ("mean", "std", "sem", "min", "max"))
                 + ("exited", "rest", "trapped", "total_collisions"))
EVENT_COLUMNS = ("time", "kind", "wall", "x", "y", "u_before", "v_before", "omega_before", "u_after", "v_after",
                 "omega_after", "slip_before", "regime", "j_n", "j_t", "energy_lost")
DEFAULTS = {"theta": 60.0, "e": 0.99, "mu": 1.0, "beta0": 0.0, "radius": 0.01, "gap": 0.04, "inertia": 0.4,
            "t_max": 1e5, "max_collisions": 100000000}


def _meta(figure, kind, panels, series, observables, params, claim, holds, **extra):
    meta = {"figure": figure, "kind": kind, "title": f"synthetic {kind}",
            "caption": f"Synthetic data of kind {kind} for the plotting tests.",
            "params": params, "panels": [{"id": i, "label": label} for i, label in panels],
            "series": series, "observables": observables, "version": "0.1.0", "git_commit": "fake",
            "run_time_s": 1.5, "samples": 40,
            "check": {"claim": claim, "measured": "synthetic numbers", "holds": holds}}
    meta.update(extra)
    return meta


def _write(outdir, meta, header, rows):
    d = Path(outdir) / meta["figure"]
    d.mkdir(parents=True, exist_ok=True)
    (d / f"{meta['figure']}.json").write_text(json.dumps(meta, indent=2, ensure_ascii=False))
    with open(d / f"{meta['figure']}.csv", "w", newline="") as f:
        w = csv.writer(f)
        w.writerow(header)
        w.writerows(rows)
    return d


def _sweep_row(panel, point, release_dist="line"):
    """One row of a theta sweep: `point` holds the parameters; observables are shaped by theta."""
    p = dict(DEFAULTS, **point)
    theta, mu, e = p["theta"], p["mu"], p["e"]
    base = 40.0 / math.sqrt(theta) * (1.0 + (3.0 * min(mu, 1.0) if theta > 45 else -0.3 * min(mu, 1.0)))
    base *= e ** 2 * (1.2 if release_dist == "disk" else 1.0)
    values = {"duration": base, "impulse": 2.0 * base, "normal_impulse": 1.9 * base,
              "energy_loss": min(1.0, 0.01 * base), "collisions": 5 * base, "edge_collisions": 1.0,
              "contact_time": 0.1 * base}
    row = [panel] + [p[k] for k in SWEEP_PARAMS] + [release_dist, 40]
    for o in OBSERVABLES:
        m = values[o]
        row += [m, 0.5 * m, 0.5 * m / math.sqrt(40), 0.1 * m, 2.0 * m]
    return row + [40, 0, 0, int(200 * base)]


def _theta_sweep(outdir, figure, panels, series, values, observables, dists=("line",)):
    rows = []
    for pid, beta0 in panels:
        for theta in np.arange(5.0, 85.01, 2.5):
            for v in values:
                for dist in dists:
                    point = {"theta": float(theta), "beta0": beta0}
                    if series != "release_dist":
                        point[series] = v
                    rows.append(_sweep_row(pid, point, dist if series != "release_dist" else v))
    panel_list = [(pid, f"β0 = {beta0:g}") for pid, beta0 in panels]
    meta = _meta(figure, "theta_sweep", panel_list, series, list(observables), {"e": 0.99},
                 "the mean duration just above 45° is far larger than just below", True,
                 run_time_basis={"batch_time_s": 6.0, "batch_collisions": 4.0e6, "figure_collisions": 1.0e6})
    return _write(outdir, meta, ("panel",) + SWEEP_COLUMNS, rows)


def bounce(theta, release, e=0.95, max_events=200, radius=0.01, gap=0.04):
    """Events of a frictionless point bouncing between the centre lines of a funnel of angle
    theta (degrees), released at rest at x0 = release * L, until it falls through y_b."""
    t = math.radians(theta)
    s, c = math.sin(t), math.cos(t)
    y_b = 0.5 * gap * math.tan(t) - radius / c
    y0 = y_b + 1.0
    L = y0 / math.tan(t)
    normals = {"left": np.array([s, c]), "right": np.array([-s, c])}
    r, v, time = np.array([release * L, y0]), np.zeros(2), 0.0
    events = []
    for _ in range(max_events):
        h = r[1] - y_b  # exit when y(t) = y_b
        best = (v[1] + math.sqrt(v[1] ** 2 + 2.0 * h), "exit")
        for wall, n in normals.items():
            d0, p = float(r @ n), float(v @ n)
            disc = p * p + 2.0 * d0 * c
            dt = (p + math.sqrt(disc)) / c if p >= 0 else 2.0 * d0 / (math.sqrt(disc) - p)
            hit = r + v * dt + np.array([0.0, -0.5 * dt * dt])
            if dt > 1e-12 and dt < best[0] and hit[1] > y_b:
                best = (dt, wall)
        dt, what = best
        r = r + v * dt + np.array([0.0, -0.5 * dt * dt])
        before = v + np.array([0.0, -dt])
        time += dt
        if what == "exit":
            events.append([time, "exit", "none", r[0], r[1], *before, 0.0, *before, 0.0, 0.0, "none", 0.0, 0.0, 0.0])
            break
        n = normals[what]
        p = float(before @ n)
        after = before - (1.0 + e) * p * n
        r = r - float(r @ n) * n  # exactly on the centre line
        events.append([time, "face", what, r[0], r[1], *before, 0.0, *after, 0.0, 0.0, "sticking",
                       (1.0 + e) * abs(p), 0.0, 0.5 * (1.0 - e * e) * p * p])
        v = after
    return events, {"y_bottom": y_b, "y_release": y0, "half_width": L, "half_gap": 0.5 * gap, "radius": radius,
                    "theta": theta, "x_face_end": 0.5 * gap + radius * s, "y_face_end": y_b + radius * c,
                    "release": release}


def write_fake_dataset(outdir):
    """Writes one synthetic figure of every kind into outdir; returns the figure directories."""
    outdir = Path(outdir)
    rng = np.random.default_rng(12345)
    dirs = []
    dirs.append(_theta_sweep(outdir, "fig02", [("a", 0.0)], "e", [0.99, 0.95, 0.9, 0.8], ["duration"]))
    dirs.append(_theta_sweep(outdir, "fig03", [("a", 0.0), ("b", 0.31), ("c", -0.31)], "mu",
                             [0.0, 0.05, 0.1, 0.2, 1.0, 5.0], ["duration"]))
    dirs.append(_theta_sweep(outdir, "fig06", [("a", 0.0), ("b", 0.31), ("c", -0.31)], "e",
                             [0.99, 0.9, 0.7, 0.4, 0.1], ["duration", "impulse", "energy_loss"]))
    dirs.append(_theta_sweep(outdir, "fig13", [("a", 0.0), ("b", 0.31), ("c", -0.31)], "release_dist",
                             ["disk", "line"], ["duration", "impulse", "energy_loss"]))

    thetas = [20, 30, 40, 44, 46, 50, 60, 70, 80]
    rows = []
    for pid, theta in zip("abcdefghi", thetas):
        for x in np.linspace(-1, 1, 201)[1:-1]:
            dur = 30.0 + 20.0 * rng.random() + (60.0 if theta > 45 and abs(x) > 0.4 else 0.0)
            rows.append([pid, theta, x, dur, "exited" if dur < 105 else "trapped", int(3 * dur)])
    meta = _meta("fig07", "release_scan", [(p, f"θ = {t}°") for p, t in zip("abcdefghi", thetas)], "theta",
                 ["duration"], {"e": 0.99, "mu": 1.0, "beta0": 0.0}, "insensitive ranges only above 45°", False)
    dirs.append(_write(outdir, meta, ("panel", "theta", "release", "duration", "status", "collisions"), rows))

    rows, geometry = [], {}
    for pid, theta, release in (("a", 60.0, 0.3), ("b", 40.0, -0.5)):
        events, geometry[pid] = bounce(theta, release)
        rows += [[pid, theta] + ev for ev in events]
    meta = _meta("fig08", "trajectories", [("a", "θ = 60°"), ("b", "θ = 40°")], None, [],
                 {"e": 0.95, "mu": 0.0}, "a repeating pattern above 45°", True, geometry=geometry)
    dirs.append(_write(outdir, meta, ("panel", "theta") + EVENT_COLUMNS, rows))

    theta = np.arange(5.0, 85.01, 0.5)
    stable = theta > 45
    m1 = np.where(stable, 1.0, 1.0 + 0.02 * (45 - theta))
    rows = [[t, a, 1.0, 0.6 + 0.003 * t, 0.3, int(s)] for t, a, s in zip(theta, m1, stable)]
    meta = _meta("fig10", "eigenvalues", [], None, [], {"beta0": 0.31, "inertia": 0.4},
                 "stable exactly for theta > 45°", True)
    dirs.append(_write(outdir, meta, ("theta", "mod1", "mod2", "mod3", "mod4", "stable"), rows))

    rows = []
    mus = [0.01, 0.1, 0.2, 1.0]
    for pid, mu in zip("abcd", mus):
        for x in np.linspace(-1, 1, 301)[1:-1]:
            u = rng.random()
            state = "rest" if u < 0.2 else "undecided" if u < 0.22 else "periodic"
            xc = 0.0 if state == "rest" else 0.3 + 0.2 * rng.random() / (1 + 10 * mu)
            rows.append([pid, mu, x, state, xc, -xc])
    meta = _meta("fig11", "closed_final", [(p, f"μ = {m:g}") for p, m in zip("abcd", mus)], "mu", [],
                 {"theta": 50.0, "e": 1.0, "beta0": 0.0, "gap": 0.0}, "two final states only", True)
    meta["caption"] = r"$x_c/L$ of the last two collisions against $x_0/L$, $\sqrt{H/g}$ and $\frac{2}{5} m a^2$."
    dirs.append(_write(outdir, meta, ("panel", "mu", "release", "state", "x_last_over_L", "x_prev_over_L"), rows))

    rows = []
    for theta in (50, 60, 70):
        for mu in [0.0] + list(np.logspace(-3, 0, 10)):
            rows.append([theta, mu, min(1.0, (theta - 45) / 25 * (1 - math.exp(-mu * 300)))])
    meta = _meta("fig12", "periodic_fraction", [], "theta", [], {"e": 1.0, "beta0": 0.0, "gap": 0.0},
                 "the fraction grows with theta", True)
    dirs.append(_write(outdir, meta, ("theta", "mu", "periodic_fraction"), rows))
    return dirs
