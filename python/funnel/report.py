"""A static HTML page of the reproduced figures: ``OUTDIR/index.html``.

Each figure is shown with its caption, its parameters, its provenance (the number N of release
positions where the figure averages over them, and its own compute time) and one line saying
what the paper claims and whether the data show it (the figure JSON's "check" object).
Mathematics is MathML (:mod:`funnel.mathml`), which browsers display natively; figures of kind
"trajectories" get an interactive player (:mod:`funnel.player`). Links are relative and nothing
is fetched from the network, so the page works from the file system, without a server.
``python -m funnel.plot`` writes it after rendering the images; ``python -m funnel.report OUTDIR``
rewrites only the page from images already there.
"""

from __future__ import annotations

import html
import json
import sys
from pathlib import Path

from .mathml import parameter_html, tex_to_mathml, text_to_html
from .player import PLAYER_CSS, player_data, player_html, player_script

#: Figure kinds that average over N release positions (the others show no N).
SAMPLED_KINDS = frozenset({"theta_sweep", "release_scan", "closed_final", "periodic_fraction"})

THETA = tex_to_mathml(r"\theta")

_CSS = """
body { font-family: Georgia, 'STIX Two Text', serif; max-width: 980px; margin: 2em auto; padding: 0 1em;
       color: #111; line-height: 1.45; }
h1 { font-size: 1.5em; margin-bottom: 0.2em; }
h2 { font-size: 1.15em; margin: 2.2em 0 0.4em; border-bottom: 1px solid #ccc; padding-bottom: 0.2em; }
figure { margin: 0; }
figure img { max-width: 100%; height: auto; border: 1px solid #eee; }
figcaption { font-size: 0.95em; margin: 0.5em 0; }
.check { padding: 0.45em 0.7em; margin: 0.6em 0; border-left: 4px solid #999; background: #f6f6f6; }
.check.holds { border-color: #1a7f37; background: #eefbf1; }
.check.fails { border-color: #cf222e; background: #fff0f0; }
.verdict { font-weight: bold; }
.holds .verdict { color: #1a7f37; }
.fails .verdict { color: #cf222e; }
table { border-collapse: collapse; font-size: 0.85em; margin: 0.4em 0; }
td, th { border: 1px solid #ddd; padding: 0.15em 0.5em; text-align: left; }
th { background: #fafafa; font-weight: normal; color: #555; }
.meta { font-size: 0.8em; color: #555; }
nav a { margin-right: 0.8em; }
math { font-size: 1.05em; font-family: 'STIX Two Math', 'Latin Modern Math', 'DejaVu Math TeX Gyre', math; }
"""


def _e(value):
    return html.escape(str(value), quote=True)


def _params_table(params):
    if not params:
        return ""
    head = "".join(f"<th>{parameter_html(k)}</th>" for k in params)
    cells = "".join(f"<td>{_e(_text(v))}</td>" for v in params.values())
    return f"<table><tr>{head}</tr><tr>{cells}</tr></table>"


def _text(value):
    if isinstance(value, float):
        return f"{value:g}"
    if isinstance(value, (list, tuple)):
        return ", ".join(_text(v) for v in value)
    return str(value)


def check_line(check):
    """HTML of the claim line: what the paper says, what the data show, and the verdict."""
    if not check:
        return '<p class="check">No check recorded for this figure.</p>'
    holds = check.get("holds")
    css, verdict = {True: ("holds", "✔ holds"), False: ("fails", "✘ does not hold")}.get(holds, ("", "not decided"))
    return (f'<p class="check {css}"><b>The paper claims:</b> {text_to_html(check.get("claim", ""))} '
            f'<b>Measured:</b> {text_to_html(check.get("measured", ""))} '
            f'<span class="verdict">{verdict}</span></p>')


def _seconds(value):
    return f"{value:.3g} s" if value < 10 else f"{value:.1f} s"


def run_time_text(meta):
    """The figure's compute time, and how it was measured: its own, or (θ sweeps computed in one
    shared batch) its share of the batch in proportion to the collisions simulated for it."""
    value = meta.get("run_time_s")
    if not isinstance(value, (int, float)):
        return ""
    text = f"computed in {_seconds(float(value))}"
    basis = meta.get("run_time_basis")
    if isinstance(basis, dict) and basis.get("batch_time_s") is not None:
        share = basis.get("figure_collisions", 0) / basis["batch_collisions"] if basis.get("batch_collisions") else 0
        text += (f" (its share of the {_seconds(float(basis['batch_time_s']))} batch of all θ sweeps, in proportion "
                 f"to the collisions simulated for its ensembles: {100 * share:.3g}%; an ensemble shared by "
                 "several figures is split evenly between them)")
    return text


def figure_section(entry):
    """HTML of one figure: title, image (linked to the SVG), caption, claim line, parameters,
    and a trajectory player when the entry has "player" data."""
    meta, d = entry["meta"], entry["dir"]
    name = meta.get("figure", d)
    images = {Path(p).suffix: f"{d}/{p}" for p in entry.get("images", [])}
    png, svg = images.get(".png", f"{d}/{d}.png"), images.get(".svg", f"{d}/{d}.svg")
    panels = meta.get("panels") or []
    panel_text = "; ".join(f"({_e(p.get('id', ''))}) {text_to_html(p.get('label', ''))}".strip() for p in panels)
    series = meta.get("series")
    details = []
    if panel_text:
        details.append(f"panels: {panel_text}")
    if series:
        details.append(f"curves by: {parameter_html(series)}")
    if meta.get("observables"):
        details.append(f"observables: {_e(', '.join(meta['observables']))}")
    if meta.get("samples") is not None and meta.get("kind") in SAMPLED_KINDS:
        details.append(f"{tex_to_mathml('N')} = {_e(meta['samples'])} release positions")
    prov = []
    for key, label in (("version", "funnel"), ("git_commit", "commit")):
        if meta.get(key) is not None:
            prov.append(f"{label} {_e(meta[key])}")
    if run_time_text(meta):
        prov.append(_e(run_time_text(meta)).replace("θ", tex_to_mathml(r"\theta")))
    player = ""
    if entry.get("player"):
        player = (f'<p class="meta">Play the trajectories: the close-up on the right follows the ball (to scale) and '
                  f'shows its spin as a line.</p>\n{player_html(d, entry["player"])}')
    return f"""
<section id="{_e(name)}">
<h2>{_e(name)}: {text_to_html(meta.get("title", ""))}</h2>
<figure>
<a href="{_e(svg)}"><img src="{_e(png)}" alt="{_e(name)}"></a>
<figcaption>{text_to_html(meta.get("caption", ""))}</figcaption>
</figure>
{player}
{check_line(meta.get("check"))}
<p class="meta">{' &middot; '.join(details)}</p>
{_params_table(meta.get("params") or {})}
<p class="meta">{' &middot; '.join(prov)} &middot; data: <a href="{_e(d)}/{_e(d)}.csv">{_e(d)}.csv</a>,
<a href="{_e(d)}/{_e(d)}.json">{_e(d)}.json</a> &middot; vector image: <a href="{_e(svg)}">{_e(Path(svg).name)}</a></p>
</section>"""


def _with_players(outdir, entries):
    """The entries, those of kind "trajectories" with their player data read from their CSV."""
    from .plot import read_csv
    out = []
    for e in entries:
        if e["meta"].get("kind") == "trajectories" and "player" not in e:
            csv_path = Path(outdir) / e["dir"] / f"{e['dir']}.csv"
            if csv_path.is_file():
                e = dict(e, player=player_data(e["meta"], read_csv(csv_path)))
        out.append(e)
    return out


def write_index(outdir, entries):
    """Writes outdir/index.html for the figure entries ({"dir", "meta", "images"}); returns its path."""
    outdir = Path(outdir)
    entries = _with_players(outdir, entries)
    summary = [e["meta"].get("check", {}).get("holds") for e in entries]
    n_hold = sum(1 for h in summary if h is True)
    nav = " ".join(f'<a href="#{_e(e["meta"].get("figure", e["dir"]))}">{_e(e["meta"].get("figure", e["dir"]))}</a>'
                   for e in entries)
    sections = "".join(figure_section(e) for e in entries)
    script = f"<script>\n{player_script()}</script>" if any(e.get("player") for e in entries) else ""
    units = ", ".join(f"{what} in {tex_to_mathml(tex)}" for what, tex in (
        ("lengths", "H"), ("times", r"\sqrt{H/g}"), ("impulses", r"m\sqrt{gH}"), ("energies", "mgH")))
    page = f"""<!DOCTYPE html>
<html lang="en">
<head>
<meta charset="utf-8">
<title>funnel: figures of "Critical role of friction for a single particle falling through a funnel"</title>
<style>{_CSS}{PLAYER_CSS}</style>
</head>
<body>
<h1>funnel: the paper's figures, reproduced</h1>
<p>Simulated with funnel (exact event-driven dynamics) for the paper <i>Critical role of friction for a
single particle falling through a funnel</i>. Units: {units}. Claims confirmed by the data: {n_hold} of
{len(entries)}.</p>
<nav>{nav}</nav>
{sections}
{script}
</body>
</html>
"""
    from ._files import replacing
    path = outdir / "index.html"
    with replacing(path, hidden=False) as tmp:
        tmp.write_text(page, encoding="utf-8")
    return path


def main(argv=None):
    """Command line: ``python -m funnel.report OUTDIR`` (the page only, from existing images)."""
    from .plot import figure_dirs, no_figures
    args = sys.argv[1:] if argv is None else list(argv)
    usage = "usage: python -m funnel.report OUTDIR"
    if args in (["-h"], ["--help"]):
        print(f"{usage}\n\nRewrite OUTDIR/index.html from the figures' records and existing images "
              "(python -m funnel.plot OUTDIR draws them first).")
        return 0
    # Say what is wrong, not only the usage line.
    if len(args) != 1:
        problem = f"expected one argument OUTDIR, got {len(args)}"
    elif not Path(args[0]).is_dir():
        what = "not a directory" if Path(args[0]).exists() else "no such directory"
        problem = f"invalid outdir = '{args[0]}': {what}"
    else:
        problem = None
    if problem:
        print(f"{usage}\npython -m funnel.report: error: {problem}", file=sys.stderr)
        return 2
    from .plot import load_meta
    entries = []
    try:
        dirs = figure_dirs(args[0])
        if not dirs:
            raise no_figures(args[0])
        for d in dirs:
            entries.append({"dir": d.name, "meta": load_meta(d), "images": [f"{d.name}.png", f"{d.name}.svg"]})
        index = write_index(args[0], entries)
    except (ValueError, OSError) as err:
        print(f"python -m funnel.report: error: {err}", file=sys.stderr)
        return 2
    print(f"funnel.report: wrote {index}", file=sys.stderr)
    return 0


if __name__ == "__main__":
    sys.exit(main())
