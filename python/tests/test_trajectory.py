"""Pictures and animations of single trajectories: funnel.trajectory, funnel.animate, and the
zoom panel of Fig. 8 built from a real simulation."""

import math
import shutil
from pathlib import Path

import matplotlib
import numpy as np
import pytest

import funnel
from funnel import animate, motion, plot, trajectory

PNG_MAGIC = b"\x89PNG\r\n\x1a\n"


@pytest.fixture(scope="module")
def bouncing():
    """The trajectory of the paper's Fig. 8(a): it settles into bouncing between the walls."""
    return trajectory.simulate_for_plot(0.3, theta=60.0)


def test_plot_trajectory_command(tmp_path, capsys):
    out = tmp_path / "traj.png"
    assert plot.main(["trajectory", "--theta", "60", "--release", "0.3", "--e", "0.99", "--out", str(out)]) == 0
    assert out.read_bytes()[:8] == PNG_MAGIC and out.stat().st_size > 20_000
    assert "342 collisions" in capsys.readouterr().err
    assert [p.name for p in tmp_path.iterdir()] == ["traj.png"]  # no temporary file left


@pytest.mark.parametrize("args,message", [
    (["--theta", "95", "--release", "0.3", "--out", "x.png"], "invalid theta = 95"),
    (["--release", "1.5", "--out", "x.png"], "release"),
    (["--release", "0.3", "--out", "x.txt"], "x.txt': the file name must end in .png, .svg or .pdf"),
])
def test_plot_trajectory_command_rejects_bad_input(tmp_path, capsys, args, message):
    with pytest.raises(SystemExit) as exit_info:
        trajectory.main([*args[:-1], str(tmp_path / args[-1])])
    assert exit_info.value.code == 2
    assert message in capsys.readouterr().err
    assert not list(tmp_path.iterdir())


def test_trajectory_figure_shows_every_collision_and_zooms_on_the_bounces(bouncing):
    result, geometry = bouncing
    with matplotlib.rc_context(plot.STYLE):
        fig = trajectory.plot_trajectory(result, geometry)
    main, zoom = fig.axes[0], fig.axes[1]
    points = np.concatenate([c.get_offsets() for c in main.collections if c.get_offsets().shape[1:] == (2,)
                             and len(c.get_offsets()) > 1])
    cx, cy, _ = motion.collision_points(result["events"])
    assert len(points) == result["collisions"] == len(cx)
    # The zoom shows four consecutive bounces of the alternating run, whole, with equal scales.
    first, last = trajectory.zoom_window(result["events"])
    assert last - first == trajectory.ZOOM_COLLISIONS
    assert set(result["events"]["wall"][first:last + 1]) == {"left", "right"}
    px, py, _ = motion.trajectory_path(geometry, result["events"], window=(first, last))
    (x0, x1), (y0, y1) = zoom.get_xlim(), zoom.get_ylim()
    assert x0 < px.min() and px.max() < x1 and y0 < py.min() and py.max() < y1
    assert zoom.get_aspect() == 1.0
    assert any(p.get_width() == pytest.approx(x1 - x0) for p in main.patches)  # the zoomed box


def test_no_zoom_without_a_repeating_pattern():
    result, geometry = trajectory.simulate_for_plot(0.3, theta=40.0)
    assert trajectory.zoom_window(result["events"]) is None
    with matplotlib.rc_context(plot.STYLE):
        fig = trajectory.plot_trajectory(result, geometry)
    assert len([ax for ax in fig.axes if ax.get_label() != "<colorbar>"]) == 1


def test_sustained_contact_is_drawn_on_the_face():
    result, geometry = trajectory.simulate_for_plot(0.5, theta=30.0, e=0.3)
    with matplotlib.rc_context(plot.STYLE):
        fig = trajectory.plot_trajectory(result, geometry)
    contact = [line for line in fig.axes[0].get_lines() if line.get_color() == trajectory.CONTACT_COLOR
               and len(line.get_xdata()) > 1]
    assert len(contact) == result["contacts"] == 1
    x, y = contact[0].get_data()
    s, c = math.sin(math.radians(30.0)), math.cos(math.radians(30.0))
    np.testing.assert_allclose(np.asarray(x) * s - np.asarray(y) * c, 0.0, atol=1e-12)


def test_fig08_from_real_data_has_a_zoom_panel_for_the_bouncing_trajectory():
    rows, geometries = [], {}
    header = None
    for pid, theta in (("a", 60.0), ("b", 40.0)):
        result, g = trajectory.simulate_for_plot(0.3, theta=theta)
        geometries[pid] = g
        ev = result["events"]
        header = list(ev)
        rows.append({"panel": np.full(len(ev["time"]), pid), **ev})
    columns = {name: np.concatenate([r[name] for r in rows]) for name in ["panel", *header]}
    meta = {"kind": "trajectories", "panels": [{"id": "a", "label": "θ = 60°"}, {"id": "b", "label": "θ = 40°"}],
            "geometry": geometries}
    fig = plot.plot_figure(meta, columns)
    titles = [ax.get_title(loc="left") for ax in fig.axes]
    assert sum(t.startswith("(c)  zoom on the box in (a)") for t in titles) == 1
    assert not any("in (b)" in t for t in titles)


# ---------------------------------------------------------------------------------------------
# Animation

def test_frame_times():
    times, speed = animate.frame_times(10.0, 2.0, speed=4.0, fps=5)
    assert speed == 4.0 and times[0] == 2.0 and times[-1] == 10.0 and len(times) == 11
    times, speed = animate.frame_times(30.0, fps=20)  # whole interval in 15 s
    assert speed == 2.0 and len(times) == 301


def test_animation_frames_follow_the_motion_and_show_the_spin(bouncing):
    result, geometry = bouncing
    ev = result["events"]
    times = np.linspace(1.5, 2.5, 9)  # early bounces, when the ball spins fast
    fig, update = animate.build_animation(result, geometry, times)
    x, y, phi = motion.state_at(geometry, ev, times)
    assert np.ptp(phi) > 1.0  # the ball turns
    for i in range(len(times)):
        artists = update(i)
        circles = [a for a in artists if hasattr(a, "center")]
        assert all(c.center == pytest.approx((x[i], y[i]), abs=1e-15) for c in circles)
        dots = [a for a in artists if getattr(a, "get_marker", lambda: None)() == "o"]
        for dot, circle in zip(dots, circles):
            dx, dy = dot.get_xdata()[0] - x[i], dot.get_ydata()[0] - y[i]
            assert math.atan2(dy, dx) == pytest.approx(math.remainder(phi[i], 2 * math.pi), abs=1e-9)
            assert math.hypot(dx, dy) == pytest.approx(0.7 * circle.radius, rel=1e-12)


def test_animate_writes_a_gif(tmp_path, bouncing):
    from PIL import Image
    result, geometry = bouncing
    out = tmp_path / "traj.gif"
    frames, speed, turn = animate.animate(result, geometry, out, t_start=77.0, t_end=77.5, speed=0.5, fps=4)
    assert frames == 5 and speed == 0.5 and 0 < turn < math.pi
    with Image.open(out) as gif:
        assert gif.n_frames == frames
        first = np.asarray(gif.convert("RGB"), dtype=int)
        gif.seek(frames - 1)
        last = np.asarray(gif.convert("RGB"), dtype=int)
    assert np.mean(np.any(first != last, axis=-1)) > 0.001  # the ball moved
    assert [p.name for p in tmp_path.iterdir()] == ["traj.gif"]


def test_animate_command_errors(tmp_path, capsys):
    with pytest.raises(SystemExit) as exit_info:
        animate.main(["--release", "0.3", "--out", str(tmp_path / "a.avi")])
    assert exit_info.value.code == 2 and "must end in .gif or .mp4" in capsys.readouterr().err
    with pytest.raises(SystemExit):
        animate.main(["--release", "0.3", "--fps", "0", "--out", str(tmp_path / "a.gif")])
    assert "invalid fps = 0" in capsys.readouterr().err
    if shutil.which("ffmpeg") is None:
        with pytest.raises(SystemExit):
            animate.main(["--release", "0.3", "--out", str(tmp_path / "a.mp4")])
        assert "ffmpeg is not installed" in capsys.readouterr().err
    assert not list(tmp_path.iterdir())


def test_animate_says_when_the_trajectory_ends_before_t_end(tmp_path, capsys):
    out = tmp_path / "short.gif"
    assert animate.main(["--release", "0.3", "--theta", "30", "--t-start", "0.9", "--t-end", "1e6", "--fps", "1",
                         "--speed", "2", "--out", str(out)]) == 0
    err = capsys.readouterr().err
    duration = funnel.simulate(release=0.3, theta=30)["duration"]
    assert f"the trajectory ends at t = {duration:.6g}, before --t-end 1e+06" in err and out.exists()


def test_model_options_match_the_library():
    import argparse
    parser = argparse.ArgumentParser()
    trajectory.add_model_arguments(parser)
    args = parser.parse_args(["--release", "0.3", "--theta", "50", "--max-collisions", "7"])
    assert trajectory.model_arguments(args) == {"theta": 50.0, "max_collisions": 7.0}
    assert set(funnel.MODEL_PARAMETERS) <= set(vars(args))


def test_bad_outputs_are_refused_before_the_work_and_leave_no_temporary(tmp_path, capsys):
    # A missing directory was found only after the simulation (a traceback, exit 1); a directory
    # as the target left the finished temporary picture beside it.
    (tmp_path / "isdir.png").mkdir()
    (tmp_path / "isdir.gif").mkdir()
    for main, out in ((trajectory.main, "nodir/x.png"), (trajectory.main, "isdir.png"),
                      (animate.main, "nodir/x.gif"), (animate.main, "isdir.gif")):
        with pytest.raises(SystemExit) as exit_:
            main(["--release", "0.3", "--out", str(tmp_path / out)])
        assert exit_.value.code == 2
        assert "invalid out" in capsys.readouterr().err
    assert sorted(p.name for p in tmp_path.iterdir()) == ["isdir.gif", "isdir.png"]
    assert not any((tmp_path / "isdir.png").iterdir())
    # Too slow an animation is refused before drawing (2.4 million frames, or petabytes at 1e-12).
    with pytest.raises(SystemExit) as exit_:
        animate.main(["--release", "0.3", "--speed", "1e-12", "--out", str(tmp_path / "slow.gif")])
    assert exit_.value.code == 2 and "frames; valid range is at most" in capsys.readouterr().err


def test_a_failed_save_removes_its_temporary(tmp_path):
    import matplotlib.pyplot as plt

    from funnel._files import replacing
    fig = plt.figure()
    with pytest.raises(RuntimeError):
        with replacing(tmp_path / "x.png") as tmp:
            fig.savefig(tmp, format="png")
            raise RuntimeError("interrupted while writing")
    plt.close(fig)
    assert list(tmp_path.iterdir()) == []
    with pytest.raises(ValueError, match="is a directory; valid values are a file path"):
        with replacing(tmp_path):
            pass


LINED = str(Path(__file__).resolve().parents[2] / "examples" / "geometry" / "lined.toml")


def _release_dot(ax):
    (dot,) = [line for line in ax.get_lines() if line.get_marker() == "o" and len(line.get_xdata()) == 1
              and line.get_color() == trajectory.RELEASE_COLOR]
    return dot.get_xdata()[0], dot.get_ydata()[0]


@pytest.mark.parametrize("model,label", [
    ({"theta_left": 50.0}, r"$\theta_\mathrm{left}$ = 50°, $\theta_\mathrm{right}$ = 60°, $x_0/L$ = 0.3"),
    # Both walls' angles: params' theta is None (a TypeError in the title before).
    ({"theta_left": 50.0, "theta_right": 55.0}, r"$\theta_\mathrm{left}$ = 50°, $\theta_\mathrm{right}$ = 55°, $x_0/L$ = 0.3"),
    ({"geometry": LINED}, "lined.toml, $x_0/L$ = 0.3"),
    ({"theta": 45.0, "release_u": 0.5, "release_v": 0.3, "release_spin": 2.0}, r"$\theta$ = 45°, $x_0/L$ = 0.3"),
], ids=["asymmetric", "both-walls", "geometry-file", "velocity"])
def test_pictures_and_animations_start_at_the_release_and_name_the_funnel(model, label):
    # The release was drawn at release * half_width (off the release point of an asymmetric V
    # or a geometry file), the first flight as a fall from rest, and the title gave the V's
    # theta = 60° for a geometry file, one angle for an asymmetric V.
    result, geometry = trajectory.simulate_for_plot(0.3, **model)
    ev = result["events"]
    with matplotlib.rc_context(plot.STYLE):
        fig = trajectory.plot_trajectory(result, geometry)
    ax = fig.axes[0]
    assert _release_dot(ax) == (result["x0"], result["y0"])
    assert ax.get_title(loc="left").startswith(label + ":")
    # The drawn path is continuous: its first flight runs from the release to the first event.
    arcs = [c for c in ax.collections if c.get_array() is not None and len(c.get_paths()) == len(ev["time"])]
    first = arcs[0].get_paths()[0].vertices
    assert tuple(first[0]) == (result["x0"], result["y0"])
    assert tuple(first[-1]) == pytest.approx((ev["x"][0], ev["y"][0]), abs=1e-12)
    times = np.array([0.0, ev["time"][0]])
    fig, update = animate.build_animation(result, geometry, times)
    artists = update(1)
    center = [a for a in artists if hasattr(a, "center")][0].center
    assert center == pytest.approx((ev["x"][0], ev["y"][0]), abs=1e-12)
    assert fig.axes[0].get_title(loc="left").startswith(label + ":")
    # Given funnel.geometry(...) and "release" only, the result's own release state is used.
    bare = {key: value for key, value in geometry.items() if key not in motion.RELEASE_STATE}
    with matplotlib.rc_context(plot.STYLE):
        assert _release_dot(trajectory.plot_trajectory(result, bare).axes[0]) == (result["x0"], result["y0"])


def test_bad_results_and_geometries_are_value_errors(tmp_path):
    # KeyErrors ('wall', 'events', 'release'), or a 3D run drawn as if it were a plane one.
    result, geometry = trajectory.simulate_for_plot(0.3, theta=40.0)
    g = dict(funnel.geometry(theta=40.0))
    run3 = funnel.simulate(release=0.3, events=True, space="3d")
    cases = [(run3, geometry, r"^invalid result: a run with space = '3d'; valid results are 2D runs"),
             (funnel.simulate(release=0.3, theta=40.0), geometry, r"^invalid result: no 'events'; valid results "
                                                                  r"come from funnel.simulate\(..., events=True\)"),
             ({k: v for k, v in result.items() if k != "release"}, g,
              r"^invalid geometry: no 'release' \(x0/L\), and none in the result")]
    for bad, geo, message in cases:
        for tool in (lambda: trajectory.plot_trajectory(bad, geo),
                     lambda: animate.build_animation(bad, geo, np.array([0.0, 1.0])),
                     lambda: animate.animate(bad, geo, tmp_path / "x.gif")):
            with pytest.raises(ValueError, match=message):
                tool()
    assert not list(tmp_path.iterdir())
    # A geometry without "release" is enough when the result has its own.
    with matplotlib.rc_context(plot.STYLE):
        fig = trajectory.plot_trajectory(result, g)
    assert "$x_0/L$ = 0.3:" in fig.axes[0].get_title(loc="left")


@pytest.mark.parametrize("main", [trajectory.main, animate.main])
def test_help_gives_the_wall_angles_default_as_theta(main, capsys):
    # It said "(default 60)": theta's default, not theta's value.
    with pytest.raises(SystemExit):
        main(["--help"])
    text = " ".join(capsys.readouterr().out.split())
    for side in ("left", "right"):
        assert f"--theta-{side} THETA_{side.upper()} 0 < theta-{side} < 90 (degrees) (default: theta)" in text


def test_a_run_with_no_event_is_refused_naming_t_max(tmp_path):
    # t_max within the first flight: the log is empty, and the pictures broke on it (a traceback).
    import subprocess
    import sys
    for module in (["funnel.plot", "trajectory"], ["funnel.animate"]):
        out = tmp_path / ("a.png" if module[0] == "funnel.plot" else "a.gif")
        run = subprocess.run([sys.executable, "-m", *module, "--release", "0.3", "--t-max", "0.5", "--out", str(out)],
                             capture_output=True, text=True)
        assert run.returncode == 2, run.stderr
        assert "error: invalid t-max = 0.5: the run ends before its first collision" in run.stderr
        assert "Traceback" not in run.stderr and not out.exists()
        # One line and a pointer to --help, not argparse's usage block.
        assert "usage:" not in run.stderr and len(run.stderr.strip().splitlines()) == 2, run.stderr
    result, geometry = trajectory.simulate_for_plot(0.3, t_max=0.5)
    with pytest.raises(ValueError, match="an empty log"):
        trajectory.plot_trajectory(result, geometry)


def test_ctrl_c_stops_an_animation_with_one_line_and_no_file(tmp_path):
    # It printed a 237-line KeyboardInterrupt traceback (no file was left, as now).
    import signal
    import subprocess
    import sys
    import time
    out = tmp_path / "x.gif"
    run = subprocess.Popen([sys.executable, "-m", "funnel.animate", "--release", "0.3", "--fps", "60", "--out", str(out)],
                           stderr=subprocess.PIPE, text=True)
    time.sleep(2.5)  # past the imports (about 0.5 s), within the frames (about 8 s)
    run.send_signal(signal.SIGINT)
    err = run.communicate(timeout=60)[1]
    if run.returncode == 0:
        pytest.skip("the animation was written before the signal")
    assert run.returncode == 130, err
    assert err.strip().splitlines() == ["python -m funnel.animate: interrupted"]
    assert not out.exists() and not list(tmp_path.iterdir())
