"""Example: simulate one trajectory, look at its collisions, and draw it.

    PYTHONPATH=build/python /usr/bin/python3 examples/trajectory_plot.py [OUTDIR]

Writes OUTDIR/trajectory.png (default: the current directory): the funnel of the paper's
Fig. 8(a) (θ = 60°, e = 0.99, μ = 1, β0 = 0), the path of the particle's centre coloured by time,
the collisions as dots, and a zoom on the bounces it settles into.
"""

import sys
from pathlib import Path

import numpy as np

import funnel
from funnel import trajectory

outdir = Path(sys.argv[1] if len(sys.argv) > 1 else ".")
outdir.mkdir(parents=True, exist_ok=True)

# One trajectory, released at rest at x0 = 0.3 L, with its event log (numpy arrays).
model = dict(theta=60.0, e=0.99, mu=1.0, beta0=0.0)
result = funnel.simulate(release=0.3, events=True, **model)
events = result["events"]
print(f"{result['status']} after t = {result['duration']:.4g} sqrt(H/g) and {result['collisions']} collisions")

# The collisions alternate between the walls at slowly decreasing heights (the period-2 orbit).
walls = events["wall"][events["kind"] == "face"]
heights = events["y"][events["kind"] == "face"]
alternating = np.mean(walls[1:] != walls[:-1])
print(f"{100 * alternating:.1f}% of consecutive face collisions change wall; "
      f"collision height {heights[0]:.3f} H at first, {heights[-1]:.3f} H at last")

# The picture: walls, path (parabolas between events), collisions and a zoom panel.
geometry = dict(funnel.geometry(**model), release=0.3)
fig = trajectory.plot_trajectory(result, geometry)
trajectory.save_figure(fig, outdir / "trajectory.png")
print(f"wrote {outdir / 'trajectory.png'}")
