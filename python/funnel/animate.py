"""An animation of one trajectory: ``python -m funnel.animate --theta 60 --release 0.3 --out traj.gif``.

The trajectory is simulated with :func:`funnel.simulate` (events=True) and drawn frame by frame
at uniform steps of simulated time: on the left the funnel with the path so far and the ball; on
the right a close-up that follows the ball (drawn to scale, radius a) with its spin shown as a
diameter and a dot. Positions and spin angles come from :func:`funnel.motion.state_at`: in flight
the exact parabola and an angle advancing by ω·dt, during contacts an interpolation between the
logged ends. A GIF is written with Pillow, an MP4 with ffmpeg when it is installed (else the
command says so and exits with status 2). matplotlib is imported only when drawing.
"""

from __future__ import annotations

import math
import shutil
import sys
from pathlib import Path

import numpy as np

from . import motion
from . import trajectory as tr

#: Close-up half-width in ball radii.
CLOSE_UP = 5.0


MAX_FRAMES = 20_000  # 16 min at 20 fps


def frame_times(t_end, t_start=0.0, speed=None, fps=20, max_seconds=15.0):
    """Simulated times of the frames: from t_start to t_end at `speed` (simulated time per second
    of video; by default the whole interval in at most max_seconds), `fps` frames per second."""
    span = max(0.0, t_end - t_start)
    if speed is None:
        speed = max(span / max_seconds, 1e-12)
    frames = span / speed * fps
    if not frames <= MAX_FRAMES:
        # A slow speed over a long interval asked for millions of frames (hours, or an
        # allocation of petabytes at 1e-12).
        raise ValueError(f"invalid speed = {speed:g}: {frames:.3g} frames; valid range is at most {MAX_FRAMES} "
                         f"frames (speed >= {span * fps / MAX_FRAMES:.3g} for this interval, or a shorter "
                         "--t-start/--t-end window)")
    count = max(2, int(math.ceil(frames)) + 1)
    return np.linspace(t_start, t_start + span, count), speed


def spin_step(geometry, events, times):
    """Largest turn of the ball between two frames [rad]: above about pi/2 the spin cannot be
    seen (a stroboscope effect)."""
    _, _, phi = motion.state_at(geometry, events, times)
    return float(np.max(np.abs(np.diff(phi)))) if len(phi) > 1 else 0.0


class _Ball:
    """The ball and its spin marker on one axes."""

    def __init__(self, ax, radius):
        from matplotlib.patches import Circle
        self.radius = radius
        self.circle = Circle((0, 0), radius, fc="#F0C8A0", ec="#D55E00", lw=1.0, zorder=6)
        ax.add_patch(self.circle)
        (self.line,) = ax.plot([], [], color="#7A2E00", lw=1.4, zorder=7, solid_capstyle="round")
        (self.dot,) = ax.plot([], [], "o", color="#7A2E00", ms=2.5, zorder=7)

    def move(self, x, y, phi):
        c, s = math.cos(phi), math.sin(phi)
        r = self.radius
        self.circle.center = (x, y)
        self.line.set_data([x - r * c, x + r * c], [y - r * s, y + r * s])
        self.dot.set_data([x + 0.7 * r * c], [y + 0.7 * r * s])
        return self.circle, self.line, self.dot


def build_animation(result, geometry, times):
    """(Figure, update function) drawing the trajectory at `times`; update(i) draws frame i.
    geometry: funnel.geometry(...) with "release" added (see funnel.trajectory.release_geometry)."""
    from matplotlib.figure import Figure
    g = tr.release_geometry(result, geometry)
    events = result["events"]
    x, y, phi = motion.state_at(g, events, times)
    px, py, pt = motion.trajectory_path(g, events)
    fig = Figure(figsize=(7.2, 3.9), dpi=100)
    fig.subplots_adjust(left=0.07, right=0.98, bottom=0.12, top=0.9, wspace=0.18)
    ax, close = fig.subplots(1, 2, gridspec_kw={"width_ratios": [1.6, 1.0]})
    for a in (ax, close):
        tr.draw_funnel(a, g)
        a.plot(px, py, color="0.82", lw=0.4, zorder=1)
        a.set_aspect("equal")
    w, _ = tr.funnel_extent(g)
    ax.set_xlim(-w, w)
    ax.set_ylim(*tr.funnel_ylim(g))
    ax.set_xlabel(r"$x/H$")
    ax.set_ylabel(r"$y/H$")
    radius = float(g.get("radius", 0.01))
    close.set_xticks([])
    close.set_yticks([])
    close.set_title(f"close-up, {2 * CLOSE_UP * radius:.2g} H wide (ball to scale)", fontsize=8)
    (trail,) = ax.plot([], [], color="#0072B2", lw=0.3, alpha=0.6, zorder=3)
    (recent_main,) = ax.plot([], [], color="#0072B2", lw=1.3, zorder=4)
    (trail_close,) = close.plot([], [], color="#0072B2", lw=1.2, zorder=3)
    event_times = np.asarray(events["time"], dtype=float)
    # On the overview the ball is drawn at least 0.6% of the funnel's width across.
    big = _Ball(ax, max(radius, 0.012 * w))
    small = _Ball(close, radius)
    title = ax.set_title("", loc="left", fontsize=8)
    label = rf"{tr.funnel_label(result, g)}, $x_0/L$ = {float(g['release']):g}"

    def update(i):
        t = times[i]
        m = pt <= t
        trail.set_data(np.append(px[m], x[i]), np.append(py[m], y[i]))
        # The last three flights, bold.
        k = int(np.searchsorted(event_times, t))
        recent = m & (pt >= (event_times[k - 3] if k >= 3 else 0.0))
        for line in (recent_main, trail_close):
            line.set_data(np.append(px[recent], x[i]), np.append(py[recent], y[i]))
        close.set_xlim(x[i] - CLOSE_UP * radius, x[i] + CLOSE_UP * radius)
        close.set_ylim(y[i] - CLOSE_UP * radius, y[i] + CLOSE_UP * radius)
        title.set_text(rf"{label}:  $t$ = {t:8.3f} $\sqrt{{H/g}}$")
        return (trail, recent_main, trail_close, title, *big.move(x[i], y[i], phi[i]), *small.move(x[i], y[i], phi[i]))

    return fig, update


def writer_for(path, fps):
    """A matplotlib animation writer for the file's suffix; ValueError (with what to do) when
    the format cannot be written here."""
    from matplotlib import animation
    suffix = Path(path).suffix.lower()
    if suffix == ".gif":
        try:
            import PIL  # noqa: F401  (Pillow writes the GIF)
        except ImportError:
            raise ValueError("cannot write a GIF: Pillow is not installed (Debian: apt-get install python3-pil)")
        return animation.PillowWriter(fps=fps)
    if suffix == ".mp4":
        if shutil.which("ffmpeg") is None:
            raise ValueError(f"cannot write '{path}': ffmpeg is not installed (Debian: apt-get install ffmpeg); "
                             "write a .gif instead")
        return animation.FFMpegWriter(fps=fps, codec="libx264", extra_args=["-pix_fmt", "yuv420p"])
    raise ValueError(f"invalid out = '{path}': the file name must end in .gif or .mp4")


def animate(result, geometry, out, t_start=0.0, t_end=None, speed=None, fps=20, dpi=100):
    """Writes the animation of a simulated trajectory (funnel.simulate(..., events=True)) to
    out (.gif or .mp4); returns (frames, speed, largest spin turn per frame [rad])."""
    import matplotlib
    from matplotlib import animation
    from .plot import STYLE
    geometry = tr.release_geometry(result, geometry)  # the release state, and a clear error for a bad result
    events = result["events"]
    last = float(events["time"][-1]) if len(events["time"]) else 0.0
    t_end = last if t_end is None else min(float(t_end), last)
    times, speed = frame_times(t_end, t_start, speed, fps)
    writer = writer_for(out, fps)
    from ._files import replacing
    out = Path(out)
    with matplotlib.rc_context(STYLE), replacing(out) as tmp:  # never a partial file, nor a stray temporary
        fig, update = build_animation(result, geometry, times)
        movie = animation.FuncAnimation(fig, update, frames=len(times), blit=False)
        movie.save(str(tmp), writer=writer, dpi=dpi)
    return len(times), speed, spin_step(geometry, events, times)


def main(argv=None):
    """Command line: simulate one trajectory and animate it into --out."""
    from ._files import OneLineParser
    parser = OneLineParser(prog="python -m funnel.animate", description=(
        "Simulate one trajectory (funnel.simulate) and write an animation: the funnel with the path so far, "
        "and a close-up following the ball with its spin. GIF through Pillow; MP4 when ffmpeg is installed."))
    tr.add_model_arguments(parser)
    parser.add_argument("--out", required=True, help="animation file: .gif, or .mp4 (needs ffmpeg)")
    parser.add_argument("--t-start", type=float, default=0.0, help="first frame's time, sqrt(H/g) (default 0)")
    parser.add_argument("--t-end", type=float, default=None, help="last frame's time (default: the end)")
    parser.add_argument("--speed", type=float, default=None,
                        help="simulated time per second of video, > 0 (default: the interval in 15 s)")
    parser.add_argument("--fps", type=int, default=20, help="frames per second, 1 to 60 (default 20)")
    args = parser.parse_args(argv)
    if not 1 <= args.fps <= 60:
        parser.error(f"invalid fps = {args.fps}: valid range is 1 <= fps <= 60")
    if args.speed is not None and not (args.speed > 0 and math.isfinite(args.speed)):
        parser.error(f"invalid speed = {args.speed}: valid range is speed > 0")
    if not (args.t_start >= 0 and math.isfinite(args.t_start)):
        parser.error(f"invalid t-start = {args.t_start}: valid range is t-start >= 0")
    if args.t_end is not None and not args.t_end > args.t_start:
        parser.error(f"invalid t-end = {args.t_end}: valid range is t-end > t-start ({args.t_start:g})")
    try:
        writer_for(args.out, args.fps)
        from ._files import check_output
        check_output(args.out)  # before the simulation, not after it
        result, geometry = tr.simulate_for_plot(args.release, **tr.model_arguments(args))
        tr.nothing_to_draw(result)
    except ValueError as error:
        parser.error(str(error))
    if args.t_start >= float(result["duration"]):
        parser.error(f"invalid t-start = {args.t_start:g}: the trajectory ends at t = {result['duration']:.6g}")
    last = float(result["events"]["time"][-1]) if len(result["events"]["time"]) else 0.0
    try:
        frame_times(last if args.t_end is None else min(args.t_end, last), args.t_start, args.speed, args.fps)
    except ValueError as error:
        parser.error(str(error))
    frames, speed, turn = animate(result, geometry, args.out, args.t_start, args.t_end, args.speed, args.fps)
    if args.t_end is not None and args.t_end > last:
        print(f"funnel.animate: note: the trajectory ends at t = {last:.6g}, before --t-end {args.t_end:g}; "
              "the animation ends there", file=sys.stderr)
    print(f"funnel.animate: wrote {args.out} ({frames} frames at {args.fps} fps, {speed:.3g} sqrt(H/g) per second)",
          file=sys.stderr)
    if turn > math.pi / 2:
        print(f"funnel.animate: note: the spin turns up to {turn:.3g} rad between frames, too fast to see; "
              f"for a visible spin use --speed {0.5 * math.pi / turn * speed:.2g} or less with --t-start/--t-end",
              file=sys.stderr)
    return 0


if __name__ == "__main__":
    try:
        sys.exit(main())
    except KeyboardInterrupt:  # Ctrl-C: one line and the shell's status, not a traceback (no file is left)
        print("python -m funnel.animate: interrupted", file=sys.stderr)
        sys.exit(130)
