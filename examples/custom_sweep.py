"""Example: a custom parameter sweep, saved as CSV and plotted.

    PYTHONPATH=build/python /usr/bin/python3 examples/custom_sweep.py [OUTDIR]

How does the jump of the mean duration at θ = 45° depend on friction? One ensemble of 400
release positions per (θ, μ) on a grid around 45°, through funnel.sweep (the same numbers as
`funnel sweep --theta 40:50:1 --mu 0.05,0.2,1 --samples 400 --out sweep.csv`, though written as
Python writes them: 40.0 for 40, 100000.0 for 1e+05). Writes OUTDIR/sweep.csv (the columns of
`funnel sweep`) and OUTDIR/sweep.png.
"""

import csv
import sys
from pathlib import Path

import numpy as np
from matplotlib.figure import Figure

import funnel

outdir = Path(sys.argv[1] if len(sys.argv) > 1 else ".")
outdir.mkdir(parents=True, exist_ok=True)

mus = [0.05, 0.2, 1.0]
table = funnel.sweep(theta="40:50:1", mu=mus, samples=400)  # one 1-D array per column

with open(outdir / "sweep.csv", "w", newline="") as f:
    writer = csv.writer(f, lineterminator="\n")  # Unix lines, as funnel sweep writes them
    writer.writerow(table)
    writer.writerows(zip(*(values.tolist() for values in table.values())))
print(f"wrote {outdir / 'sweep.csv'} ({len(table['theta'])} grid points)")

fig = Figure(figsize=(4.5, 3.2), layout="constrained")
ax = fig.subplots()
for mu in mus:
    row = table["mu"] == mu
    theta, mean, sem = table["theta"][row], table["duration_mean"][row], table["duration_sem"][row]
    ax.errorbar(theta, mean, yerr=sem, marker="o", ms=3, capsize=2, label=f"μ = {mu:g}")
    ratio = mean[theta == 46][0] / mean[theta == 44][0]
    print(f"mu = {mu:g}: mean duration at 46° / 44° = {ratio:.2f}")
ax.axvline(45, color="0.5", ls="--", lw=0.8)
ax.set_xlabel("θ [deg]")
ax.set_ylabel("mean duration [√(H/g)]")
ax.legend()
fig.savefig(outdir / "sweep.png", dpi=150)
print(f"wrote {outdir / 'sweep.png'}")
