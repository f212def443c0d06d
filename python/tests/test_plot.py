"""funnel.plot and funnel.report on a synthetic dataset with one figure of every kind."""

import html
import os
import re
import shutil
import subprocess
import sys

import numpy as np
import pytest

from fake_figures import EVENT_COLUMNS, bounce, write_fake_dataset
from funnel import plot
from funnel.mathml import text_to_html

PNG_MAGIC = b"\x89PNG\r\n\x1a\n"


@pytest.fixture(scope="module")
def dataset(tmp_path_factory):
    """A synthetic OUTDIR, rendered once by funnel.plot.main."""
    outdir = tmp_path_factory.mktemp("paper")
    dirs = write_fake_dataset(outdir)
    (outdir / "fig99").mkdir()  # no data: must be skipped
    (outdir / "fig99" / "fig99.json").write_text("{}")
    assert plot.main([str(outdir)]) == 0
    return outdir, dirs


def test_every_kind_is_in_the_dataset(dataset):
    _, dirs = dataset
    kinds = {plot.load_figure(d)[0]["kind"] for d in dirs}
    assert kinds == set(plot.KINDS)


def test_images_are_written_for_every_figure(dataset):
    outdir, dirs = dataset
    for d in dirs:
        png, svg = d / f"{d.name}.png", d / f"{d.name}.svg"
        assert png.read_bytes()[:8] == PNG_MAGIC and png.stat().st_size > 10_000, d.name
        text = svg.read_text()
        assert "<svg" in text and text.rstrip().endswith("</svg>"), d.name
        assert not list(d.glob("*.tmp.*")), d.name
    assert not (outdir / "fig99" / "fig99.png").exists()


def test_index_links_every_figure_with_its_caption_and_check(dataset):
    outdir, dirs = dataset
    page = (outdir / "index.html").read_text()
    for d in dirs:
        meta, _ = plot.load_figure(d)
        assert f'src="{d.name}/{d.name}.png"' in page
        assert f'href="{d.name}/{d.name}.svg"' in page
        assert text_to_html(meta["caption"]) in page
        assert html.escape(meta["check"]["claim"]) in page
    assert page.count("✔ holds") == 8 and page.count("✘ does not hold") == 1  # fig07 is marked as failing
    assert "/tmp" not in page and str(outdir) not in page  # relative links only
    assert "fig99" not in page


def test_svg_output_is_reproducible(dataset, tmp_path):
    outdir, _ = dataset
    copy = tmp_path / "fig10"
    shutil.copytree(outdir / "fig10", copy)
    plot.render(copy)
    assert (copy / "fig10.svg").read_bytes() == (outdir / "fig10" / "fig10.svg").read_bytes()


def test_each_picture_is_laid_out_once_and_drawn_once_per_file(dataset, tmp_path, monkeypatch):
    # savefig with a layout engine draws twice (a draw without output to lay the figure out,
    # then the file's); render runs the layout alone (plot.lay_out) and draws each file once:
    # two draws in all, neither with an engine (three before lay_out, four with "none").
    outdir, _ = dataset
    copy = tmp_path / "fig03"
    shutil.copytree(outdir / "fig03", copy)
    draws, figures = [], []
    build = plot.plot_figure

    def counted(meta, columns):
        fig = build(meta, columns)
        fig.canvas.mpl_connect("draw_event", lambda event: draws.append(fig.get_layout_engine()))
        figures.append(fig)
        return fig

    monkeypatch.setattr(plot, "plot_figure", counted)
    plot.render(copy)
    assert len(figures) == 1 and draws == [None, None]
    for ext in ("png", "svg"):  # the same pictures as main() drew
        assert (copy / f"fig03.{ext}").read_bytes() == (outdir / "fig03" / f"fig03.{ext}").read_bytes(), ext


def test_the_layout_alone_gives_savefigs_own_pictures_byte_for_byte(dataset, tmp_path):
    # plot.lay_out stands in for the layout pass savefig makes with the constrained-layout engine:
    # every kind's PNG and SVG must be the bytes savefig writes with the engine left on (the
    # PNG's layout kept for the SVG). A matplotlib whose pass differs fails here.
    import matplotlib
    outdir, dirs = dataset
    laid_out = 0
    for d in dirs:
        meta, columns = plot.load_figure(d)
        fig = plot.plot_figure(meta, columns)
        laid_out += fig.get_layout_engine() is not None
        with matplotlib.rc_context(plot.STYLE):
            for ext, metadata in plot.FORMATS:
                fig.savefig(tmp_path / f"own.{ext}", format=ext, metadata=metadata)
                fig.set_layout_engine(None)  # the PNG's layout kept for the SVG
        for ext, _ in plot.FORMATS:
            own = (tmp_path / f"own.{ext}").read_bytes()
            assert own == (d / f"{d.name}.{ext}").read_bytes(), f"{d.name}.{ext}"
    assert laid_out == len(dirs)


def test_figures_drawn_in_parallel_are_those_drawn_one_by_one(dataset, tmp_path):
    # The dataset was drawn by main() with a process per core; drawn again here in this process.
    outdir, dirs = dataset
    serial = tmp_path / "serial"
    shutil.copytree(outdir, serial)
    plot.render_all(serial, jobs=1)
    for d in dirs:
        assert (serial / d.name / f"{d.name}.png").read_bytes() == (d / f"{d.name}.png").read_bytes(), d.name
    assert (serial / "index.html").read_text() == (outdir / "index.html").read_text()
    with pytest.raises(ValueError, match="invalid jobs = 0"):
        plot.render_all(serial, jobs=0)


def test_module_entry_point(tmp_path):
    write_fake_dataset(tmp_path)
    for d in list(tmp_path.iterdir()):
        if d.name not in ("fig10", "fig12"):
            shutil.rmtree(d)
    env = dict(os.environ, PYTHONPATH=os.pathsep.join(sys.path))
    proc = subprocess.run([sys.executable, "-m", "funnel.plot", str(tmp_path)], capture_output=True, text=True,
                          env=env)
    assert proc.returncode == 0, proc.stderr
    assert (tmp_path / "fig12" / "fig12.png").is_file() and (tmp_path / "index.html").is_file()
    bad = subprocess.run([sys.executable, "-m", "funnel.plot", str(tmp_path / "missing")], capture_output=True,
                         text=True, env=env)
    assert bad.returncode == 2 and "not a directory" in bad.stderr


def test_matplotlib_is_imported_lazily():
    code = "import sys, funnel, funnel.plot, funnel.report; assert 'matplotlib' not in sys.modules"
    env = dict(os.environ, PYTHONPATH=os.pathsep.join(sys.path))
    subprocess.run([sys.executable, "-c", code], check=True, env=env)


def test_read_csv_types(tmp_path):
    path = tmp_path / "t.csv"
    path.write_text("panel,theta,status,n\n1,40,exited,3\n2,45.5,rest,4\n")
    columns = plot.read_csv(path)
    assert columns["theta"].dtype == np.float64 and columns["theta"].tolist() == [40.0, 45.5]
    assert columns["panel"].tolist() == ["1", "2"] and columns["status"].dtype.kind == "U"
    assert columns["n"].tolist() == [3.0, 4.0]


def test_read_csv_converts_a_column_when_it_is_first_read(tmp_path):
    path = tmp_path / "t.csv"
    path.write_text("panel,theta,bad\na,40,x\nb,45.5,1\na,50,2\n")
    columns = plot.read_csv(path)
    assert list(columns) == ["panel", "theta", "bad"] and len(columns) == 3
    assert "theta" in columns and "nope" not in columns
    with pytest.raises(KeyError):
        columns["nope"]
    assert columns["theta"] is columns["theta"]  # converted once
    assert columns["bad"].dtype.kind == "U"  # one field is not a number: text
    rows = plot._panel_rows(columns, "a")
    assert rows["theta"].tolist() == [40.0, 50.0] and rows["bad"].tolist() == ["x", "2"]
    assert dict(rows.items())["panel"].tolist() == ["a", "a"]


def test_trajectory_path_follows_the_events():
    rows, geometry = bounce(55.0, 0.4, max_events=60)
    columns = {name: np.array([row[j] for row in rows]) for j, name in enumerate(EVENT_COLUMNS)}
    for name in ("time", "x", "y", "u_after", "v_after"):
        columns[name] = columns[name].astype(float)
    k = 16
    x, y, t = plot.trajectory_path(geometry, columns, samples_per_arc=k)
    assert x.shape == y.shape == t.shape == (k * len(rows),)
    np.testing.assert_allclose(t[k - 1::k], columns["time"], rtol=1e-15)
    assert t[0] == 0 and np.all(np.diff(t) >= 0)
    # Each arc starts at the previous event (the first at the release) and ends at its own event.
    np.testing.assert_allclose(x[k - 1::k], columns["x"], atol=1e-12)
    np.testing.assert_allclose(y[k - 1::k], columns["y"], atol=1e-12)
    assert x[0] == pytest.approx(0.4 * geometry["half_width"]) and y[0] == geometry["y_release"]


def test_sustained_contact_is_drawn_along_the_wall():
    events = {"time": np.array([1.0, 2.0, 3.0]), "kind": np.array(["contact_start", "contact_end", "exit"]),
              "x": np.array([-0.5, -0.1, -0.05]), "y": np.array([0.5, 0.1, 0.0]),
              "u_after": np.array([0.3, 0.1, 0.0]), "v_after": np.array([-0.3, -0.2, 0.0])}
    geometry = {"y_release": 1.0, "half_width": 1.0, "release": -0.5}
    x, y, _ = plot.trajectory_path(geometry, events, samples_per_arc=5)
    seg_x, seg_y = x[5:10], y[5:10]  # contact_start -> contact_end: a straight line
    np.testing.assert_allclose(np.diff(seg_y) / np.diff(seg_x), -1.0)


def test_unknown_kind_is_an_error():
    with pytest.raises(ValueError, match="unknown figure kind 'pie'"):
        plot.plot_figure({"kind": "pie"}, {})


def test_labels():
    assert plot.series_label("mu", 0.05) == r"$\mu$ = 0.05"
    assert plot.series_label("theta", 50.0) == r"$\theta$ = 50°"
    assert plot.series_label("beta0", -0.31) == "$\\beta_0$ = \u22120.31"
    assert plot.series_label("release_dist", "disk") == "cone (disk)"
    assert plot.axis_label("duration") == r"average duration [$\sqrt{H/g}$]"
    assert plot.axis_label("energy_loss") == r"average energy loss [$mgH$]"
    assert plot.axis_label("exit_speed") == r"average exit speed [$\sqrt{gH}$]"
    assert plot.pretty("β0 = -0.31") == "$\\beta_0$ = \u22120.31"


# ---------------------------------------------------------------------------------------------
# Curves that coincide stay visible

def _labelled_lines(ax):
    return {line.get_label(): line for line in ax.get_lines() if not line.get_label().startswith("_")}


def test_coinciding_curves_differ_in_dashes_and_markers(dataset):
    _, dirs = dataset
    meta, columns = plot.load_figure(next(d for d in dirs if d.name == "fig03"))
    columns = dict(columns)
    # Make mu = 5 identical to mu = 1, as in the paper: both must still be seen.
    one, five = columns["mu"] == 1.0, columns["mu"] == 5.0
    columns["duration_mean"] = columns["duration_mean"].copy()
    columns["duration_mean"][five] = columns["duration_mean"][one]
    fig = plot.plot_figure(meta, columns)
    for ax in fig.axes:
        lines = _labelled_lines(ax)
        if not lines:
            continue
        styles = {(str(line.get_linestyle()), line.get_marker()) for line in lines.values()}
        assert len(styles) == len(lines), "two curves share dashes and marker"
        mu1, mu5 = lines[plot.series_label("mu", 1.0)], lines[plot.series_label("mu", 5.0)]
        assert mu1.get_linestyle() == "-" and mu5.get_linestyle() == "--"
        assert mu5.get_zorder() > mu1.get_zorder()  # the dashed curve on top: both colours show
        assert mu1.get_markevery() != mu5.get_markevery()  # markers at different angles


def test_theta_sweep_rows_show_all_their_data(dataset):
    _, dirs = dataset
    meta, columns = plot.load_figure(next(d for d in dirs if d.name == "fig06"))
    columns = dict(columns, duration_mean=columns["duration_mean"].copy())
    columns["duration_mean"][columns["panel"] == "b"] *= 3.0  # the middle panel has the largest values
    fig = plot.plot_figure(meta, columns)
    for ax in fig.axes:
        lo, hi = ax.get_ylim()
        for line in ax.get_lines():
            y = np.asarray(line.get_ydata(), dtype=float)
            if len(y) > 2:
                assert lo == 0 and np.nanmax(y) <= hi, ax.get_title()


def _caption(figure):
    import tomllib
    from pathlib import Path
    path = Path(__file__).resolve().parents[2] / "paper" / f"{figure}.toml"
    with open(path, "rb") as f:
        return tomllib.load(f)["caption"]


@pytest.mark.parametrize("figure,index_a,index_b", [("fig03", 4, 5), ("fig04", 4, 5), ("fig05", 4, 5),
                                                    ("fig12", 1, 2)])
def test_captions_say_how_coinciding_curves_are_drawn(figure, index_a, index_b):
    caption = _caption(figure)
    for index in (index_a, index_b):
        dashes, marker = plot.style_description(index).split(", ")
        assert dashes in caption and marker in caption, (figure, index)


def test_eigenvalue_legend_explains_dashes_and_equal_moduli_stay_visible(dataset):
    _, dirs = dataset
    meta, columns = plot.load_figure(next(d for d in dirs if d.name == "fig10"))
    columns = dict(columns, mod3=columns["mod2"].copy())  # |lambda_2| = |lambda_3|
    fig = plot.plot_figure(meta, columns)
    legend = fig.legends[0]
    labels = [t.get_text() for t in legend.get_texts()]
    assert "stable" in labels and "unstable" in labels
    handles = dict(zip(labels, getattr(legend, "legend_handles", None) or legend.legendHandles))
    assert handles["stable"].get_linestyle() == "-" and handles["unstable"].get_linestyle() == "--"
    l2, l3 = handles[r"$|\lambda_2|$"], handles[r"$|\lambda_3|$"]
    assert l2.get_marker() != l3.get_marker() and l2.get_linewidth() > 2 * l3.get_linewidth()
    caption = _caption("fig10")
    for index in (1, 2):
        assert plot.MARKER_NAMES[index] in caption


def test_closed_final_y_range_fits_the_data(dataset):
    _, dirs = dataset
    meta, columns = plot.load_figure(next(d for d in dirs if d.name == "fig11"))
    reach = float(np.max(np.abs(np.concatenate([columns["x_last_over_L"], columns["x_prev_over_L"]]))))
    assert reach < 0.6
    fig = plot.plot_figure(meta, columns)
    for ax in fig.axes:
        if ax.get_visible() and ax.collections:
            lo, hi = ax.get_ylim()
            assert lo == -hi and reach < hi < 1.3 * reach


def test_report_shows_n_only_where_it_applies_and_per_figure_run_times(dataset):
    outdir, _ = dataset
    page = (outdir / "index.html").read_text()
    sections = {s.split('"', 1)[0]: s for s in page.split('<section id="')[1:]}
    for name, section in sections.items():
        kind = plot.load_figure(outdir / name)[0]["kind"]
        assert ("release positions" in section) == (kind in ("theta_sweep", "release_scan", "closed_final",
                                                             "periodic_fraction")), name
    assert "computed in 1.5 s (its share of the 6 s batch" in sections["fig03"] and "25%" in sections["fig03"]
    assert "computed in 1.5 s" in sections["fig10"] and "batch" not in sections["fig10"]


def test_report_renders_maths_as_mathml(dataset):
    outdir, _ = dataset
    page = (outdir / "index.html").read_text()
    visible = page
    for tag in ("annotation", "script"):  # TeX source kept for copying, and the player's code
        while f"<{tag}" in visible:
            start = visible.index(f"<{tag}")
            visible = visible[:start] + visible[visible.index(f"</{tag}>", start) + len(tag) + 3:]
    assert "<math>" in page and "<msub><mi>x</mi><mi>c</mi></msub>" in page and "<mfrac>" in page
    assert "x_c/L" not in visible and "$" not in visible and "\\sqrt" not in visible
    assert "β0" not in visible  # the panels' "β0 = 0.31" is shown as a subscript


def test_report_embeds_a_player_with_the_figure_data(dataset):
    import json
    outdir, _ = dataset
    page = (outdir / "index.html").read_text()
    assert page.count('<div class="player" id="player-fig08">') == 1 and "FunnelPlayer" in page
    start = page.index('<script type="application/json" id="player-data-fig08">')
    data = json.loads(page[page.index(">", start) + 1:page.index("</script>", start)])
    meta, columns = plot.load_figure(outdir / "fig08")
    assert [p["id"] for p in data["panels"]] == ["a", "b"]
    for panel in data["panels"]:
        rows = plot._panel_rows(columns, panel["id"])
        assert panel["events"]["time"] == rows["time"].tolist()
        assert panel["events"]["omega_after"] == rows["omega_after"].tolist()
        assert panel["geometry"] == meta["geometry"][panel["id"]]


def test_bad_figure_data_is_one_line_and_exit_status_2(tmp_path, capsys):
    # A corrupt record, an unknown kind or a list for the bench JSON gave tracebacks (exit 1),
    # some after other pictures were drawn.
    from funnel import plot, report
    fig = tmp_path / "fig01"
    fig.mkdir()
    (fig / "fig01.csv").write_text("a\n1\n")
    (fig / "fig01.json").write_text("{not json")
    assert plot.main([str(tmp_path)]) == 2
    assert "invalid figure data" in capsys.readouterr().err
    assert report.main([str(tmp_path)]) == 2
    (fig / "fig01.json").write_text('{"kind": "nonsense"}')
    assert plot.main([str(tmp_path)]) == 2
    assert "kind = 'nonsense'; valid kinds are" in capsys.readouterr().err
    assert sorted(p.name for p in fig.iterdir()) == ["fig01.csv", "fig01.json"]  # nothing drawn
    (tmp_path / "b.json").write_text("[1, 2]")
    assert plot.main(["bench", str(tmp_path / "b.json"), "--out", str(tmp_path / "b.png")]) == 2
    assert "not the JSON of funnel bench" in capsys.readouterr().err


def test_an_outdir_without_figures_and_a_missing_one_say_what_is_wrong(tmp_path, capsys):
    # funnel.plot said "invalid jobs = 0: valid range is an integer >= 1", funnel.report printed
    # only its usage line.
    from funnel import report
    (tmp_path / "fig01").mkdir()
    (tmp_path / "fig01" / "fig01.json").write_text("{}")  # no CSV: not a figure directory
    expected = (f"invalid outdir = '{tmp_path}': no figure directories (figNN/ with figNN.json and figNN.csv) "
                "found in it")
    for jobs in (None, 1, 2):
        with pytest.raises(ValueError, match="^" + re.escape(expected)):
            plot.render_all(tmp_path, jobs=jobs)
    assert plot.main([str(tmp_path)]) == 2
    assert capsys.readouterr().err.startswith(f"python -m funnel.plot: error: {expected}")
    assert report.main([str(tmp_path)]) == 2
    assert capsys.readouterr().err.startswith(f"python -m funnel.report: error: {expected}")
    assert not (tmp_path / "index.html").exists()
    missing = tmp_path / "missing"
    assert report.main([str(missing)]) == 2
    assert f"python -m funnel.report: error: invalid outdir = '{missing}': no such directory" in capsys.readouterr().err
    (tmp_path / "file").write_text("")
    assert report.main([str(tmp_path / "file")]) == 2
    assert "file': not a directory" in capsys.readouterr().err
    assert report.main([]) == 2
    err = capsys.readouterr().err
    assert err.startswith("usage: python -m funnel.report OUTDIR") and "expected one argument OUTDIR, got 0" in err
    assert report.main(["--help"]) == 0
    assert capsys.readouterr().out.startswith("usage: python -m funnel.report OUTDIR")
