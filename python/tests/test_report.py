"""The report's pieces: formulas as MathML, the player's embedded data, per-figure run times
from `funnel paper`, and the strict pytest configuration."""

import json
import shutil
import warnings
from pathlib import Path

import pytest

from funnel import mathml, player, report

PAPER_DIR = Path(__file__).resolve().parents[2] / "paper"


@pytest.mark.parametrize("tex,mathml_text", [
    ("x_c/L", "<msub><mi>x</mi><mi>c</mi></msub><mo>/</mo><mi>L</mi>"),
    (r"\sqrt{H/g}", "<msqrt><mrow><mi>H</mi><mo>/</mo><mi>g</mi></mrow></msqrt>"),
    (r"I = \frac{2}{5} m a^2", "<mfrac><mn>2</mn><mn>5</mn></mfrac><mi>m</mi><msup><mi>a</mi><mn>2</mn></msup>"),
    (r"\beta_0 = -0.31", "<msub><mi>β</mi><mn>0</mn></msub><mo>=</mo><mo>−</mo><mn>0.31</mn>"),
    (r"|\lambda_2|", '<mo stretchy="false">|</mo><msub><mi>λ</mi><mn>2</mn></msub><mo stretchy="false">|</mo>'),
    (r"t_\mathrm{max}^2", '<msubsup><mi>t</mi><mi mathvariant="normal">max</mi><mn>2</mn></msubsup>'),
    (r"\Delta E", '<mi mathvariant="normal">Δ</mi><mi>E</mi>'),
    ("a<b", "<mi>a</mi><mo>&lt;</mo><mi>b</mi>"),
])
def test_tex_to_mathml(tex, mathml_text):
    out = mathml.tex_to_mathml(tex)
    assert out.startswith("<math><semantics>") and mathml_text in out
    assert f'<annotation encoding="application/x-tex">' in out


def test_text_to_html_turns_formulas_and_plain_spellings_into_mathml():
    html = mathml.text_to_html("x_c/L against x0/L (β0 = 0.31, units √(H/g)) & $e = 1$; costs $5")
    assert "x_c/L" not in html.replace('x-tex">x_c/L<', "")
    assert html.count("<math>") == 5 and "&amp;" in html and "costs $5" in html
    assert mathml.text_to_html("<b>") == "&lt;b&gt;"
    assert mathml.text_to_html("fig03 in x0.5") == "fig03 in x0.5"  # no false matches


def test_parameter_names_are_symbols():
    assert "<mi>μ</mi>" in mathml.parameter_html("mu") and "<msub><mi>β</mi><mn>0</mn></msub>" in \
        mathml.parameter_html("beta0")
    assert mathml.parameter_html("release_dist") == "release_dist"


def test_every_caption_of_the_paper_renders_without_raw_tex():
    import tomllib
    for path in sorted(PAPER_DIR.glob("*.toml")):
        with open(path, "rb") as f:
            caption = tomllib.load(f)["caption"]
        html = mathml.text_to_html(caption)
        visible = "".join(part.split("</annotation>")[-1] for part in html.split("<annotation"))
        assert "$" not in visible and "\\" not in visible and "x_c" not in visible and "β0" not in visible, path.name


def test_player_json_cannot_close_its_script():
    text = player.script_json({"label": "</script><script>alert(1)</script>"})
    assert "</" not in text and json.loads(text)["label"].startswith("</script>")
    assert "</script" not in player.player_script()


def test_run_time_text():
    meta = {"run_time_s": 2.5, "run_time_basis": {"batch_time_s": 10.0, "batch_collisions": 8e6,
                                                  "figure_collisions": 2e6}}
    text = report.run_time_text(meta)
    assert text.startswith("computed in 2.5 s (its share of the 10.0 s batch") and "25%" in text
    assert report.run_time_text({"run_time_s": 0.01234}) == "computed in 0.0123 s"
    assert report.run_time_text({}) == ""


def _sweep_definition(figure, grid):
    """A θ-sweep figure definition (the schema of paper/*.toml) on a tiny grid."""
    return f"""figure = "{figure}"
kind = "theta_sweep"
title = "test"
caption = "test"
observables = ["duration"]
series = "mu"
samples = 24
release_dist = "line"

[params]
e = 0.9

[grid]
{grid}

[check]
type = "ratio_above_below"
series_value = 1
claim = "test"
"""


def test_paper_attributes_the_shared_batch_time_by_collisions(cli, tmp_path):
    defs = tmp_path / "defs"
    defs.mkdir()
    # fig03 and fig04 share all their ensembles, fig02 has its own, fig10 is no sweep at all.
    (defs / "fig02.toml").write_text(_sweep_definition("fig02", 'theta = "40:50:5"\nmu = [0.5]'), "utf-8")
    for fig in ("fig03", "fig04"):
        (defs / f"{fig}.toml").write_text(_sweep_definition(fig, 'theta = "44:48:2"\nmu = [1]'), "utf-8")
    shutil.copy(PAPER_DIR / "fig10.toml", defs / "fig10.toml")
    cli("paper", "--no-plots", "--quick", "--paper-dir", defs, "--out", tmp_path / "out", json_output=False)
    meta = {f: json.loads((tmp_path / "out" / f / f"{f}.json").read_text()) for f in ("fig02", "fig03", "fig04",
                                                                                      "fig10")}
    basis = {f: meta[f]["run_time_basis"] for f in ("fig02", "fig03", "fig04")}
    batch = basis["fig02"]["batch_collisions"]
    assert all(b["batch_collisions"] == batch and b["batch_time_s"] == basis["fig02"]["batch_time_s"]
               for b in basis.values())
    assert basis["fig03"]["figure_collisions"] == basis["fig04"]["figure_collisions"] > 0
    assert sum(b["figure_collisions"] for b in basis.values()) == pytest.approx(batch, rel=1e-12)
    for f, b in basis.items():
        share = b["figure_collisions"] / batch * b["batch_time_s"]
        assert share <= meta[f]["run_time_s"] < share + 0.5
    assert "run_time_basis" not in meta["fig10"] and meta["fig10"]["run_time_s"] >= 0


# ---------------------------------------------------------------------------------------------
# The pytest configuration (python/pyproject.toml): strict, warnings are errors

def test_warnings_are_errors():
    with pytest.raises(UserWarning):
        warnings.warn("any warning fails the suite", UserWarning)


def test_markers_and_configuration_are_strict(pytestconfig):
    assert pytestconfig.getoption("strict_markers") is True
    assert pytestconfig.getoption("strict_config") is True
    assert pytestconfig.getini("filterwarnings") == ["error"]
    assert pytestconfig.getini("xfail_strict") is True
