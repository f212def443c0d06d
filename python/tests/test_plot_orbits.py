"""funnel.plot_orbits (Figs. 1, 9, 14 and Fig. 2 explained) on data made by ``funnel paper --quick``."""

import json

import pytest

from funnel import plot
from funnel.mathml import text_to_html

PNG_MAGIC = b"\x89PNG\r\n\x1a\n"
ORBIT_FIGURES = ("fig01", "fig02x", "fig09", "fig14")


@pytest.fixture(scope="module")
def paper(cli, tmp_path_factory):
    """The orbit figures' data (a quick preview), rendered by funnel.plot.main."""
    outdir = tmp_path_factory.mktemp("orbits")
    cli("paper", "--quick", "--no-plots", "--only", ",".join(ORBIT_FIGURES), "--out", outdir, json_output=False)
    assert plot.main([str(outdir)]) == 0
    return outdir


def test_every_orbit_kind_is_drawn(paper):
    kinds = {plot.load_figure(paper / f)[0]["kind"] for f in ORBIT_FIGURES}
    assert kinds == set(plot.ORBIT_KINDS)
    for f in ORBIT_FIGURES:
        png, svg = paper / f / f"{f}.png", paper / f / f"{f}.svg"
        assert png.read_bytes()[:8] == PNG_MAGIC and png.stat().st_size > 10_000, f
        assert svg.read_text().rstrip().endswith("</svg>"), f


def test_report_shows_the_orbit_figures_with_their_checks(paper):
    page = (paper / "index.html").read_text()
    for f in ORBIT_FIGURES:
        meta = json.loads((paper / f / f"{f}.json").read_text())
        assert f'src="{f}/{f}.png"' in page
        assert text_to_html(meta["check"]["claim"]) in page  # as the report renders it (MathML)
        assert meta["check"]["holds"] is True, (f, meta["check"]["measured"])
    assert "Beyond the paper" in page


def test_orbit_paths_end_where_the_next_event_is(paper):
    """Fig. 14: each flight drawn from an event ends at the next event's position (the path is exact)."""
    meta, columns = plot.load_figure(paper / "fig14")
    from funnel.plot_orbits import event_path
    for pid in {str(p) for p in columns["panel"]}:
        rows = plot._panel_rows(columns, pid)
        x, y = event_path(rows, samples_per_arc=2)
        assert x[1::2] == pytest.approx(rows["x"][1:], abs=1e-9)
        assert y[1::2] == pytest.approx(rows["y"][1:], abs=1e-9)
        # ... and the period ends at rest at the release point.
        assert (x[-1], y[-1]) == pytest.approx((rows["x"][0], rows["y"][0]), abs=1e-12)


def test_fig02x_marks_every_detected_peak(paper):
    meta, columns = plot.load_figure(paper / "fig02x")
    peaks = meta["peaks"]
    assert peaks and all(p["from"] <= p["theta_max"] <= p["to"] for p in peaks)
    elevated = columns["theta"][columns["elevated"] > 0.5]
    assert all(any(p["from"] <= t <= p["to"] for p in peaks) for t in elevated)
    explained = sum(p["explained"] for p in peaks)
    assert f"{explained} of {len(peaks)} peaks" in meta["check"]["measured"]
