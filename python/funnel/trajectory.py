"""Pictures of single trajectories: the funnel, the centre's path and the collision points.

``python -m funnel.plot trajectory --theta 60 --release 0.3 --out traj.png`` (or
``python -m funnel.trajectory ...``) simulates one trajectory with :func:`funnel.simulate` and
draws it: the walls ending at their edge points, the centre lines (dotted) and the release line
(dash-dotted) in the frame of the paper's Fig. 1; the path of the centre (parabolas in flight,
straight along a face during a sustained contact, arcs about an edge point during an edge
contact; see :mod:`funnel.motion`) coloured by time; the collisions as dots. When the particle
settles into bouncing between the walls, a second panel zooms on a few of those bounces. The
same drawing makes panels of the paper's Fig. 8 (:func:`funnel.plot.plot_trajectories`).
matplotlib is imported only when drawing.
"""

from __future__ import annotations

import math
import sys
from pathlib import Path

import numpy as np

from . import motion

#: Bounces shown by the zoom panel, and the shortest alternating run that gets one.
ZOOM_COLLISIONS = 4
ZOOM_MIN_RUN = 20

#: Colours of the special segments and points (Okabe-Ito).
CONTACT_COLOR = "#009E73"
EDGE_COLOR = "#D55E00"
RELEASE_COLOR = "#D55E00"


def time_colormap():
    """Light blue (early) to dark blue (late), so that a repeating pattern stands out."""
    from matplotlib import colormaps
    from matplotlib.colors import ListedColormap
    return ListedColormap(colormaps["Blues"](np.linspace(0.3, 1.0, 256)))


def draw_funnel(ax, g):
    """Walls (solid, ending at the edge points), centre lines (dotted, meeting at the origin)
    and the release line (dash-dotted), in the frame of the paper's Fig. 1. g: a geometry dict
    (theta [deg], half_gap, y_bottom, y_release, half_width, as funnel.geometry()). A funnel
    of any shape (g["walls"] and g["source"] != "v") is drawn from its walls' vertices."""
    if _from_walls(g):
        for side in ("left", "right"):
            xy = np.asarray(g["walls"][side], dtype=float)
            ax.plot(xy[:, 0], xy[:, 1], color="k", lw=1.6, solid_capstyle="butt", zorder=3)
        mid, L = g.get("x_release_mid", 0.0), g["half_width"]
        ax.plot([mid - L, mid + L], [g["y_release"]] * 2, color="0.3", lw=0.7, ls="-.", zorder=1)
        return
    t = math.radians(g["theta"])
    s, c = math.sin(t), math.cos(t)
    top = g["y_release"] + 0.06
    for sign in (-1.0, 1.0):
        ex, ey = sign * g["half_gap"], g["y_bottom"]
        length = (top - ey) / s
        ax.plot([ex, ex + sign * c * length], [ey, top], color="k", lw=1.6, solid_capstyle="butt", zorder=3)
        ax.plot([0.0, sign * top / math.tan(t)], [0.0, top], color="0.4", lw=0.6, ls=(0, (1, 2)), zorder=1)
    L = g["half_width"]
    ax.plot([-L, L], [g["y_release"]] * 2, color="0.3", lw=0.7, ls="-.", zorder=1)


def draw_path(ax, g, events, norm, lw=0.35, point_size=1.2, window=None):
    """Draws the centre's path coloured by time (norm: a matplotlib Normalize of the time),
    the collision points, sustained contacts (green) and edge contacts (vermillion); returns the
    path's LineCollection (for a colour bar). window: (first, last) event indices to draw only
    the path from event first to event last."""
    from matplotlib.collections import LineCollection
    n = len(events["time"])
    k = 48 if window is not None else 24 if n < 2000 else 8
    px, py, pt = motion.trajectory_path(g, events, samples_per_arc=k, window=window)
    lines = LineCollection(np.zeros((0, 2, 2)), cmap=time_colormap(), norm=norm, lw=lw, zorder=2)
    if len(px) > 1:
        # One polyline per segment between events, coloured by its mean time: few paths, so
        # the SVG stays small.
        arcs = np.stack([px, py], axis=1).reshape(-1, k, 2)
        lines = LineCollection(arcs, cmap=time_colormap(), norm=norm, lw=lw, zorder=2, capstyle="round",
                               rasterized=len(arcs) > 20000)
        lines.set_array(pt.reshape(-1, k).mean(axis=1))
        ax.add_collection(lines)
        seg = motion.Segments(g, events)
        first = 0 if window is None else window[0] + 1
        for kind, color in ((motion.FACE_CONTACT, CONTACT_COLOR), (motion.EDGE_CONTACT, EDGE_COLOR)):
            for i in np.flatnonzero(seg.kind[first:first + len(px) // k] == kind):
                ax.plot(px[i * k:(i + 1) * k], py[i * k:(i + 1) * k], color=color, lw=max(1.2, 3 * lw), zorder=3,
                        solid_capstyle="round")
    sub = events if window is None else {key: np.asarray(v)[window[0]:window[1] + 1] for key, v in events.items()}
    cx, cy, _ = motion.collision_points(sub)
    if len(cx):
        ax.scatter(cx, cy, s=point_size, c="k", lw=0, zorder=4)
    return lines


def zoom_window(events, collisions=ZOOM_COLLISIONS, min_run=ZOOM_MIN_RUN):
    """(first, last) event indices of `collisions` consecutive bounces in the middle of the
    longest run of alternating face collisions, or None when that run is shorter than min_run."""
    run = motion.alternating_run(events)
    if run is None or run[1] - run[0] < min_run:
        return None
    first = (run[0] + run[1] - collisions) // 2
    return first, first + collisions


def zoom_limits(g, events, window):
    """(x_lo, x_hi, y_lo, y_hi) of a close-up of the path from event window[0] to window[1],
    with room for the ball (radius a) and the walls at the collision points."""
    px, py, _ = motion.trajectory_path(g, events, samples_per_arc=48, window=window)
    a = float(g.get("radius", 0.0))
    reach = a * (1.0 + 1.0 / math.sin(math.radians(g["theta"])))  # the wall beside a collision
    pad = 0.04 * max(px.max() - px.min(), py.max() - py.min())
    return px.min() - reach - pad, px.max() + reach + pad, py.min() - 1.5 * a - pad, py.max() + pad


def draw_zoom(ax, g, events, window, main_ax=None):
    """A close-up of the path from event window[0] to window[1], coloured by time within the
    window (light to dark), with the ball drawn to scale at the collisions; equal aspect. The
    zoomed region is outlined on main_ax."""
    from matplotlib.colors import Normalize
    from matplotlib.patches import Circle, Rectangle
    first, last = window
    draw_funnel(ax, g)
    t0, t1 = float(events["time"][first]), float(events["time"][last])
    draw_path(ax, g, events, Normalize(t0 - 0.3 * (t1 - t0), t1), lw=1.0, point_size=6, window=window)
    cx, cy, _ = motion.collision_points({k: np.asarray(v)[first:last + 1] for k, v in events.items()})
    for x, y in zip(cx, cy):
        ax.add_patch(Circle((x, y), float(g.get("radius", 0.0)), fc="0.85", ec="0.3", lw=0.5, alpha=0.6, zorder=1))
    x_lo, x_hi, y_lo, y_hi = zoom_limits(g, events, window)
    ax.set_xlim(x_lo, x_hi)
    ax.set_ylim(y_lo, y_hi)
    ax.set_aspect("equal")
    ax.set_xlabel(r"$x/H$")
    ax.text(0.5, 0.97, f"$t$ = {t0:.4g} to {t1:.4g} " r"$\sqrt{H/g}$, darker = later", transform=ax.transAxes,
            fontsize=7, ha="center", va="top")
    if main_ax is not None:
        main_ax.add_patch(Rectangle((x_lo, y_lo), x_hi - x_lo, y_hi - y_lo, fill=False, ec=EDGE_COLOR, lw=0.8,
                                    zorder=5))


def _shaped_v(g):
    """True for a V with its own wall angles or a spout (drawn from its walls' vertices)."""
    walls = g.get("walls")
    return bool(walls) and (len(walls["left"]) > 2 or not g.get("symmetric", True))


def _from_walls(g):
    """True when a funnel is drawn from its walls' vertices: a profile, or a V with its own wall
    angles or a spout (the paper's V keeps its centre lines, meeting at the origin)."""
    return bool(g.get("walls")) and (g.get("source", "v") != "v" or _shaped_v(g))


def _walls_xy(g):
    return np.concatenate([np.asarray(g["walls"][side], dtype=float) for side in ("left", "right")])


def funnel_extent(g):
    """(half width, top) of the drawing area of a funnel, in H."""
    if _from_walls(g):
        xy = _walls_xy(g)
        return float(np.max(np.abs(xy[:, 0]))) + 0.05, g["y_release"] + 0.1
    return g["y_release"] / math.tan(math.radians(g["theta"])) + 0.1, g["y_release"] + 0.1


def funnel_ylim(g):
    """(bottom, top) of the drawing area of a funnel, in H."""
    if _from_walls(g):
        return float(np.min(_walls_xy(g)[:, 1])) - 0.05, funnel_extent(g)[1]
    return min(0.0, g["y_bottom"]) - 0.05, funnel_extent(g)[1]


def legend_handles(ax, events):
    """Legend entries of a trajectory drawing: release, collision, and the contacts present."""
    kinds = set(np.asarray(events["kind"], dtype=str).tolist())
    handles = [ax.plot([], [], "o", ms=3.5, color=RELEASE_COLOR, label="release")[0],
               ax.plot([], [], "o", ms=2.5, color="k", label="collision")[0]]
    if "contact_start" in kinds:
        handles.append(ax.plot([], [], color=CONTACT_COLOR, lw=1.5, label="sliding/rolling on a face")[0])
    if "edge_contact_start" in kinds:
        handles.append(ax.plot([], [], color=EDGE_COLOR, lw=1.5, label="rolling on an edge")[0])
    return handles


def check_result(result):
    """ValueError unless result is a 2D funnel.simulate(..., events=True) result (a 3D run's
    motion leaves the plane these pictures draw; without events there is no path)."""
    if not hasattr(result, "get"):
        raise ValueError(f"invalid result = {type(result).__name__}: valid results are the dicts of "
                         "funnel.simulate(..., events=True)")
    if result.get("space", "2d") != "2d":
        raise ValueError(f"invalid result: a run with space = {result['space']!r}; valid results are 2D runs, "
                         "funnel.simulate(..., events=True) (the pictures and animations draw the plane funnel)")
    if "events" not in result:
        raise ValueError("invalid result: no 'events'; valid results come from funnel.simulate(..., events=True)")


def release_geometry(result, geometry):
    """geometry with the result's release added: "release" (x0/L) and the release state x0, y0,
    u0, v0, omega0 from which funnel.motion starts the first flight (so that it ends at the first
    event, whatever the release velocity, spin, wall angles or geometry file). ValueError for a
    result that is not a 2D one with events, or when neither gives the release."""
    check_result(result)
    g = dict(geometry)
    for key in ("release", *motion.RELEASE_STATE):
        if key in result:
            g[key] = result[key]
    if "release" not in g:
        raise ValueError("invalid geometry: no 'release' (x0/L), and none in the result; valid geometries are "
                         'funnel.geometry(**model) with "release" added, as funnel.trajectory.simulate_for_plot '
                         "gives")
    return g


def funnel_label(result, g):
    """The funnel in a title: the V's angle (both wall angles of an asymmetric V) or, for walls
    from a geometry file, the file's name (the V's angle theta does not apply to them)."""
    source = str(g.get("source", "v"))
    if source != "v":
        return Path(source).name.replace("$", r"\$")
    params = result.get("params") or {}

    def angle(key, default):  # None (or NaN): a parameter the run did not use
        value = params.get(key)
        return default if value is None or math.isnan(float(value)) else float(value)

    # With both wall angles given, params' theta is None: the walls' own angles name the funnel.
    theta = angle("theta", float(g["theta"]))
    left, right = angle("theta_left", theta), angle("theta_right", theta)
    if left == right:
        return rf"$\theta$ = {left:g}°"
    return rf"$\theta_\mathrm{{left}}$ = {left:g}°, $\theta_\mathrm{{right}}$ = {right:g}°"


def plot_trajectory(result, geometry, title=None):
    """A matplotlib Figure of one simulated trajectory (result of funnel.simulate(...,
    events=True); geometry of funnel.geometry(...) with "release" added, see release_geometry),
    with a zoom panel below when the particle settles into bouncing between the walls."""
    from matplotlib.colors import Normalize
    from matplotlib.figure import Figure
    from matplotlib.layout_engine import ConstrainedLayoutEngine
    g = release_geometry(result, geometry)
    events = result["events"]
    window = zoom_window(events)
    w, _ = funnel_extent(g)
    y_lo, y_hi = funnel_ylim(g)
    width = 5.6
    axes_w = width - 1.4
    heights = [min(6.0, max(1.0, axes_w * (y_hi - y_lo) / (2 * w)))]
    if window:
        zx0, zx1, zy0, zy1 = zoom_limits(g, events, window)
        heights.append(min(3.0, max(0.6, axes_w * (zy1 - zy0) / (zx1 - zx0))))
    fig = Figure(figsize=(width, sum(heights) + 0.75 * len(heights) + 0.3),
                 layout=ConstrainedLayoutEngine(h_pad=0.06, w_pad=0.06))
    axes = fig.subplots(len(heights), 1, squeeze=False, gridspec_kw={"height_ratios": heights})[:, 0]
    ax = axes[0]
    draw_funnel(ax, g)
    t_end = float(events["time"][-1]) if len(events["time"]) else 1.0
    lines = draw_path(ax, g, events, Normalize(0.0, t_end), lw=0.35 if len(events["time"]) > 100 else 0.8,
                      point_size=2.5)
    x0, y0, *_ = motion.release_state(g, events)
    ax.plot(x0, y0, "o", ms=3.5, color=RELEASE_COLOR, zorder=5)
    ax.set_aspect("equal")
    ax.set_xlim(-w, w)
    ax.set_ylim(y_lo, y_hi)
    ax.set_xlabel(r"$x/H$")
    ax.set_ylabel(r"$y/H$")
    ax.set_title(title or (rf"{funnel_label(result, g)}, $x_0/L$ = {float(g['release']):g}: "
                           f"{result['status']} after {result['collisions']} collisions, "
                           rf"$t$ = {result['duration']:.4g} $\sqrt{{H/g}}$"), loc="left", fontsize=8)
    bar = fig.colorbar(lines, ax=ax, shrink=0.8, aspect=25, pad=0.02)
    bar.set_label(r"$t$ [$\sqrt{H/g}$]")
    ax.legend(handles=legend_handles(ax, events), loc="lower right", fontsize=7, handlelength=1.2)
    if window:
        draw_zoom(axes[1], g, events, window, main_ax=ax)
        axes[1].set_ylabel(r"$y/H$")
        axes[1].set_title("zoom on the outlined box", loc="left", fontsize=8)
    return fig


def plot_trajectories(meta, columns):
    """The particle centre's path in the funnel, one panel per trajectory, equal aspect ratio,
    coloured by time with the collisions as dots; below, a zoom on a few bounces of each
    trajectory that settles into bouncing between the walls (Fig. 8(a))."""
    from matplotlib.colors import Normalize
    from .plot import _new_figure, _panel_rows, _panel_title, _panels
    panels = _panels(meta, columns)
    geometries = meta.get("geometry") or {}
    rows = {pid: _panel_rows(columns, pid) for pid, _ in panels}
    extents = [funnel_extent(geometries[pid]) for pid, _ in panels]
    widths = [2 * w for w, _ in extents]
    height = max(np.subtract(*funnel_ylim(geometries[pid])[::-1]) for pid, _ in panels)
    zooms = [(pid, zoom_window(rows[pid])) for pid, _ in panels]
    zooms = [(pid, window) for pid, window in zooms if window]
    fig_w = 7.0
    # Axes of equal aspect: their height follows from the width left after labels and gaps.
    top = min(9.0, (fig_w - 0.6 - 0.75 * len(panels)) * height / sum(widths))
    zoom_heights = []
    for pid, window in zooms:
        x0, x1, y0, y1 = zoom_limits(geometries[pid], rows[pid], window)
        zoom_heights.append(min(1.5, max(0.8, (fig_w - 1.6) * (y1 - y0) / (x1 - x0))))
    ids = [pid for pid, _ in panels]
    fig = _new_figure(fig_w, top + 0.75 + sum(h + 0.9 for h in zoom_heights))
    # Sub-figures: the zoom rows span the width without constraining the panels' colour bars.
    rows_h = [top + 0.75] + [h + 0.9 for h in zoom_heights]
    subs = fig.subfigures(len(rows_h), 1, height_ratios=rows_h, squeeze=False)[:, 0]
    axes = dict(zip(ids, subs[0].subplots(1, len(ids), squeeze=False, gridspec_kw={"width_ratios": widths})[0]))
    for sub, (pid, _) in zip(subs[1:], zooms):
        axes[f"zoom_{pid}"] = sub.subplots()
    for (pid, plabel), (w, _) in zip(panels, extents):
        ax = axes[pid]
        g = dict(geometries[pid])
        events = rows[pid]
        draw_funnel(ax, g)
        t_end = float(np.max(events["time"])) if len(events["time"]) else 1.0
        lines = draw_path(ax, g, events, Normalize(0.0, t_end), lw=0.3 if len(events["time"]) > 100 else 0.5)
        if len(events["time"]):
            bar = fig.colorbar(lines, ax=ax, shrink=0.7, aspect=25, pad=0.02)
            bar.set_label(r"$t$ [$\sqrt{H/g}$]")
            bar.outline.set_linewidth(0.5)
            x0, y0, *_ = motion.release_state(g, events)
            ax.plot(x0, y0, "o", ms=3, color=RELEASE_COLOR, zorder=4)
        ax.set_aspect("equal")
        ax.set_anchor("E")  # next to its colour bar; any spare width goes to the left
        ax.set_xlim(-w, w)
        ax.set_ylim(*funnel_ylim(g))
        ax.set_xlabel(r"$x/H$")
        _panel_title(ax, pid if len(panels) > 1 else "", plabel)
    axes[ids[0]].set_ylabel(r"$y/H$")
    letters = [chr(ord(max(ids)) + 1 + i) if len(max(ids)) == 1 else "" for i in range(len(zooms))]
    for (pid, window), letter in zip(zooms, letters):
        ax = axes[f"zoom_{pid}"]
        draw_zoom(ax, dict(geometries[pid]), rows[pid], window, main_ax=axes[pid])
        ax.set_ylabel(r"$y/H$")
        _panel_title(ax, letter, f"zoom on the box in ({pid}): the particle bounces left-right-left on nearly the "
                     "same arch, a little lower each time")
    return fig


def simulate_for_plot(release, **model):
    """(result, geometry) of funnel.simulate(release, events=True, **model), the geometry with
    the release x0/L and the result's release state x0, y0, u0, v0, omega0 added (what
    plot_trajectory, funnel.animate and funnel.motion take: the first flight starts where and
    as the engine's did)."""
    import funnel
    result = funnel.simulate(release=release, events=True, **model)
    shape = model.pop("geometry", None)
    geometry = dict(funnel.geometry(geometry=shape, **model), release=float(release))
    geometry.update({key: result[key] for key in motion.RELEASE_STATE})
    return result, geometry


def add_model_arguments(parser):
    """The model options of the command line (--theta, --e, ...) and --release."""
    import funnel
    parser.add_argument("--release", type=float, required=True, help="release position x0/L, -1 < x0/L < 1")
    defaults = funnel.default_params()
    for name in funnel.MODEL_PARAMETERS:
        # An unset wall angle is theta's (default_params shows theta's default value there).
        default = "default: theta" if name in ("theta_left", "theta_right") else f"default {defaults[name]:g}"
        parser.add_argument(f"--{name.replace('_', '-')}", dest=name, type=float, default=None,
                            help=f"{funnel.valid_range(name)} ({default})")
    parser.add_argument("--geometry", default=None,
                        help="the funnel's walls from a geometry TOML file (docs/cli.md, 'Geometry files')")


def model_arguments(args):
    """The model keywords given on the command line."""
    import funnel
    model = {name: getattr(args, name) for name in funnel.MODEL_PARAMETERS if getattr(args, name) is not None}
    if getattr(args, "geometry", None):
        model["geometry"] = args.geometry
    return model


def save_figure(fig, out):
    """Writes fig to out (.png, .svg or .pdf) through a temporary file (never a partial file)."""
    import matplotlib
    from .plot import STYLE
    from ._files import replacing
    out = Path(out)
    with matplotlib.rc_context(STYLE), replacing(out) as tmp:
        fig.savefig(tmp, format=out.suffix.lstrip(".").lower() or None,
                    metadata={"Software": None} if out.suffix == ".png" else None)


def nothing_to_draw(result):
    """ValueError naming t_max when the run logged no event: t_max ended its first flight, and
    the pictures are drawn from the event log (a traceback before)."""
    if not len(result["events"]["time"]):
        t_max = float(result["params"]["t_max"])
        raise ValueError(f"invalid t-max = {t_max:g}: the run ends before its first collision, with nothing to draw; "
                         "valid range is a t-max beyond the first flight")


def main(argv=None, prog="python -m funnel.trajectory"):
    """Command line: simulate one trajectory and draw it into --out."""
    from ._files import OneLineParser
    import matplotlib
    from .plot import STYLE
    parser = OneLineParser(prog=prog, description=(
        "Simulate one trajectory (funnel.simulate) and draw it: the funnel, the centre's path coloured by "
        "time and the collision points, with a zoom on the bounces when the particle settles into them."))
    add_model_arguments(parser)
    parser.add_argument("--out", required=True, help="image file: .png, .svg or .pdf")
    args = parser.parse_args(argv)
    if Path(args.out).suffix.lower() not in (".png", ".svg", ".pdf"):
        parser.error(f"invalid out = '{args.out}': the file name must end in .png, .svg or .pdf")
    from ._files import check_output
    try:
        check_output(args.out)  # before the simulation, not after it
    except ValueError as error:
        parser.error(str(error))
    try:
        result, geometry = simulate_for_plot(args.release, **model_arguments(args))
        nothing_to_draw(result)
    except ValueError as error:
        parser.error(str(error))
    with matplotlib.rc_context(STYLE):
        fig = plot_trajectory(result, geometry)
    save_figure(fig, args.out)
    print(f"funnel.trajectory: wrote {args.out} ({result['status']}, {result['collisions']} collisions, "
          f"duration {result['duration']:.4g})", file=sys.stderr)
    return 0


if __name__ == "__main__":
    try:
        sys.exit(main())
    except KeyboardInterrupt:  # Ctrl-C: one line and the shell's status, not a traceback (no file is left)
        print("python -m funnel.trajectory: interrupted", file=sys.stderr)
        sys.exit(130)
