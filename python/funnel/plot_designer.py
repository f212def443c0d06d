"""Plots of the figures beyond the paper made for funnel designers (docs/python.md).

Kinds (the JSON's "kind"): wear_profiles (where the walls wear) and cone_3d_sweep (the cone in
3D with random sideways release velocities, drawn as a theta sweep with one curve per σ). :mod:`funnel.plot` registers it
in its ``PLOTTERS`` and draws it in its style; matplotlib is imported only when drawing.
"""

from __future__ import annotations

import numpy as np

from . import plot as base


def _wall_mean(columns, panel, key):
    """Heights and the mean of both walls' `key` per bin for one panel (the edge rows left out)."""
    rows = base._select(columns, (columns["panel"] == panel) & (columns["bin"] != "edge"))
    left = rows["wall"] == "left"
    right = rows["wall"] == "right"
    height = rows["height"][left]
    values = 0.5 * (rows[key][left] + rows[key][right])
    return height, values


def plot_wear_profiles(meta, columns):
    """Two panels against the height above the funnel bottom, one curve per angle: (a) the normal
    impulse and (b) the number of collisions per unit length of wall, per particle released."""
    fig = base._new_figure(6.6, 3.0)
    axes = fig.subplots(1, 2)
    panels = meta.get("panels", [])
    quantities = (("normal_impulse_per_length", "normal impulse per unit wall length", r"$m\sqrt{gH}/H$"),
                  ("collisions_per_length", "collisions per unit wall length", r"$1/H$"))
    for ax, (key, label, unit), letter in zip(axes, quantities, "ab"):
        for i, panel in enumerate(panels):
            height, values = _wall_mean(columns, panel["id"], key)
            order = np.argsort(height)
            ax.plot(values[order], height[order], label=base.pretty(panel["label"]),
                    **base.curve_style(i, len(panels), len(height)))
        ax.set_xlabel(f"{label} [{unit}]")
        ax.set_ylabel("height above the funnel bottom [$H$]")
        ax.set_xscale("log")
        ax.set_ylim(0.0, 1.0)
        base._panel_title(ax, letter, "")
    axes[0].legend(loc="upper right")
    fig.suptitle("Beyond the paper: where the walls wear (per particle, mean of both walls)", fontsize=9)
    return fig


#: Plot function of each kind of this module.
PLOTTERS = {"wear_profiles": plot_wear_profiles, "cone_3d_sweep": base.plot_theta_sweep}
