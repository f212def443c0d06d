"""Example: the real cone in 3D — a ball thrown a little sideways orbits the axis.

    PYTHONPATH=build/python /usr/bin/python3 examples/cone_3d.py [OUTDIR]

One trajectory in the cone (theta = 60, e = 0.99, mu = 1) released at 0.6 L with a sideways
velocity w0 = 0.05 sqrt(gH): prints its status, duration and turns about the axis, and draws its
collisions seen from above (x, z) into OUTDIR/cone_3d.png. Then 400-ball ensembles at 44 and 46
degrees, at rest (the paper's cone) and with random sideways velocities sigma = 0.03: prints
the mean duration of the balls that leave and the fraction that rolls round the cone for ever.
"""

import sys
from pathlib import Path

import numpy as np
from matplotlib.figure import Figure

import funnel

outdir = Path(sys.argv[1] if len(sys.argv) > 1 else ".")
outdir.mkdir(parents=True, exist_ok=True)

r = funnel.simulate(0.6, events=True, space="3d", theta=60, release_w=0.05)
print(f"one ball: {r['status']} at t = {r['duration']:.0f} sqrt(H/g) after {r['collisions']} collisions, "
      f"{r['orbits']:.0f} turns about the axis" + (" (it rolls round the outlet for ever)" if r["periodic"] else ""))
ev = r["events"]
hits = np.isin(ev["kind"], ("face", "edge"))
fig = Figure(figsize=(4.0, 4.0))
ax = fig.add_subplot()
ax.plot(ev["x"][hits], ev["z"][hits], ".", ms=2, color="#0072B2")
ax.set_aspect("equal")
ax.set_xlabel("x [H]")
ax.set_ylabel("z [H]")
ax.set_title("collisions seen from above", fontsize=9)
fig.savefig(outdir / "cone_3d.png", dpi=120)

for sigma in (0.0, 0.03):
    line = []
    for theta in (44, 46):
        e = funnel.ensemble(samples=400, theta=theta, velocity_sd=sigma, t_max=300, space="3d", per_sample=True)
        ps = e["per_sample"]
        left = ps["status"] == "exited"
        line.append(f"{theta} deg: {ps['duration'][left].mean():.1f} ({1 - left.mean():.1%} trapped)")
    print(f"sigma = {sigma}: mean duration of the balls that leave, " + ", ".join(line))
