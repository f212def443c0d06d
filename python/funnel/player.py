"""An interactive trajectory player for the HTML report (canvas + JavaScript, no network).

For a figure of kind "trajectories" (Fig. 8), :func:`player_html` embeds the figure's own data
(the events of ``figNN.csv`` with positions, velocities and spins, and the geometry of
``figNN.json``) in the page, and ``player.js`` draws and plays them: play, pause, a time slider
and a speed choice, the funnel with the path so far, and a close-up that follows the ball with
its spin drawn as a line. The motion between events is that of :mod:`funnel.motion`.
"""

from __future__ import annotations

import json
from pathlib import Path

import numpy as np

#: Event columns the player needs (the CSV has more).
EVENT_FIELDS = ("time", "kind", "wall", "x", "y", "u_before", "v_before", "omega_before", "u_after", "v_after",
                "omega_after")
NUMBER_FIELDS = frozenset(EVENT_FIELDS) - {"kind", "wall"}


def player_data(meta, columns):
    """The player's data for a trajectories figure: {"figure", "panels": [{"id", "label",
    "geometry", "events": {field: list}}]} from the figure's JSON (meta) and CSV (columns)."""
    from .plot import _panel_rows, _panels
    geometries = meta.get("geometry") or {}
    panels = []
    for pid, label in _panels(meta, columns):
        rows = _panel_rows(columns, pid)
        events = {}
        for name in EVENT_FIELDS:
            values = rows.get(name, np.zeros(len(rows["time"])))
            events[name] = [float(v) for v in values] if name in NUMBER_FIELDS else [str(v) for v in values]
        panels.append({"id": pid, "label": label, "geometry": geometries.get(pid, {}), "events": events})
    return {"figure": meta.get("figure", ""), "panels": panels}


def script_json(data):
    """JSON that is safe inside <script type="application/json">: no "</" and no "<!--"."""
    return json.dumps(data, separators=(",", ":"), ensure_ascii=False).replace("<", "\\u003c")


def player_html(figure_id, data):
    """HTML of one player: its container and its embedded data (the script comes once per page,
    from :func:`player_script`)."""
    return (f'<div class="player" id="player-{figure_id}"></div>\n'
            f'<script type="application/json" id="player-data-{figure_id}">{script_json(data)}</script>')


def player_script():
    """The player's JavaScript, to be put once at the end of the page."""
    return (Path(__file__).with_name("player.js")).read_text(encoding="utf-8").replace("</", "<\\/")


PLAYER_CSS = """
.player { margin: 0.8em 0; }
.player-controls { display: flex; gap: 0.6em; align-items: center; flex-wrap: wrap; font-size: 0.9em;
                   margin-bottom: 0.3em; }
.player-controls input[type=range] { flex: 1; min-width: 12em; }
.player canvas { border: 1px solid #ddd; display: block; }
"""
