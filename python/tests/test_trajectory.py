"""Pictures and animations of single trajectories: funnel.trajectory, funnel.animate, and the
zoom panel of Fig. 8 built from a real simulation."""

import math
import shutil

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
    with pytest.raises(ValueError, match="is a directory"):
        with replacing(tmp_path):
            pass
