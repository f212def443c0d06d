"""Figures of the paper from the data that ``funnel paper`` writes (docs/python.md).

``python -m funnel.plot OUTDIR`` renders, for every ``OUTDIR/figNN/`` holding ``figNN.json`` and
``figNN.csv``, the files ``figNN.png`` and ``figNN.svg`` next to them, then writes
``OUTDIR/index.html`` (see :mod:`funnel.report`). matplotlib is imported only when a figure is
drawn; figures are drawn on the Agg canvas without pyplot, so no display is needed. The data
are read with the standard csv module and numpy.

Figure kinds (the JSON's "kind"): theta_sweep (Figs. 2-6, 13), release_scan (Fig. 7),
trajectories (Fig. 8), eigenvalues (Fig. 10), closed_final (Fig. 11), periodic_fraction (Fig. 12);
and, drawn by :mod:`funnel.plot_orbits`, funnel_sketch (Fig. 1), period2_orbits (Fig. 9),
retrace_orbits (Fig. 14), retrace_windows (Fig. 2 explained, beyond the paper); and, drawn by
:mod:`funnel.plot_designer`, wear_profiles (where the walls wear, beyond the paper) and
cone_3d_sweep (the cone in 3D with sideways release velocities, beyond the paper).

``python -m funnel.plot trajectory --theta 60 --release 0.3 --out traj.png`` draws one simulated
trajectory instead (:mod:`funnel.trajectory`).
"""

from __future__ import annotations

import csv
import json
import math
import os
import sys
from collections.abc import Mapping
from pathlib import Path

import numpy as np

#: Axis label and unit of each observable (units of the nondimensionalisation, docs/model.md §1).
OBSERVABLE_LABELS = {
    "duration": ("average duration", r"$\sqrt{H/g}$"),
    "impulse": ("average impulse", r"$m\sqrt{gH}$"),
    "normal_impulse": ("average normal impulse", r"$m\sqrt{gH}$"),
    "energy_loss": ("average energy loss", r"$mgH$"),
    "collisions": ("average number of collisions", None),
    "edge_collisions": ("average number of edge collisions", None),
    "contact_time": ("average contact time", r"$\sqrt{H/g}$"),
    "duration_exited": ("average duration (balls that leave)", r"$\sqrt{H/g}$"),
    "impulse_exited": ("average impulse (balls that leave)", r"$m\sqrt{gH}$"),
    "energy_loss_exited": ("average energy loss (balls that leave)", r"$mgH$"),
    "trapped_fraction": ("fraction trapped (rolling for ever)", None),
    "orbits": ("average turns about the axis", None),
    "edge_contacts": ("average number of edge contacts", None),
    "exit_speed": ("average exit speed", r"$\sqrt{gH}$"),
    "exit_angle": ("average exit angle", "deg"),
    "exit_x": ("average exit position", r"$H$"),
    "exit_u": ("average exit velocity, horizontal", r"$\sqrt{gH}$"),
    "exit_v": ("average exit velocity, vertical", r"$\sqrt{gH}$"),
    "exit_spin": ("average exit spin", r"$\sqrt{g/H}$"),
}

#: Symbols of the parameters that distinguish curves.
SYMBOLS = {"theta": r"$\theta$", "e": r"$e$", "mu": r"$\mu$", "beta0": r"$\beta_0$", "radius": r"$a$",
           "gap": r"$d$", "inertia": r"$\kappa$", "t_max": r"$t_\mathrm{max}$", "velocity_sd": r"$\sigma$"}

#: Curve colours (Okabe-Ito, readable in gray and by colour-blind readers); black first.
COLORS = ("#000000", "#E69F00", "#0072B2", "#009E73", "#D55E00", "#CC79A7", "#56B4E9", "#F0E442")

#: Open markers cycled with the colours: curves that coincide (μ = 1 and 5 in Figs. 3-5, θ = 60°
#: and 70° in Fig. 12, |λ2| = |λ3| in Fig. 10) stay visible by their markers and dashes.
MARKERS = ("o", "s", "^", "v", "D", "x", "+", "*")
MARKER_NAMES = ("circles", "squares", "triangles", "down-triangles", "diamonds", "crosses", "plus signs", "stars")
DASHED = (0, (4.5, 2.0))

#: Publication style: serif text (STIX, as in the paper), thin lines, ticks inside.
STYLE = {
    "font.family": "STIXGeneral",
    "mathtext.fontset": "stix",
    "font.size": 9,
    "axes.labelsize": 9,
    "axes.titlesize": 9,
    "legend.fontsize": 7.5,
    "xtick.labelsize": 8,
    "ytick.labelsize": 8,
    "axes.linewidth": 0.7,
    "lines.linewidth": 1.0,
    "xtick.direction": "in",
    "ytick.direction": "in",
    "xtick.top": True,
    "ytick.right": True,
    "xtick.major.size": 3.5,
    "ytick.major.size": 3.5,
    "xtick.minor.size": 2,
    "ytick.minor.size": 2,
    "xtick.major.width": 0.6,
    "ytick.major.width": 0.6,
    "legend.frameon": False,
    "legend.handlelength": 1.8,
    "savefig.dpi": 200,
    "svg.hashsalt": "funnel",
    # Layout engines come only from _new_figure; so that render's set_layout_engine(None) leaves
    # none, whatever a user's matplotlibrc says.
    "figure.autolayout": False,
    "figure.constrained_layout.use": False,
}

#: Columns read as text even when every field looks like a number.
TEXT_COLUMNS = frozenset({"panel", "kind", "wall", "regime", "status", "state", "release_dist"})

#: Kinds drawn by funnel.plot_orbits (imported when first needed).
ORBIT_KINDS = ("funnel_sketch", "period2_orbits", "retrace_orbits", "retrace_windows")

#: Kinds drawn by funnel.plot_designer (imported when first needed).
DESIGNER_KINDS = ("wear_profiles", "cone_3d_sweep")

KINDS = ("theta_sweep", "release_scan", "trajectories", "eigenvalues", "closed_final", "periodic_fraction")


# ---------------------------------------------------------------------------------------------
# Data

class Columns(Mapping):
    """Columns of a CSV as 1-D numpy arrays, each converted when first read: a figure draws a
    few of the hundred columns a record holds (reading every one took a tenth of the drawing
    time). ``select(mask)`` gives the rows where mask holds, again column by column."""

    def __init__(self, names, load):
        self._names = list(names)
        self._known = frozenset(self._names)
        self._load = load
        self._cache = {}

    def __getitem__(self, name):
        if name in self._cache:
            return self._cache[name]
        if name not in self._known:
            raise KeyError(name)
        values = self._cache[name] = self._load(name)
        return values

    def __contains__(self, name):
        return name in self._known

    def __iter__(self):
        return iter(self._names)

    def __len__(self):
        return len(self._names)

    def select(self, mask):
        mask = np.asarray(mask)
        return Columns(self._names, lambda name: self[name][mask])


def _column_array(name, values):
    if name in TEXT_COLUMNS:
        return np.array(values, dtype=str)
    try:
        return np.array([float(v) for v in values], dtype=np.float64)
    except ValueError:
        return np.array(values, dtype=str)


def read_csv(path):
    """Columns of a CSV file as a mapping of 1-D numpy arrays (:class:`Columns`): float64 where
    every field is a number, str otherwise (and always for the TEXT_COLUMNS)."""
    with open(path, newline="") as f:
        reader = csv.reader(f)
        header = next(reader, [])
        rows = [row for row in reader if row]
    index = {name: j for j, name in enumerate(header)}

    def load(name):
        j = index[name]
        return _column_array(name, [row[j] if j < len(row) else "" for row in rows])

    return Columns(header, load)


def load_meta(figdir):
    """The JSON record ``figNN/figNN.json`` of a figure; ValueError naming the file if it is not
    a figure's record (not JSON, or no known kind)."""
    figdir = Path(figdir)
    path = figdir / f"{figdir.name}.json"
    try:
        with open(path) as f:
            meta = json.load(f)
    except json.JSONDecodeError as err:
        raise ValueError(f"invalid figure data '{path}': not JSON ({err})") from None
    if not isinstance(meta, dict) or meta.get("kind") not in KINDS + ORBIT_KINDS + DESIGNER_KINDS:
        kind = meta.get("kind") if isinstance(meta, dict) else None
        raise ValueError(f"invalid figure data '{path}': kind = {kind!r}; valid kinds are "
                         f"{', '.join(KINDS + ORBIT_KINDS + DESIGNER_KINDS)}")
    return meta


def load_figure(figdir):
    """(meta, columns) of a figure directory ``figNN/`` with ``figNN.json`` and ``figNN.csv``."""
    figdir = Path(figdir)
    return load_meta(figdir), read_csv(figdir / f"{figdir.name}.csv")


def _select(columns, mask):
    if isinstance(columns, Columns):
        return columns.select(mask)
    return {name: values[mask] for name, values in columns.items()}


def _unique(values):
    """Distinct values in order of first appearance."""
    seen = []
    for v in values.tolist():
        if v not in seen:
            seen.append(v)
    return seen


def _panels(meta, columns):
    """[(id, label)] of the figure's panels: those of the CSV's panel column, with their labels
    from the JSON (else the JSON's list). A panel without a label is named by the series column
    when it holds one value there (e.g. "θ = 20°" in Fig. 7)."""
    panels = [(str(p.get("id", "")), str(p.get("label", ""))) for p in meta.get("panels") or []]
    if "panel" in columns:
        labels = dict(panels)
        ids = [str(p) for p in _unique(columns["panel"])]
        panels = [(pid, labels[pid]) for pid, _ in panels if pid in ids]
        panels += [(pid, labels.get(pid, "")) for pid in ids if pid not in dict(panels)]
    series = meta.get("series")
    if series in columns and "panel" in columns:
        for i, (pid, label) in enumerate(panels):
            values = _unique(columns[series][columns["panel"] == pid])
            if not label and len(values) == 1:
                panels[i] = (pid, series_label(series, values[0]))
    return panels or [("", "")]


def _panel_rows(columns, panel_id):
    if "panel" not in columns or panel_id == "":
        return columns
    return _select(columns, columns["panel"].astype(str) == panel_id)


def _number(x):
    return (f"{x:g}" if isinstance(x, float) else str(x)).replace("-", "\u2212")


def series_label(name, value):
    """Legend text of one curve, e.g. "μ = 0.05", "θ = 50°", "cone (disk)"."""
    if name == "release_dist":
        return {"disk": "cone (disk)", "line": "2D funnel (line)"}.get(str(value), str(value))
    text = f"{SYMBOLS.get(name, name)} = {_number(value)}"
    return text + "°" if name == "theta" else text


def pretty(label):
    """A panel label as mathtext: "β0 = -0.31" -> "$\\beta_0$ = −0.31"."""
    for plain, math_text in (("β0", r"$\beta_0$"), ("μ", r"$\mu$"), ("θ", r"$\theta$"), ("κ", r"$\kappa$")):
        label = label.replace(plain, math_text)
    return label.replace("= -", "= \u2212")


def axis_label(observable):
    label, unit = OBSERVABLE_LABELS.get(observable, (observable.replace("_", " "), None))
    return f"{label} [{unit}]" if unit else label


# ---------------------------------------------------------------------------------------------
# Drawing helpers

def _new_figure(width, height):
    from matplotlib.figure import Figure  # lazy: the package works without matplotlib
    from matplotlib.layout_engine import ConstrainedLayoutEngine
    return Figure(figsize=(width, height), layout=ConstrainedLayoutEngine(h_pad=0.06, w_pad=0.06))


def _panel_title(ax, letter, label, centred=False):
    """Panel letter "(a)" above the axes on the left; the label next to it, or centred."""
    text = f"({letter})" if letter else ""
    label = pretty(label)
    if centred:
        if text:
            ax.set_title(text, loc="left", pad=3)
        if label:
            ax.set_title(label, pad=3)
    else:
        ax.set_title(f"{text}  {label}".strip(), loc="left", pad=3)


def _legend_band(entries, ncol):
    """Height in inches of a legend band of `entries` in `ncol` columns."""
    return 0.17 * math.ceil(entries / ncol) + 0.06 if entries else 0.0


def _top_legend(fig, ncol, **kwargs):
    """One legend of every panel's labelled artists, in a band above all panels (the figure is
    already that much taller)."""
    handles, labels = [], []
    for ax in fig.axes:
        for h, lab in zip(*ax.get_legend_handles_labels()):
            if lab not in labels:
                handles.append(h)
                labels.append(lab)
    if not handles:
        return
    band = _legend_band(len(handles), ncol)
    fig.get_layout_engine().set(rect=(0, 0, 1, 1 - band / fig.get_figheight()))
    fig.legend(handles, labels, loc="upper center", bbox_to_anchor=(0.5, 1.0), ncol=ncol,
               columnspacing=1.4 if ncol * 1.1 < fig.get_figwidth() else 0.8, handlelength=1.5, borderaxespad=0.2,
               **kwargs)


def _theta_axis(ax, theta):
    from matplotlib.ticker import MultipleLocator
    ax.axvline(45.0, color="0.45", lw=0.7, ls=(0, (4, 3)), zorder=0)
    if len(theta):
        lo, hi = float(np.min(theta)), float(np.max(theta))
        if hi > lo:
            ax.set_xlim(lo, hi)
    ax.xaxis.set_major_locator(MultipleLocator(15))
    ax.xaxis.set_minor_locator(MultipleLocator(5))
    ax.set_xlabel(r"$\theta$ [deg]")


def curve_style(index, count=None, points=None):
    """Matplotlib keywords of curve `index` among `count` curves of `points` points each: an
    Okabe-Ito colour, solid for even and dashed for odd indices (drawn on top, so a dashed curve
    lying on a solid one shows both), an open marker of its own; with `points`, about six markers
    per curve, shifted from curve to curve so that coinciding curves do not hide each other's."""
    style = {"color": COLORS[index % len(COLORS)], "ls": "-" if index % 2 == 0 else DASHED,
             "marker": MARKERS[index % len(MARKERS)], "ms": 3.2, "mfc": "none", "mew": 0.8,
             "zorder": 2.2 + 0.1 * (index % 2)}
    if points is not None and points > 12:
        step = max(1, points // 6)
        style["markevery"] = ((index * step) // max(1, count or 1) % step, step)
    return style


def style_description(index):
    """Words for the style of curve `index` (for captions), e.g. "dashed, open squares"."""
    return f"{'solid' if index % 2 == 0 else 'dashed'}, {MARKER_NAMES[index % len(MARKER_NAMES)]}"


def _series_style(series, index, value, count=None, points=None):
    """Line keywords of curve `index`; Fig. 13 draws the cone solid and the 2D funnel dashed."""
    style = curve_style(index, count, points)
    if series == "release_dist":
        line = str(value) == "line"
        style.update(color="#0072B2" if line else "#000000", ls=DASHED if line else "-", marker="s" if line else "o")
    return style


# ---------------------------------------------------------------------------------------------
# The kinds

def plot_theta_sweep(meta, columns):
    """<observable>_mean vs theta, one curve per value of the series column, a ±sem band;
    one column per panel, one row per observable."""
    panels = _panels(meta, columns)
    observables = meta.get("observables") or ["duration"]
    series = meta.get("series")
    nrow, ncol = len(observables), len(panels)
    values = _unique(columns[series]) if series and series in columns else [None]
    legend_cols = len(values) if ncol > 1 or len(values) <= 4 else 3
    band = _legend_band(len(values) if values != [None] else 0, legend_cols)
    fig = _new_figure(3.4 if ncol == 1 else 7.0, (2.5 if ncol == 1 else 2.2) * nrow + 0.2 + band)
    axes = fig.subplots(nrow, ncol, squeeze=False, sharex=True, sharey="row")
    grid = nrow > 1
    for c, (pid, plabel) in enumerate(panels):
        rows = _panel_rows(columns, pid)
        for r, obs in enumerate(observables):
            ax = axes[r][c]
            for k, value in enumerate(values):
                sel = rows if value is None else _select(rows, rows[series] == value)
                order = np.argsort(sel["theta"], kind="stable")
                theta = sel["theta"][order]
                mean = sel[f"{obs}_mean"][order]
                style = _series_style(series, k, value, len(values), len(theta))
                label = None if value is None else series_label(series, value)
                if f"{obs}_sem" in sel:
                    sem = sel[f"{obs}_sem"][order]
                    ax.fill_between(theta, mean - sem, mean + sem, color=style["color"], alpha=0.18, lw=0)
                ax.plot(theta, mean, lw=0.9, label=label, **style)
            _theta_axis(ax, rows["theta"])
            if c == 0:
                ax.set_ylabel(axis_label(obs))
            if r < nrow - 1:
                ax.set_xlabel("")
            if grid:
                letter = "abcdefghijklmnopqrstuvwxyz"[r * ncol + c]
                _panel_title(ax, letter, plabel if r == 0 else "", centred=True)
            else:
                _panel_title(ax, pid if ncol > 1 else "", plabel, centred=True)
    for row in axes:  # a row shares its y axis: scale it to all its panels' data, from 0
        row[0].autoscale_view(scalex=False)
        row[0].set_ylim(bottom=0)
    if values != [None]:
        _top_legend(fig, legend_cols)
    return fig


def plot_release_scan(meta, columns):
    """Duration vs x0/L, one panel per funnel angle (3 x 3 for Fig. 7), as small points."""
    panels = _panels(meta, columns)
    ncol = 3 if len(panels) > 4 else len(panels)
    nrow = math.ceil(len(panels) / ncol)
    fig = _new_figure(7.0, 1.95 * nrow + 0.3)
    axes = fig.subplots(nrow, ncol, squeeze=False, sharex=True)
    for i, (pid, plabel) in enumerate(panels):
        ax = axes[i // ncol][i % ncol]
        rows = _panel_rows(columns, pid)
        status = rows["status"].astype(str) if "status" in rows else np.full(len(rows["release"]), "exited")
        done = status == "exited"
        ax.scatter(rows["release"][done], rows["duration"][done], s=1.0, c="k", marker="o", lw=0,
                   rasterized=True)
        if np.any(~done):
            ax.scatter(rows["release"][~done], rows["duration"][~done], s=4, c="#D55E00", marker="x", lw=0.5,
                       label="not exited", rasterized=True)
            ax.legend(loc="best", markerscale=1.5)
        ax.set_xlim(-1, 1)
        ax.margins(y=0.04)
        ax.set_ylim(bottom=0)
        _panel_title(ax, pid, plabel)
        if i // ncol == nrow - 1:
            ax.set_xlabel(r"$x_0/L$")
        if i % ncol == 0:
            ax.set_ylabel(r"duration [$\sqrt{H/g}$]")
    for j in range(len(panels), nrow * ncol):
        axes[j // ncol][j % ncol].set_visible(False)
    return fig


def trajectory_path(geometry, events, samples_per_arc=None, window=None):
    """(x, y, t) of the particle centre's path between the logged events: parabolas in flight,
    straight along a face during a sustained contact, arcs about an edge point during an edge
    contact (see funnel.motion.trajectory_path)."""
    from .motion import trajectory_path as path
    return path(geometry, events, samples_per_arc, window)


def plot_trajectories(meta, columns):
    """The particle centre's path in the funnel, one panel per trajectory, with a zoom on the
    bounces of a trajectory that settles into them (drawn by funnel.trajectory)."""
    from .trajectory import plot_trajectories as draw
    return draw(meta, columns)


def plot_eigenvalues(meta, columns):
    """Moduli of the eigenvalues vs theta: solid where the orbit is stable, dashed where not.
    Each eigenvalue has its colour and marker, so |λ2| = |λ3| (a complex pair) stays visible."""
    from matplotlib.lines import Line2D
    fig = _new_figure(3.4, 2.9)
    ax = fig.subplots()
    theta = columns["theta"]
    order = np.argsort(theta, kind="stable")
    theta = theta[order]
    stable = columns["stable"][order] > 0.5
    # Each style is extended by one point into the other, so that the curves stay connected.
    grow = lambda m: m | np.concatenate([m[1:], [False]]) | np.concatenate([[False], m[:-1]])
    solid, dashed = grow(stable), grow(~stable)
    mods = sorted((c for c in columns if c.startswith("mod") and c[3:].isdigit()), key=lambda c: int(c[3:]))
    handles = []
    for k, name in enumerate(mods):
        y = columns[name][order]
        style = curve_style(k, len(mods), len(theta))
        del style["ls"]
        # Odd curves wide and below, even ones thin on top: a pair of equal moduli shows as a
        # thin line inside a wide one.
        lw = 2.2 if k % 2 else 0.9
        line = dict(style, marker="None", zorder=2.0 if k % 2 else 2.4)
        ax.plot(theta, np.where(solid, y, np.nan), lw=lw, **line)
        ax.plot(theta, np.where(dashed, y, np.nan), lw=lw, ls=(0, (4.5 / lw, 2.0 / lw)), **line)
        ax.plot(theta, y, ls="None", **style)  # markers on both parts, at shifted angles
        handles.append(Line2D([], [], color=style["color"], marker=style["marker"], mfc="none", ms=3.2, mew=0.8,
                              lw=lw, label=rf"$|\lambda_{name[3:]}|$"))
    handles += [Line2D([], [], color="0.2", lw=1.0, label="stable"),
                Line2D([], [], color="0.2", lw=1.0, ls=DASHED, label="unstable")]
    ax.axhline(1.0, color="0.5", lw=0.6, ls=":", zorder=0)
    _theta_axis(ax, theta)
    ax.set_ylabel(r"$|\lambda|$")
    fig.get_layout_engine().set(rect=(0, 0, 1, 1 - _legend_band(3, 3) / fig.get_figheight()))
    fig.legend(handles=handles, loc="upper center", bbox_to_anchor=(0.5, 1.0), ncol=3, columnspacing=1.2,
               handlelength=2.2, borderaxespad=0.2)
    return fig


def closed_final_reach(columns):
    """Half the y range of Fig. 11: the largest |x_c/L| of the data plus 12%, at least 0.05."""
    values = np.abs(np.concatenate([columns["x_last_over_L"], columns["x_prev_over_L"]]))
    values = values[np.isfinite(values)]
    return max(0.05, 1.12 * float(values.max())) if len(values) else 1.0


def plot_closed_final(meta, columns):
    """x_c/L of the last two collisions vs x0/L in a closed funnel: gray when the particle ends
    on the periodic orbit, dark when it comes to rest."""
    from matplotlib.ticker import MultipleLocator
    panels = _panels(meta, columns)
    ncol = 2 if len(panels) > 1 else 1
    nrow = math.ceil(len(panels) / ncol)
    states = set(columns["state"].astype(str).tolist())
    fig = _new_figure(3.3 * ncol, 2.3 * nrow + 0.2 + _legend_band(len(states), 3))
    axes = fig.subplots(nrow, ncol, squeeze=False, sharex=True, sharey=True)
    # The y range fits the data: the largest |x_c/L| of any panel, with a margin.
    reach = closed_final_reach(columns)
    styles = (("periodic", "0.6", "periodic orbit"), ("rest", "0.05", "rest"), ("undecided", "#D55E00", "undecided"))
    for i, (pid, plabel) in enumerate(panels):
        ax = axes[i // ncol][i % ncol]
        rows = _panel_rows(columns, pid)
        state = rows["state"].astype(str)
        for name, color, label in styles:
            m = state == name
            if not np.any(m):
                continue
            x = np.concatenate([rows["release"][m]] * 2)
            y = np.concatenate([rows["x_last_over_L"][m], rows["x_prev_over_L"][m]])
            ax.scatter(x, y, s=1.5, c=color, marker="o", lw=0, label=label, rasterized=True)
        ax.set_xlim(-1, 1)
        ax.set_ylim(-reach, reach)
        ax.xaxis.set_major_locator(MultipleLocator(0.5))
        ax.xaxis.set_minor_locator(MultipleLocator(0.25))
        _panel_title(ax, pid if len(panels) > 1 else "", plabel)
        if i // ncol == nrow - 1:
            ax.set_xlabel(r"$x_0/L$")
        if i % ncol == 0:
            ax.set_ylabel(r"$x_c/L$")
    _top_legend(fig, 3, markerscale=3, handletextpad=0.2)
    for j in range(len(panels), nrow * ncol):
        axes[j // ncol][j % ncol].set_visible(False)
    return fig


def plot_periodic_fraction(meta, columns):
    """Fraction of releases reaching the periodic orbit vs mu, one curve per theta."""
    fig = _new_figure(3.4, 2.6)
    ax = fig.subplots()
    mu_all = columns["mu"]
    thetas = _unique(columns["theta"])
    for k, theta in enumerate(thetas):
        sel = _select(columns, columns["theta"] == theta)
        order = np.argsort(sel["mu"], kind="stable")
        ax.plot(sel["mu"][order], sel["periodic_fraction"][order], label=series_label("theta", theta),
                **curve_style(k, len(thetas), len(order)))
    positive = mu_all[mu_all > 0]
    if len(positive) and positive.max() / positive.min() >= 100:
        if np.any(mu_all <= 0):
            ax.set_xscale("symlog", linthresh=float(positive.min()))
        else:
            ax.set_xscale("log")
    ax.set_ylim(-0.02, 1.05)
    ax.set_xlabel(r"$\mu$")
    ax.set_ylabel("fraction reaching the periodic orbit")
    ax.legend(loc="best")
    return fig


PLOTTERS = {
    "theta_sweep": plot_theta_sweep,
    "release_scan": plot_release_scan,
    "trajectories": plot_trajectories,
    "eigenvalues": plot_eigenvalues,
    "closed_final": plot_closed_final,
    "periodic_fraction": plot_periodic_fraction,
}


def plot_figure(meta, columns):
    """The matplotlib Figure of a figure's data (meta from the JSON, columns from the CSV)."""
    import matplotlib
    kind = meta.get("kind")
    if kind in ORBIT_KINDS and kind not in PLOTTERS:
        from .plot_orbits import PLOTTERS as orbit_plotters
        PLOTTERS.update(orbit_plotters)
    if kind in DESIGNER_KINDS and kind not in PLOTTERS:
        from .plot_designer import PLOTTERS as designer_plotters
        PLOTTERS.update(designer_plotters)
    if kind not in PLOTTERS:
        raise ValueError(f"unknown figure kind {kind!r}: valid kinds are "
                         f"{', '.join(KINDS + ORBIT_KINDS + DESIGNER_KINDS)}")
    with matplotlib.rc_context(STYLE):
        return PLOTTERS[kind](meta, columns)


#: The files of a figure, and the metadata savefig leaves out of each (no version or date: the
#: same data give the same bytes).
FORMATS = (("png", {"Software": None}), ("svg", {"Date": None, "Creator": None}))


def render(figdir):
    """Draws ``figdir/figNN.{png,svg}`` from ``figdir/figNN.{json,csv}``; returns (meta, [paths])."""
    import matplotlib
    from ._files import replacing
    figdir = Path(figdir)
    meta, columns = load_figure(figdir)
    fig = plot_figure(meta, columns)
    paths = []
    with matplotlib.rc_context(STYLE):
        lay_out(fig)
        for ext, metadata in FORMATS:
            path = figdir / f"{figdir.name}.{ext}"
            with replacing(path, hidden=False) as tmp:  # never a partial image, nor a stray temporary
                fig.savefig(tmp, format=ext, metadata=metadata)
            paths.append(path)
    return meta, paths


def lay_out(fig):
    """Runs fig's layout engine once, as savefig would for the PNG, and removes the engine.

    With an engine, savefig first draws the whole figure without output (to lay it out), then
    draws it into the file. Here only the layout runs, at the PNG's resolution (the text's extents
    depend on it) on an Agg canvas, as savefig's own pass does; both files are then drawn once
    each. The Agg canvas stays: the PNG is drawn by the renderer that laid the figure out, which
    has measured its texts already (matplotlib caches their extents by renderer). None, not
    "none": "none" leaves a placeholder engine, with which savefig still draws the figure once
    without output. The PNG and SVG are the same bytes as savefig's with the engine
    (python/tests/test_plot.py compares them), in 10–15% less time.
    """
    import matplotlib
    from matplotlib.backends.backend_agg import FigureCanvasAgg
    engine = fig.get_layout_engine()
    if engine is None:
        return
    dpi = fig.get_dpi()
    saved_dpi = matplotlib.rcParams["savefig.dpi"]
    FigureCanvasAgg(fig)  # attaches itself to fig, and stays: the PNG is drawn with its renderer
    fig.set_dpi(dpi if saved_dpi == "figure" else saved_dpi)
    try:
        engine.execute(fig)
    finally:
        fig.set_dpi(dpi)
    fig.set_layout_engine(None)


def figure_dirs(outdir):
    """The subdirectories ``figNN`` of outdir that hold figNN.json and figNN.csv, sorted."""
    outdir = Path(outdir)
    return sorted(d for d in outdir.iterdir()
                  if d.is_dir() and (d / f"{d.name}.json").is_file() and (d / f"{d.name}.csv").is_file())


def no_figures(outdir):
    """The ValueError for an outdir without figure directories (what funnel.plot and
    funnel.report refuse: nothing to draw, and an empty page would replace the index)."""
    return ValueError(f"invalid outdir = '{outdir}': no figure directories (figNN/ with figNN.json and figNN.csv) "
                      "found in it; valid outdirs are those funnel paper writes")


def _render_entry(figdir):
    meta, paths = render(figdir)
    return {"dir": Path(figdir).name, "meta": meta, "images": [p.name for p in paths]}, paths


def render_all(outdir, log=None, jobs=None):
    """Renders every figure of outdir and writes outdir/index.html; returns the index's path.

    ``jobs`` figures are drawn at once in separate processes (default: the number of cores;
    1 draws them one after the other in this process). Each picture is the same either way.
    ValueError when outdir holds no figure directory.
    """
    from . import report
    dirs = figure_dirs(outdir)
    if not dirs:
        raise no_figures(outdir)  # not "invalid jobs = 0" (one job per figure, at most)
    for figdir in dirs:
        load_meta(figdir)  # every record readable before any picture is drawn
    jobs = min(len(dirs), os.cpu_count() or 1) if jobs is None else int(jobs)
    if jobs < 1:
        raise ValueError(f"invalid jobs = {jobs}: valid range is an integer >= 1")
    by_dir = {}
    if jobs == 1 or len(dirs) < 2:
        for figdir in dirs:
            by_dir[figdir], paths = _render_entry(figdir)
            if log:
                log(f"funnel.plot: wrote {', '.join(str(p) for p in paths)}")
    else:
        import concurrent.futures
        import multiprocessing

        import matplotlib.figure  # noqa: F401  (imported once here, inherited by the forked workers)
        context = multiprocessing.get_context("fork")
        with concurrent.futures.ProcessPoolExecutor(max_workers=jobs, mp_context=context) as pool:
            futures = {pool.submit(_render_entry, figdir): figdir for figdir in dirs}
            for done in concurrent.futures.as_completed(futures):
                by_dir[futures[done]], paths = done.result()
                if log:
                    log(f"funnel.plot: wrote {', '.join(str(p) for p in paths)}")
    return report.write_index(outdir, [by_dir[d] for d in dirs])


def main(argv=None):
    """Command line: ``python -m funnel.plot OUTDIR``, or ``python -m funnel.plot trajectory
    --theta 60 --release 0.3 --out traj.png`` for one trajectory (funnel.trajectory)."""
    from ._files import OneLineParser
    argv = sys.argv[1:] if argv is None else list(argv)
    if argv[:1] == ["trajectory"]:
        from .trajectory import main as trajectory_main
        return trajectory_main(argv[1:], prog="python -m funnel.plot trajectory")
    if argv[:1] == ["bench"]:
        from .plot_bench import main as bench_main
        return bench_main(argv[1:])
    parser = OneLineParser(prog="python -m funnel.plot", description=(
        "Render OUTDIR/figNN/figNN.{png,svg} from figNN.{json,csv} for every figure directory, "
        "then write OUTDIR/index.html."), epilog=(
        "One trajectory: python -m funnel.plot trajectory --theta 60 --release 0.3 --out traj.png "
        "(see python -m funnel.plot trajectory --help); a directory named 'trajectory': ./trajectory. "
        "Collisions per second by engine path: python -m funnel.plot bench BENCH.json --out bench.png."))
    parser.add_argument("outdir", help="directory with one subdirectory figNN/ per figure")
    parser.add_argument("--jobs", type=int, default=None,
                        help="figures drawn at once, in separate processes (default: the number of cores)")
    args = parser.parse_args(argv)
    if args.jobs is not None and args.jobs < 1:
        parser.error(f"invalid jobs = {args.jobs}: valid range is an integer >= 1")
    outdir = Path(args.outdir)
    if not outdir.is_dir():
        parser.error(f"invalid outdir = '{outdir}': not a directory")
    try:
        index = render_all(outdir, log=lambda msg: print(msg, file=sys.stderr), jobs=args.jobs)
    except (ValueError, KeyError, IndexError, OSError) as err:
        # Bad figure data (or an unwritable picture): one line, exit status 2, not a traceback.
        what = f"missing column {err}" if isinstance(err, KeyError) else str(err)
        print(f"python -m funnel.plot: error: {what}", file=sys.stderr)
        return 2
    print(f"funnel.plot: wrote {index}", file=sys.stderr)
    return 0


if __name__ == "__main__":
    try:
        sys.exit(main())
    except KeyboardInterrupt:  # Ctrl-C: one line and the shell's status, not a traceback (no file is left)
        print("python -m funnel.plot: interrupted", file=sys.stderr)
        sys.exit(130)
