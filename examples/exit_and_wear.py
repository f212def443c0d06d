"""Example: a designer's questions — how fast do particles leave, and where do the walls wear?

    PYTHONPATH=build/python /usr/bin/python3 examples/exit_and_wear.py [OUTDIR]

For a few wall angles, one ensemble of 400 releases each (e = 0.99, mu = 1, the paper's material)
with a wear record of 20 bins per wall. Prints the mean exit speed and the spread of the exit
direction, and how much of the faces' normal impulse (edges left out) lands on their lowest
fifth. Writes OUTDIR/exit_wear.csv (one row per angle) and OUTDIR/exit_wear.png (exit speed
against the angle, and the wear profile along the wall).
"""

import csv
import sys
from pathlib import Path

import numpy as np
from matplotlib.figure import Figure

import funnel

outdir = Path(sys.argv[1] if len(sys.argv) > 1 else ".")
outdir.mkdir(parents=True, exist_ok=True)

thetas = [30, 44, 46, 60]
rows = []
profiles = {}
for theta in thetas:
    r = funnel.ensemble(theta=theta, samples=400, wear_bins=20)
    wear = r["wear"]
    per_bin = 0.5 * (wear["left"]["normal_impulse"] + wear["right"]["normal_impulse"])  # symmetric funnel
    height = wear["left"]["s"] * np.sin(np.radians(theta))  # height of each bin above the funnel bottom
    low = per_bin[height < 0.2].sum() / per_bin.sum()
    profiles[theta] = (height, per_bin / wear["left"]["bin_width"])
    rows.append({"theta": theta, "exit_speed_mean": r["exit_speed"]["mean"], "exit_speed_sem": r["exit_speed"]["sem"],
                 "exit_angle_std": r["exit_angle"]["std"], "impulse_mean": r["impulse"]["mean"],
                 "lowest_fifth_share": low})
    print(f"theta = {theta:2d}°: exit speed {r['exit_speed']['mean']:.3f} ± {r['exit_speed']['sem']:.3f} sqrt(gH), "
          f"exit direction spread {r['exit_angle']['std']:.1f}°, impulse on the walls {r['impulse']['mean']:.1f} "
          f"(edges included), {100 * low:.0f}% of the faces' normal impulse on their lowest fifth")

with open(outdir / "exit_wear.csv", "w", newline="") as f:
    writer = csv.DictWriter(f, fieldnames=list(rows[0]))
    writer.writeheader()
    writer.writerows(rows)
print(f"wrote {outdir / 'exit_wear.csv'}")

fig = Figure(figsize=(7.5, 3.2), layout="constrained")
left, right = fig.subplots(1, 2)
left.errorbar([r["theta"] for r in rows], [r["exit_speed_mean"] for r in rows],
              yerr=[r["exit_speed_sem"] for r in rows], marker="o", ms=3, capsize=2)
left.axvline(45, color="0.5", ls="--", lw=0.8)
left.set_xlabel("θ [deg]")
left.set_ylabel("mean exit speed [√(gH)]")
for theta, (height, density) in profiles.items():
    right.plot(density, height, label=f"θ = {theta}°")
right.set_xscale("log")
right.set_xlabel("normal impulse per length [m√(gH)/H]")
right.set_ylabel("height above the funnel bottom [H]")
right.legend()
fig.savefig(outdir / "exit_wear.png", dpi=150)
print(f"wrote {outdir / 'exit_wear.png'}")
