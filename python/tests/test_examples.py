"""The scripts in examples/ run and write what they promise (into a temporary directory)."""

import csv
import os
import subprocess
import sys
from pathlib import Path

import numpy as np

EXAMPLES = Path(__file__).resolve().parents[2] / "examples"
PNG_MAGIC = b"\x89PNG\r\n\x1a\n"


def _run(script, outdir):
    env = dict(os.environ, PYTHONPATH=os.pathsep.join(sys.path), MPLBACKEND="Agg")
    proc = subprocess.run([sys.executable, str(EXAMPLES / script), str(outdir)], capture_output=True, text=True,
                          env=env, cwd=outdir, timeout=300)
    assert proc.returncode == 0, proc.stderr
    assert proc.stderr == "", proc.stderr  # no warnings either
    return proc.stdout


def test_trajectory_example(tmp_path):
    out = _run("trajectory_plot.py", tmp_path)
    assert "exited after t = 118 sqrt(H/g) and 342 collisions" in out
    assert "100.0% of consecutive face collisions change wall" in out
    png = tmp_path / "trajectory.png"
    assert png.read_bytes()[:8] == PNG_MAGIC and png.stat().st_size > 20_000
    assert sorted(p.name for p in tmp_path.iterdir()) == ["trajectory.png"]


def test_custom_sweep_example(tmp_path, cli):
    out = _run("custom_sweep.py", tmp_path)
    assert (tmp_path / "sweep.png").read_bytes()[:8] == PNG_MAGIC
    with open(tmp_path / "sweep.csv", newline="") as f:
        rows = list(csv.reader(f))
    header, rows = rows[0], rows[1:]
    assert len(rows) == 33 and header[:3] == ["theta", "e", "mu"]
    # The same numbers as the command line's sweep.
    cli("sweep", "--theta", "40:50:1", "--mu", "0.05,0.2,1", "--samples", 400, "--out", tmp_path / "cli.csv",
        json_output=False)
    with open(tmp_path / "cli.csv", newline="") as f:
        ref = list(csv.reader(f))
    assert ref[0] == header
    for row, ref_row in zip(rows, ref[1:]):
        for name, a, b in zip(header, row, ref_row):
            assert a == b if name == "release_dist" else float(a) == float(b), name
    # The friction dependence of the jump it prints: larger with more friction.
    ratios = [float(line.rsplit("= ", 1)[1]) for line in out.splitlines() if "46° / 44°" in line]
    assert len(ratios) == 3 and np.all(np.diff(ratios) > 0) and ratios[-1] > 2


def test_exit_and_wear_example(tmp_path):
    out = _run("exit_and_wear.py", tmp_path)
    assert (tmp_path / "exit_wear.png").read_bytes()[:8] == PNG_MAGIC
    with open(tmp_path / "exit_wear.csv", newline="") as f:
        rows = {int(float(r["theta"])): r for r in csv.DictReader(f)}
    assert sorted(rows) == [30, 44, 46, 60]
    # The numbers it prints are the library's: the mean exit speed of the 46° ensemble.
    assert float(rows[46]["exit_speed_mean"]) == funnel_exit_speed(46)
    # Above 45° the particle leaves slower (it lost more energy bouncing) and the walls take
    # several times the impulse, most of it low down.
    assert float(rows[46]["exit_speed_mean"]) < float(rows[44]["exit_speed_mean"])
    assert float(rows[46]["impulse_mean"]) > 2 * float(rows[44]["impulse_mean"])
    assert float(rows[46]["lowest_fifth_share"]) > 0.5
    assert "lowest fifth" in out


def funnel_exit_speed(theta):
    import funnel
    return funnel.ensemble(theta=theta, samples=400, wear_bins=20)["exit_speed"]["mean"]


def test_cone_3d_example(tmp_path):
    out = _run("cone_3d.py", tmp_path)
    assert "one ball: trapped at t = 100000 sqrt(H/g) after 1845 collisions" in out
    assert "(it rolls round the outlet for ever)" in out
    assert "sigma = 0.0: mean duration of the balls that leave, 44 deg: 18.6 (0.0% trapped), 46 deg: 62.2" in out
    assert "sigma = 0.03:" in out
    assert (tmp_path / "cone_3d.png").read_bytes()[:8] == PNG_MAGIC
