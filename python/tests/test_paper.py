"""funnel.paper_figure: the paper's figures from Python, computed by the module `funnel paper` uses."""

import json

import numpy as np
import pytest

import funnel


@pytest.mark.parametrize("figure", ["fig11", "fig03", "fig07"])
def test_a_figure_from_python_is_the_clis_bit_for_bit(cli, tmp_path, figure):
    # A closed-funnel figure, a theta sweep (run through the shared batch) and a release scan.
    cli("paper", "--quick", "--no-plots", "--only", figure, "--threads", 2, "--out", tmp_path, json_output=False)
    f = funnel.paper_figure(figure, quick=True, threads=1)
    assert f["csv"] == (tmp_path / figure / f"{figure}.csv").read_text()
    meta = json.loads((tmp_path / figure / f"{figure}.json").read_text())
    assert f["check"] == meta["check"]
    assert f["id"] == figure and f["title"] == meta["title"]


def test_the_closed_figure_names_its_columns_as_funnel_closed_does():
    f = funnel.paper_figure("fig11", quick=True)
    c = f["columns"]
    assert list(c) == ["panel", "mu", "release", "state", "x_last_over_L", "x_prev_over_L"]
    assert set(c["state"]) <= {"periodic", "rest", "undecided"}
    periodic = np.array(c["state"]) == "periodic"
    # The period-2 orbit's two collision points are mirror images about the axis.
    np.testing.assert_allclose(c["x_last_over_L"][periodic], -c["x_prev_over_L"][periodic], atol=1e-6)
    assert f["check"]["holds"]
    closed = funnel.closed(samples=50, mu=1.0)
    assert {"x_last_over_L", "x_prev_over_L"} <= set(closed)


def test_a_definition_path_and_bad_figures(tmp_path):
    f = funnel.paper_figure(funnel._api._paper_dir() + "/fig01.toml")
    assert f["id"] == "fig01" and f["check"]["holds"]
    with pytest.raises(ValueError, match="invalid figure = 'fig99'.*valid: fig01"):
        funnel.paper_figure("fig99")
    bad = tmp_path / "figbad.toml"
    bad.write_text('figure = "figbad"\nkind = "nonsense"\ntitle = "t"\ncaption = "c"\n')
    with pytest.raises(ValueError, match="invalid kind = 'nonsense': valid kinds are theta_sweep"):
        funnel.paper_figure(bad)
    with pytest.raises(ValueError, match="invalid threads = -1"):
        funnel.paper_figure("fig01", threads=-1)


def test_paper_figure_is_exported_like_every_public_function():
    # It was importable as funnel.paper_figure but missing from __all__ (so from "from funnel
    # import *") and from the package's list of functions.
    import types
    public = {name for name, value in vars(funnel).items()
              if not name.startswith("_") and not isinstance(value, types.ModuleType)}
    assert public == set(funnel.__all__)
    assert ":func:`paper_figure`" in funnel.__doc__
