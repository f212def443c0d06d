"""Plots of the figures built from the geometry and the orbit theories (docs/python.md).

Kinds (the JSON's "kind"): funnel_sketch (Fig. 1), period2_orbits (Fig. 9), retrace_orbits
(Fig. 14) and retrace_windows (Fig. 2 explained, beyond the paper). :mod:`funnel.plot` registers
them in its ``PLOTTERS`` and draws them in its style; matplotlib is imported only when drawing.
"""

from __future__ import annotations

import math

import numpy as np

from . import plot as base

#: Colour of the release point and of a particle at rest.
RELEASE_COLOR = "#D55E00"


# ---------------------------------------------------------------------------------------------
# Geometry helpers

def event_path(rows, samples_per_arc=48):
    """(x, y) of the centre's path through the event rows of one panel: from each row's position
    with its velocity after (u_after, v_after), a parabola under gravity (0, -1) up to the next
    row's time. The rows are sorted by time; the first one is where the path starts."""
    t, x, y = rows["time"], rows["x"], rows["y"]
    u, v = rows["u_after"], rows["v_after"]
    xs, ys = [], []
    s = np.linspace(0.0, 1.0, samples_per_arc)
    for i in range(len(t) - 1):
        tau = (t[i + 1] - t[i]) * s
        xs.append(x[i] + u[i] * tau)
        ys.append(y[i] + v[i] * tau - 0.5 * tau * tau)
    if not xs:
        return np.asarray(x, dtype=float), np.asarray(y, dtype=float)
    return np.concatenate(xs), np.concatenate(ys)


def _unit(theta_deg):
    th = math.radians(theta_deg)
    return math.sin(th), math.cos(th), math.tan(th)


def _walls(ax, g, top, lw=1.6):
    """The two walls (solid) from their lower edges up to height `top`, and the centre lines
    (dotted) from the origin, where they meet."""
    s, c, t = _unit(g["theta"])
    for sign in (-1.0, 1.0):
        ex, ey = sign * g["half_gap"], g["y_bottom"]
        run = (top - ey) / s
        ax.plot([ex, ex + sign * c * run], [ey, top], color="k", lw=lw, solid_capstyle="butt", zorder=3)
        ax.plot([0.0, sign * top / t], [0.0, top], color="0.45", lw=0.6, ls=(0, (1, 2)), zorder=1)


def _release_line(ax, g):
    L = g["half_width"]
    ax.plot([-L, L], [g["y_release"]] * 2, color="0.3", lw=0.7, ls="-.", zorder=1)


def _double_arrow(ax, p, q, text, offset=(0, 0), **kw):
    ax.annotate("", xy=q, xytext=p, arrowprops=dict(arrowstyle="<->", lw=0.6, color="0.15", shrinkA=0, shrinkB=0))
    mid = (0.5 * (p[0] + q[0]) + offset[0], 0.5 * (p[1] + q[1]) + offset[1])
    ax.text(*mid, text, ha="center", va="center", fontsize=8.5, **kw)


# ---------------------------------------------------------------------------------------------
# Fig. 1

def plot_funnel_sketch(meta, columns):
    """The funnel to scale with its symbols (θ, H, L, x0, d, a, origin), the throat enlarged in an inset."""
    from matplotlib.patches import Arc, Circle
    g = meta["geometry"]
    pts = {str(n): (float(x), float(y)) for n, x, y in zip(columns["name"], columns["x"], columns["y"])}
    s, c, t = _unit(g["theta"])
    L, y0, yb, a = g["half_width"], g["y_release"], g["y_bottom"], g["radius"]
    top = pts["wall_top_right"][1]
    fig = base._new_figure(4.6, 3.55)
    ax = fig.subplots()
    _walls(ax, g, top)
    _release_line(ax, g)
    x0 = pts["release"]
    ax.add_patch(Circle(x0, a, color=RELEASE_COLOR, zorder=5))
    ax.plot(*x0, "o", ms=3.5, color=RELEASE_COLOR, zorder=5)
    ax.plot(0, 0, "o", ms=3, color="k", zorder=5)
    ax.text(0.03, -0.012, "origin", fontsize=7.5, ha="left", va="top")
    # H: from the funnel bottom (the edges' level) up to the release line.
    xh = pts["wall_top_right"][0] + 0.06
    ax.plot([pts["edge_right"][0], xh + 0.03], [yb, yb], color="0.5", lw=0.5, ls=":")
    ax.plot([L, xh + 0.03], [y0, y0], color="0.5", lw=0.5, ls=":")
    _double_arrow(ax, (xh, yb), (xh, y0), r"$H$", offset=(0.05, 0))
    # L: half the opening for the centre at the release height; x0: the release position.
    _double_arrow(ax, (0.0, y0 + 0.05), (L, y0 + 0.05), r"$L$", offset=(0, 0.035))
    _double_arrow(ax, (0.0, y0 - 0.05), (x0[0], y0 - 0.05), r"$x_0$", offset=(0, -0.035))
    ax.plot([0, 0], [y0 - 0.09, y0 + 0.09], color="0.5", lw=0.5, ls=":")
    # theta: between the horizontal and the right wall, at its lower edge.
    r_arc = 0.22
    ax.add_patch(Arc(pts["edge_right"], 2 * r_arc, 2 * r_arc, theta1=0, theta2=g["theta"], lw=0.6))
    ax.plot([pts["edge_right"][0], pts["edge_right"][0] + r_arc * 1.3], [yb, yb], color="0.5", lw=0.5, ls=":")
    ang = math.radians(0.5 * g["theta"])
    ax.text(pts["edge_right"][0] + 1.18 * r_arc * math.cos(ang), yb + 1.18 * r_arc * math.sin(ang), r"$\theta$",
            ha="center", va="center", fontsize=9)
    ax.text(-L, y0 + 0.02, "release line", fontsize=7, ha="left", va="bottom", color="0.3")
    ax.set_aspect("equal")
    ax.set_xlim(-L - 0.4, xh + 0.15)
    ax.set_ylim(yb - 0.08, top + 0.02)
    ax.set_xlabel(r"$x/H$")
    ax.set_ylabel(r"$y/H$")
    # The throat, enlarged: edges d apart, the edge circles of radius a, the faces' ends C*.
    ins = ax.inset_axes([0.015, 0.02, 0.36, 0.36])
    zoom = max(2.2 * g["half_gap"], 6 * a)
    _walls(ins, g, yb + 1.6 * zoom, lw=2.0)
    for side in ("left", "right"):
        e = pts[f"edge_{side}"]
        ins.add_patch(Circle(e, a, fill=False, lw=0.5, ls=(0, (1, 1.5)), color="0.4"))
        ins.plot(*pts[f"face_end_{side}"], "s", ms=2.5, color="#0072B2", zorder=5)
    cx, cy = pts["face_end_right"]
    ins.annotate(r"$C^*$", (cx, cy), xytext=(cx + 0.45 * zoom, cy - 0.35 * zoom), fontsize=7, color="#0072B2",
                 arrowprops=dict(arrowstyle="-", lw=0.4, color="#0072B2"))
    ex, ey = pts["edge_left"]
    ins.annotate(r"$E$", (ex, ey), xytext=(ex - 0.5 * zoom, ey - 0.3 * zoom), fontsize=7,
                 arrowprops=dict(arrowstyle="-", lw=0.4))
    ins.plot(0, 0, "o", ms=2.5, color="k", zorder=5)
    ins.text(0.0, -0.12 * zoom, "origin", fontsize=6, ha="center", va="top")
    _double_arrow(ins, pts["edge_left"], pts["edge_right"], "", offset=(0, 0))
    ins.text(0.0, ey + 0.16 * zoom, r"$d$", fontsize=8, ha="center", va="bottom")
    # A particle touching the right face, with its radius a to the contact point.
    sr = 0.9 * zoom
    centre = (sr / t, sr)
    contact = (centre[0] + a * s, centre[1] - a * c)
    ins.add_patch(Circle(centre, a, fill=False, lw=0.8, color=RELEASE_COLOR))
    ins.plot([centre[0], contact[0]], [centre[1], contact[1]], color=RELEASE_COLOR, lw=0.6)
    ins.text(centre[0] - 1.4 * a, centre[1] + 0.4 * a, r"$a$", fontsize=8, color=RELEASE_COLOR, ha="center")
    ins.set_aspect("equal")
    ins.set_xlim(-zoom, zoom)
    ins.set_ylim(min(0.0, yb) - 0.5 * zoom, yb + 1.5 * zoom)
    ins.set_xticks([])
    ins.set_yticks([])
    ins.set_title("throat (enlarged)", fontsize=7, pad=2)
    ax.indicate_inset_zoom(ins, edgecolor="0.5", lw=0.5)
    return fig


# ---------------------------------------------------------------------------------------------
# Figs. 9 and 14: orbits in the funnel

def _orbit_panels(meta, columns, ncol, draw_extra):
    panels = base._panels(meta, columns)
    geometries = meta.get("geometry") or {}
    paths, tops = [], []
    for pid, _ in panels:
        rows = base._panel_rows(columns, pid)
        px, py = event_path(rows)
        paths.append((px, py, rows))
        tops.append(float(np.max(py)))
    nrow = math.ceil(len(panels) / ncol)
    # One vertical scale for all panels; equal aspect: the height follows from the widest panel.
    wall_top = max(tops) + 0.12
    spans = [2 * (wall_top / math.tan(math.radians(geometries[pid]["theta"])) + geometries[pid]["half_gap"]) + 0.06
             for pid, _ in panels]
    bottom = min(min(0.0, geometries[pid]["y_bottom"]) for pid, _ in panels) - 0.04
    panel_w = (7.0 - 0.5 - 0.25 * ncol) / ncol
    panel_h = panel_w * (wall_top - bottom) / max(spans)
    fig = base._new_figure(7.0, nrow * (panel_h + 1.05) + 0.1)
    axes = fig.subplots(nrow, ncol, squeeze=False)
    for i, ((pid, label), (px, py, rows), top) in enumerate(zip(panels, paths, tops)):
        ax = axes[i // ncol][i % ncol]
        g = dict(geometries[pid])
        _walls(ax, g, wall_top)
        ax.plot(px, py, color="#0072B2", lw=0.9, zorder=2)
        faces = rows["kind"].astype(str) == "face"
        ax.plot(rows["x"][faces], rows["y"][faces], "o", ms=2.2, color="k", zorder=4)
        draw_extra(ax, g, rows, i)
        w = 0.5 * max(spans)
        ax.set_aspect("equal")
        ax.set_xlim(-w, w)
        ax.set_ylim(bottom, wall_top)
        ax.set_xlabel(r"$x/H$")
        if i % ncol == 0:
            ax.set_ylabel(r"$y/H$")
        base._panel_title(ax, pid if len(panels) > 1 else "", label)
    for j in range(len(panels), nrow * ncol):
        axes[j // ncol][j % ncol].set_visible(False)
    return fig


def plot_period2_orbits(meta, columns):
    """Fig. 9: the path of the period-2 orbit in the funnel, one panel per angle, y* marked."""
    orbits = meta.get("orbits") or {}
    pids = [pid for pid, _ in base._panels(meta, columns)]

    def extra(ax, g, rows, i):
        o = orbits.get(pids[i], {})
        y_star = o.get("y_star")
        if y_star is not None:
            ax.axhline(y_star, color="0.5", lw=0.5, ls="--", zorder=0)
            ax.text(0.0, y_star - 0.02, r"$y^*$", ha="center", va="top", fontsize=8, color="0.3")
        start = rows["kind"].astype(str) == "start"
        if np.any(start):
            sx, sy = float(rows["x"][start][0]), float(rows["y"][start][0])
            u, v = float(rows["u_after"][start][0]), float(rows["v_after"][start][0])
            ax.annotate("", xy=(sx + 0.12 * u, sy + 0.12 * v), xytext=(sx, sy),
                        arrowprops=dict(arrowstyle="->", lw=0.7, color=RELEASE_COLOR))

    return _orbit_panels(meta, columns, 2, extra)


def plot_retrace_orbits(meta, columns):
    """Fig. 14: the simplest self-retracing orbits, one period each, release point in red."""
    orbits = meta.get("orbits") or []

    def extra(ax, g, rows, i):
        kind = rows["kind"].astype(str)
        rel = kind == "release"
        if np.any(rel):
            ax.plot(rows["x"][rel], rows["y"][rel], "o", ms=4, color=RELEASE_COLOR, zorder=5)
        _release_line(ax, g)
        if i < len(orbits):
            o = orbits[i]
            text = (f"$x_0/L$ = {o['release']:.4f}, period {o['period']:.3f}" + r" $\sqrt{H/g}$" +
                    f"\ntrace {o['trace']:.3f}, stable for {o['window_from']:g}–{o['window_to']:g}°")
            ax.text(0.5, -0.34, text.replace("-", "\u2212"), transform=ax.transAxes, fontsize=7, ha="center",
                    va="top")

    return _orbit_panels(meta, columns, 3, extra)


# ---------------------------------------------------------------------------------------------
# Fig. 2 explained (beyond the paper)

def _union(spans):
    """Merged intervals of a list of (start, end)."""
    out = []
    for a, b in sorted(spans):
        if out and a <= out[-1][1]:
            out[-1][1] = max(out[-1][1], b)
        else:
            out.append([a, b])
    return out


def _family_label(sequence, turn):
    return f"{sequence} (rest)" if turn == "rest" else sequence


def plot_retrace_windows(meta, columns):
    """Mean duration (μ = 0, e = 0.99) with the stability windows shaded and the peaks marked; below,
    the existence and stability windows of each orbit family that is stable somewhere."""
    from matplotlib.lines import Line2D
    from matplotlib.patches import Patch
    windows = meta.get("windows") or []
    search = meta.get("search") or {}
    step = ((search["theta_last"] - search["theta_first"]) / max(search["theta_count"] - 1, 1)) if search else 0.05
    families = []
    for w in windows:
        key = (int(w["bounces"]), w["sequence"], w["turn"])
        if w["window"] == "stable" and key not in families:
            families.append(key)
    families.sort()
    lo = 40.0
    fig = base._new_figure(7.0, 2.6 + 0.12 * len(families) + 0.6)
    ax, bx = fig.subplots(2, 1, sharex=True, gridspec_kw={"height_ratios": [2.6, 0.12 * len(families) + 0.3]})
    theta, mean, sem = columns["theta"], columns["duration_mean"], columns["duration_sem"]
    for a, b in _union([(w["theta_from"] - 0.5 * step, w["theta_to"] + 0.5 * step) for w in windows
                        if w["window"] == "stable"]):
        ax.axvspan(a, b, color="#009E73", alpha=0.25, lw=0)
    ax.fill_between(theta, mean - sem, mean + sem, color="k", alpha=0.15, lw=0)
    ax.plot(theta, mean, color="k", lw=0.9)
    for p in meta.get("peaks") or []:
        y = float(np.max(mean[(theta >= p["from"]) & (theta <= p["to"])])) * 1.06
        style = dict(marker="v", ms=5, ls="none")
        if p["explained"]:
            ax.plot(p["theta_max"], y, color="#009E73", **style)
        else:
            ax.plot(p["theta_max"], y, mfc="white", mec="#D55E00", **style)
    ax.set_ylim(bottom=0)
    ax.set_ylabel(base.axis_label("duration"))
    handles = [Line2D([], [], color="k", lw=0.9, label=r"mean duration, $\mu = 0$, $e = 0.99$"),
               Patch(color="#009E73", alpha=0.3, lw=0, label="a self-retracing orbit is stable ($e = 1$)"),
               Line2D([], [], color="#009E73", marker="v", ls="none", label="peak, explained"),
               Line2D([], [], mfc="white", mec="#D55E00", marker="v", ls="none", label="peak, not explained")]
    ax.legend(handles=handles, loc="upper right", fontsize=7)
    base._panel_title(ax, "a", "")
    for row, (k, seq, turn) in enumerate(families):
        color = base.COLORS[(k - 1) % len(base.COLORS)]
        for w in windows:
            if (int(w["bounces"]), w["sequence"], w["turn"]) != (k, seq, turn):
                continue
            span = [(w["theta_from"] - 0.5 * step, w["theta_to"] - w["theta_from"] + step)]
            if w["window"] == "stable":
                bx.broken_barh(span, (row - 0.38, 0.76), color=color, lw=0)
            else:
                bx.broken_barh(span, (row - 0.15, 0.3), color="0.8", lw=0)
    bx.set_yticks(range(len(families)))
    bx.set_yticklabels([_family_label(s, t) for _, s, t in families], fontsize=6)
    bx.set_ylim(len(families) - 0.5, -0.5)
    bx.tick_params(axis="y", length=0)
    base._theta_axis(bx, theta)
    from matplotlib.ticker import MultipleLocator
    bx.xaxis.set_major_locator(MultipleLocator(5))
    bx.xaxis.set_minor_locator(MultipleLocator(1))
    bx.set_xlim(lo, float(np.max(theta)))
    base._panel_title(bx, "b", "")
    return fig


#: The plot function of each kind, merged into funnel.plot.PLOTTERS.
PLOTTERS = {
    "funnel_sketch": plot_funnel_sketch,
    "period2_orbits": plot_period2_orbits,
    "retrace_orbits": plot_retrace_orbits,
    "retrace_windows": plot_retrace_windows,
}
