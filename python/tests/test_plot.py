"""funnel.plot and funnel.report on a synthetic dataset with one figure of every kind."""

import html
import os
import shutil
import subprocess
import sys

import numpy as np
import pytest

from fake_figures import EVENT_COLUMNS, bounce, write_fake_dataset
from funnel import plot

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
        assert html.escape(meta["caption"]) in page
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
    assert plot.pretty("β0 = -0.31") == "$\\beta_0$ = \u22120.31"
