"""Computed collisions per second by engine path, from ``funnel bench --format json``.

``python -m funnel.plot bench BENCH.json --out bench.png`` draws one bar per path (scalar, sse4,
avx2, avx512) and thread count: the collisions the engine actually computed on the reference
ensemble per second of wall time (docs/performance.md).
"""

from __future__ import annotations

import json
import os
import sys
from pathlib import Path


def bars(bench):
    """(label, computed collisions per second) per path and thread count, in the bench's order."""
    rows = bench.get("reference_ensemble_by_path")
    if not isinstance(rows, list) or not rows:
        raise ValueError("invalid bench record: no 'reference_ensemble_by_path' list (run funnel bench --format json)")
    out = []
    for r in rows:
        threads = r["threads"]
        label = f"{r['path']} ({r['lanes']} lane{'s' if r['lanes'] != 1 else ''}), {threads} thread{'s' if threads != 1 else ''}"
        out.append((label, float(r["computed_collisions_per_second"])))
    return out


def plot_bench(bench, out):
    """Draws the bars of `bench` (a dict) into `out` (PNG or SVG by its suffix); returns the path."""
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    data = bars(bench)
    ref = bench.get("reference_ensemble", {})
    fig, ax = plt.subplots(figsize=(7, 0.45 * len(data) + 1.4))
    labels = [label for label, _ in data]
    values = [value / 1e6 for _, value in data]
    ax.barh(range(len(data)), values, color=["#888888" if label.startswith("scalar") else "#1f77b4" for label in labels])
    for i, v in enumerate(values):
        ax.text(v, i, f" {v:.1f}", va="center", fontsize=8)
    ax.set_yticks(range(len(data)), labels)
    ax.invert_yaxis()
    ax.set_xlabel("computed collisions per second [millions]")
    ax.set_xlim(0, max(values) * 1.15)
    samples = ref.get("samples", "?")
    ax.set_title(f"Reference ensemble (θ = 60°, e = 0.99, μ = 1, N = {samples}) by engine path", fontsize=9)
    fig.tight_layout()
    from ._files import replacing
    out = Path(out)
    try:
        with replacing(out) as tmp:
            fig.savefig(tmp, format=out.suffix.lstrip(".").lower() or None,
                        metadata={"Software": None} if out.suffix == ".png" else {"Date": None, "Creator": None})
    finally:
        plt.close(fig)
    return out


def main(argv=None, prog="python -m funnel.plot bench"):
    from ._files import OneLineParser
    parser = OneLineParser(prog=prog, description=__doc__.splitlines()[0])
    parser.add_argument("bench", help="the JSON of funnel bench --format json ('-': standard input)")
    parser.add_argument("--out", default="bench.png", help="picture to write, .png or .svg (default bench.png)")
    args = parser.parse_args(argv)
    if Path(args.out).suffix not in (".png", ".svg"):
        parser.error(f"invalid out = '{args.out}': valid values end in .png or .svg")
    try:
        try:
            text = sys.stdin.read() if args.bench == "-" else Path(args.bench).read_text()
        except OSError as error:
            raise OSError(f"invalid bench = '{args.bench}': {error.strerror or error}; valid values are the JSON file "
                          "of funnel bench --format json, or '-'") from None
        try:
            bench = json.loads(text)
        except ValueError as error:
            raise ValueError(f"invalid bench = '{args.bench}': not JSON ({error}); valid values are the JSON of "
                             "funnel bench --format json") from None
        path = plot_bench(bench, args.out)
    except (OSError, ValueError, KeyError, TypeError, AttributeError) as error:
        # Not a bench JSON (a list, a null where a number belongs): one line, exit status 2.
        what = str(error) if isinstance(error, (OSError, ValueError)) else f"not the JSON of funnel bench ({error!r})"
        print(f"{prog}: error: {what}", file=sys.stderr)
        return 2
    print(f"funnel.plot: wrote {path}", file=sys.stderr)
    return 0
