"""The particle's motion between logged events, for drawing and animating trajectories.

An event log (``funnel.simulate(..., events=True)["events"]``, or the rows of a Fig. 8 CSV)
holds the state at each event only. Between two events the centre moves in one of three ways,
chosen by the kind of the event that starts the segment:

- after ``contact_start`` and until ``contact_end``: along the face (a straight line), as in a
  sustained sliding/rolling contact;
- after ``edge_contact_start`` and until ``edge_contact_end``: on the circle of radius a about
  the wall's edge point, E_left = (-d/2, y_b) or E_right = (d/2, y_b);
- otherwise: free flight, the parabola of the velocity after the event under gravity (0, -1).

The first segment starts at the release: the state ``x0``, ``y0``, ``u0``, ``v0``, ``omega0``
of the geometry dict when it has them (a simulate() result's own, which
:func:`funnel.trajectory.simulate_for_plot` copies into it), else at rest on the release line
(see :func:`release_state`).

Units: lengths in H, times in sqrt(H/g), spin in sqrt(g/H) (counter-clockwise positive). Only
numpy is needed; no matplotlib. The model is the 2D one: a 3D run's events are refused.
"""

from __future__ import annotations

import operator

import numpy as np

#: Segment kinds: the motion after an event, up to the next one.
FLIGHT, FACE_CONTACT, EDGE_CONTACT = 0, 1, 2

#: Kinds of events that are collisions (impulses), marked as points on plots.
COLLISION_KINDS = ("face", "edge")


#: Release-state keys a geometry dict may carry (named as in a simulate() result).
RELEASE_STATE = ("x0", "y0", "u0", "v0", "omega0")

#: Event columns that every log has; the others (wall, u_before, ...) default to zero.
REQUIRED_COLUMNS = ("time", "kind", "x", "y")


def _array(events, name, n):
    return np.asarray(events[name], dtype=np.float64) if name in events else np.zeros(n)


def check_events(events, required=REQUIRED_COLUMNS):
    """ValueError unless events is a 2D event log with the `required` columns (a 3D log, with z,
    is refused: its motion leaves the plane that these pictures draw)."""
    if not hasattr(events, "__getitem__") or not hasattr(events, "__contains__"):
        raise ValueError(f"invalid events = {type(events).__name__}: valid events are a dict of 1-D arrays "
                         "(funnel.simulate(..., events=True)['events'] or the rows of a Fig. 8 CSV)")
    if "z" in events:
        raise ValueError("invalid events: a 3D run's event log (it has z); valid events are those of a 2D run "
                         "(funnel.simulate(..., space='2d', events=True)), the only motion funnel.motion draws")
    missing = [name for name in required if name not in events]
    if missing:
        names = ", ".join(repr(m) for m in missing)
        raise ValueError(f"invalid events: no column{'s' * (len(missing) > 1)} {names}; valid events have "
                         f"{', '.join(required)} (funnel.simulate(..., events=True)['events'])")


def release_state(geometry, events=None):
    """(x, y, u, v, omega) of the centre at the release, where the first segment starts.

    The geometry's own x0, y0, u0, v0, omega0 when it has x0 and y0 (a simulate() result's
    release state: the point and the velocity and spin release_u, release_v, release_spin that
    the engine started from); else at rest at x_release_mid + release * half_width on the release
    line y_release, the point the engine computes (x_release_mid is 0 for the paper's V, and
    not 0 for an asymmetric V or a geometry file); else at rest above the first event (a log
    without its release point). ValueError when the geometry gives no release height."""
    if "x0" in geometry and "y0" in geometry:
        return tuple(float(geometry.get(key, 0.0)) for key in RELEASE_STATE)
    if "y_release" not in geometry:
        raise ValueError("invalid geometry: no release height; valid geometries have y_release "
                         "(funnel.geometry(**model)) or the release state x0, y0 (as a simulate() result)")
    if "release" in geometry and "half_width" in geometry:
        x = float(geometry.get("x_release_mid", 0.0)) + float(geometry["release"]) * float(geometry["half_width"])
    else:
        x = float(events["x"][0]) if events is not None and len(events["x"]) else 0.0  # a vertical fall
    return x, float(geometry["y_release"]), 0.0, 0.0, 0.0


def _window_segments(window, n):
    """The segments from event window[0] to event window[1]; ValueError for a window that does
    not lie inside the log or is empty (a bad window gave an IndexError, or silently nothing)."""
    try:
        first, last = (operator.index(i) for i in window)
    except (TypeError, ValueError):
        raise ValueError(f"invalid window = {window!r}: valid windows are two integer event indices "
                         "(first, last)") from None
    if not 0 <= first < last <= n - 1:
        raise ValueError(f"invalid window = ({first}, {last}): valid range is 0 <= first < last <= {n - 1} "
                         f"(event indices of this log of {n} events)")
    return np.arange(first + 1, last + 1)


def _edge_points(geometry, wall, x, y, edge):
    """(ex, ey): the edge point an edge contact turns about, for the segments where `edge`.

    With the walls' vertices (geometry["walls"], as funnel.geometry() gives them), the vertex of
    the contact's wall nearest the centre at the contact's start, which is a from it: any convex
    corner of a profile, and each side's own lower end in an asymmetric V or a spout. Else the
    paper's V: (-+half_gap, y_bottom)."""
    ex, ey = np.zeros(len(edge)), np.zeros(len(edge))
    walls = geometry.get("walls")
    for i in np.flatnonzero(edge):
        side = str(wall[i])
        if walls and side in walls and len(walls[side]):
            corners = np.asarray(walls[side], dtype=np.float64)
            k = int(np.argmin(np.hypot(corners[:, 0] - x[i], corners[:, 1] - y[i])))
            ex[i], ey[i] = corners[k]
        else:
            half_gap = float(geometry.get("half_gap", 0.0))
            ex[i], ey[i] = (-half_gap if side == "left" else half_gap), float(geometry.get("y_bottom", 0.0))
    return ex, ey


class Segments:
    """The n segments of a trajectory with n events: segment i runs from event i-1 (the release,
    :func:`release_state`, for i = 0) to event i.

    Attributes (1-D numpy arrays of length n): ``t0``, ``t1`` (times), ``x0``, ``y0``,
    ``x1``, ``y1`` (centre at the start and the end), ``u0``, ``v0``, ``omega0`` (velocity and
    spin at the start), ``u1``, ``v1``, ``omega1`` (just before the end event), ``kind``
    (FLIGHT, FACE_CONTACT or EDGE_CONTACT), ``ex``, ``ey`` (the edge point of an edge contact,
    else 0), and ``phi0`` (the spin angle at the start, radians, 0 at the release).
    """

    def __init__(self, geometry, events):
        check_events(events)
        time = _array(events, "time", 0)
        n = len(time)
        if n == 0:
            # A run that t_max ends in its first flight logs nothing: no motion to draw (the
            # segments are built from the events, and broke on an empty log).
            raise ValueError("invalid events: an empty log (the run ended before its first collision, e.g. a t_max "
                             "shorter than its first flight); valid events hold at least one event: a longer t_max")
        x, y = _array(events, "x", n), _array(events, "y", n)
        kind = np.asarray(events["kind"], dtype=str) if n else np.zeros(0, dtype=str)
        # The first flight starts from the engine's own release state (point, velocity, spin),
        # so that it ends at the first event.
        x_release, y_release, u_release, v_release, omega_release = release_state(geometry, events)
        shift = lambda a, first: np.concatenate([[first], a[:-1]]) if n else np.zeros(0)
        self.t0, self.t1 = shift(time, 0.0), time
        self.x0, self.y0 = shift(x, x_release), shift(y, y_release)
        self.x1, self.y1 = x, y
        self.u0 = shift(_array(events, "u_after", n), u_release)
        self.v0 = shift(_array(events, "v_after", n), v_release)
        self.omega0 = shift(_array(events, "omega_after", n), omega_release)
        self.u1 = _array(events, "u_before", n)
        self.v1 = _array(events, "v_before", n)
        self.omega1 = _array(events, "omega_before", n)
        starts = shift(kind, "release")
        self.kind = np.where(starts == "contact_start", FACE_CONTACT,
                             np.where(starts == "edge_contact_start", EDGE_CONTACT, FLIGHT))
        wall = shift(np.asarray(events["wall"], dtype=str), "none") if "wall" in events and n else np.full(n, "none")
        edge = self.kind == EDGE_CONTACT
        self.ex, self.ey = _edge_points(geometry, wall, self.x0, self.y0, edge)
        # A flight keeps its spin (the angle advances by omega * dt exactly); during a contact
        # the spin is taken to change linearly, so the angle advances by the mean spin * dt.
        dt = self.t1 - self.t0
        turn = np.where(self.kind == FLIGHT, self.omega0 * dt, 0.5 * (self.omega0 + self.omega1) * dt)
        self.phi0 = np.concatenate([[0.0], np.cumsum(turn)[:-1]]) if n else np.zeros(0)

    def __len__(self):
        return len(self.t1)

    def edge_angles(self):
        """(alpha0, dalpha, r0, r1) of each segment about its edge point: the polar angle at the
        start, the signed turn to the end (the short way, |dalpha| <= pi) and the radii."""
        a0 = np.arctan2(self.y0 - self.ey, self.x0 - self.ex)
        a1 = np.arctan2(self.y1 - self.ey, self.x1 - self.ex)
        turn = (a1 - a0 + np.pi) % (2.0 * np.pi) - np.pi
        return a0, turn, np.hypot(self.x0 - self.ex, self.y0 - self.ey), np.hypot(self.x1 - self.ex, self.y1 - self.ey)


def _hermite(p0, p1, m0, m1, s, dt):
    """Cubic Hermite interpolation at s in [0, 1] with end slopes m0, m1 (per unit time)."""
    s2, s3 = s * s, s * s * s
    return ((2 * s3 - 3 * s2 + 1) * p0 + (s3 - 2 * s2 + s) * dt * m0 + (-2 * s3 + 3 * s2) * p1
            + (s3 - s2) * dt * m1)


def _positions(seg, idx, tau, s, along_path):
    """Centre positions in segments `idx` at time tau after their start (fraction s of the
    segment). With along_path, contacts are sampled uniformly along the path (for drawing);
    else in time, by Hermite interpolation of the logged end velocities (for animation)."""
    x0, y0, u0, v0 = seg.x0[idx], seg.y0[idx], seg.u0[idx], seg.v0[idx]
    px = x0 + u0 * tau
    py = y0 + v0 * tau - 0.5 * tau * tau
    dt = (seg.t1 - seg.t0)[idx]
    face = seg.kind[idx] == FACE_CONTACT
    if np.any(face):
        x1, y1 = seg.x1[idx], seg.y1[idx]
        if along_path:
            fx, fy = x0 + (x1 - x0) * s, y0 + (y1 - y0) * s
        else:
            fx = _hermite(x0, x1, u0, seg.u1[idx], s, dt)
            fy = _hermite(y0, y1, v0, seg.v1[idx], s, dt)
        px, py = np.where(face, fx, px), np.where(face, fy, py)
    edge = seg.kind[idx] == EDGE_CONTACT
    if np.any(edge):
        a0, turn, r0, r1 = (v[idx] for v in seg.edge_angles())
        if along_path:
            alpha = a0 + turn * s
        else:
            # Angular rates about the edge point from the logged velocities: (r x v) / r^2.
            w0 = ((seg.x0 - seg.ex) * seg.v0 - (seg.y0 - seg.ey) * seg.u0)[idx] / np.maximum(r0 * r0, 1e-300)
            w1 = ((seg.x1 - seg.ex) * seg.v1 - (seg.y1 - seg.ey) * seg.u1)[idx] / np.maximum(r1 * r1, 1e-300)
            alpha = _hermite(a0, a0 + turn, w0, w1, s, dt)
        radius = r0 + (r1 - r0) * s
        ex, ey = seg.ex[idx], seg.ey[idx]
        px = np.where(edge, ex + radius * np.cos(alpha), px)
        py = np.where(edge, ey + radius * np.sin(alpha), py)
    return px, py


def trajectory_path(geometry, events, samples_per_arc=None, window=None):
    """(x, y, t) of the particle centre's path, for drawing: from the release, the
    parabola of each free flight up to the next event's time, a straight segment along the face
    during a sustained contact (contact_start to contact_end), an arc of radius a about the edge
    point during an edge contact (edge_contact_start to edge_contact_end). Each segment has
    `samples_per_arc` points, its last one at the event ending it.

    geometry: dict with the release state x0, y0 (u0, v0, omega0) of a simulate() result, or
    y_release and, for the release point, release, half_width and x_release_mid (else the first
    event's x; see release_state), and for edge contacts half_gap and y_bottom (as
    funnel.geometry()).
    events: dict of 1-D arrays time, kind, x, y, u_after, v_after (and wall, u_before, ...).
    window: (first, last) event indices, 0 <= first < last < len(events["time"]), to return only
    the path from event first to event last; ValueError otherwise."""
    seg = Segments(geometry, events)
    segments = np.arange(len(seg)) if window is None else _window_segments(window, len(seg))
    n = len(segments)
    if n == 0:
        return np.zeros(0), np.zeros(0), np.zeros(0)
    k = samples_per_arc or (48 if n < 2000 else 12 if n < 50000 else 4)
    s = np.broadcast_to(np.linspace(0.0, 1.0, k)[None, :], (n, k))
    idx = np.broadcast_to(segments[:, None], (n, k))
    tau = (seg.t1 - seg.t0)[segments][:, None] * s
    px, py = _positions(seg, idx, tau, s, along_path=True)
    return px.ravel(), py.ravel(), (seg.t0[segments][:, None] + tau).ravel()


def state_at(geometry, events, t):
    """(x, y, phi) of the centre and the spin angle phi [rad, counter-clockwise, 0 at the
    release] at times t (array-like, clipped to [0, last event time]). In flight the position is
    the exact parabola and phi advances by omega * dt; during contacts both are interpolated
    between the logged states at their ends (position by cubic Hermite, spin linearly)."""
    seg = Segments(geometry, events)
    t = np.atleast_1d(np.asarray(t, dtype=np.float64))
    if len(seg) == 0:
        return np.zeros_like(t), np.zeros_like(t), np.zeros_like(t)
    t = np.clip(t, 0.0, seg.t1[-1])
    idx = np.minimum(np.searchsorted(seg.t1, t, side="left"), len(seg) - 1)
    dt = (seg.t1 - seg.t0)[idx]
    tau = t - seg.t0[idx]
    s = np.where(dt > 0, tau / np.where(dt > 0, dt, 1.0), 1.0)
    px, py = _positions(seg, idx, tau, s, along_path=False)
    w0, w1 = seg.omega0[idx], seg.omega1[idx]
    contact = seg.kind[idx] != FLIGHT
    slope = np.where(contact & (dt > 0), (w1 - w0) / np.where(dt > 0, dt, 1.0), 0.0)
    phi = seg.phi0[idx] + w0 * tau + 0.5 * slope * tau * tau
    return px, py, phi


def collision_points(events):
    """(x, y, time) of the collisions (face and edge events) of an event log."""
    check_events(events)
    kind = np.asarray(events["kind"], dtype=str)
    m = np.isin(kind, COLLISION_KINDS)
    return (np.asarray(events["x"], dtype=float)[m], np.asarray(events["y"], dtype=float)[m],
            np.asarray(events["time"], dtype=float)[m])


def alternating_run(events):
    """(start, stop) event indices of the longest run of face collisions alternating between
    the walls (stop exclusive; other events inside the run break it), or None if shorter than 2."""
    check_events(events, ("kind", "wall"))
    kind = np.asarray(events["kind"], dtype=str)
    wall = np.asarray(events["wall"], dtype=str)
    best, start, last = (0, 0), None, None
    for i, (k, w) in enumerate(zip(kind.tolist(), wall.tolist())):
        if k == "release":
            continue
        if k == "face" and last is not None and w != last:
            pass
        elif k == "face":
            start = i
        else:
            start, last = None, None
            continue
        last = w
        if i + 1 - start > best[1] - best[0]:
            best = (start, i + 1)
    return best if best[1] - best[0] >= 2 else None
