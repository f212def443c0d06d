"""The Python API against the command line (same numbers, bit for bit), its errors, its arrays."""

import contextlib
import csv
import math

import numpy as np
import pytest

import funnel

EVENT_FLOATS = ("time", "x", "y", "u_before", "v_before", "omega_before", "u_after", "v_after", "omega_after",
                "slip_before", "j_n", "j_t", "energy_lost")
EVENT_TEXTS = ("kind", "wall", "regime")
TRAJECTORY_KEYS = ("status", "duration", "impulse", "normal_impulse", "energy_loss", "collisions",
                   "edge_collisions", "face_collisions", "contacts", "contact_time")


def cli_options(model):
    """--name value pairs of the command line for Python keyword arguments."""
    args = []
    for name, value in model.items():
        args += [f"--{name.replace('_', '-')}", repr(value)]
    return args


# ---------------------------------------------------------------------------------------------
# Same numbers as the command line

TRAJECTORY_CASES = [
    dict(release=0.3, model=dict(theta=60.0)),
    dict(release=-0.5, model=dict(theta=40.0, mu=0.2, beta0=0.31)),
    dict(release=0.77, model=dict(theta=46.0, e=0.9, beta0=-0.31, inertia=2 / 3)),
    dict(release=0.2, model=dict(theta=50.0, e=0.8, gap=0.0)),  # closed funnel: ends at rest
    dict(release=0.1, model=dict(theta=20.0, radius=0.02, gap=0.1)),
    dict(release=0.45, model=dict(theta=70.0, e=0.3)),  # collapse into sustained contact
    dict(release=0.3, model=dict(theta=60.0, t_max=5.0)),  # stopped by the time cap
    dict(release=0.3, model=dict(theta=60.0, max_collisions=7)),
]


@pytest.mark.parametrize("case", TRAJECTORY_CASES)
def test_simulate_matches_cli(cli, case):
    # The case with a cap of 7 collisions ends there, inside the funnel, which is warned of.
    capped = "max_collisions" in case["model"]
    with pytest.warns(funnel.CappedWarning) if capped else contextlib.nullcontext():
        py = funnel.simulate(release=case["release"], events=True, **case["model"])
    ref = cli("trajectory", "--release", repr(case["release"]), "--events", *cli_options(case["model"]))
    assert py["params"] == ref["params"]
    for key in ("release", "x0", "y0") + TRAJECTORY_KEYS:
        assert py[key] == ref[key], key
    events = py["events"]
    assert len(events["time"]) == len(ref["events"])
    for i, ev in enumerate(ref["events"]):
        for key in EVENT_FLOATS:
            assert events[key][i] == ev[key], (i, key)
        for key in EVENT_TEXTS:
            assert events[key][i] == (ev[key] if ev[key] is not None else "none"), (i, key)


@pytest.mark.parametrize("dist", ["line", "disk"])
def test_ensemble_matches_cli(cli, dist):
    model = dict(theta=46.0, mu=0.5, beta0=0.31)
    py = funnel.ensemble(samples=301, release_dist=dist, per_sample=True, **model)
    ref = cli("ensemble", "--samples", 301, "--release-dist", dist, "--per-sample", *cli_options(model))
    del ref["provenance"]
    per_sample = py.pop("per_sample")
    ref_per_sample = ref.pop("per_sample")
    assert py == ref
    assert list(per_sample) == list(ref_per_sample)
    for key, values in ref_per_sample.items():
        assert per_sample[key].tolist() == values, key


def test_sweep_matches_cli(cli, tmp_path):
    out = tmp_path / "sweep.csv"
    cli("sweep", "--theta", "30:60:15", "--mu", "0,1", "--e", "0.95", "--samples", 64, "--out", out, json_output=False)
    py = funnel.sweep(theta="30:60:15", mu=[0, 1], e=0.95, samples=64)
    with open(out, newline="") as f:
        rows = list(csv.reader(f))
    header, rows = rows[0], rows[1:]
    assert list(py) == header
    assert all(len(values) == len(rows) == 6 for values in py.values())
    for j, name in enumerate(header):
        for i, row in enumerate(rows):
            value = py[name][i]
            expected = row[j] if isinstance(value, str) else type(value.item())(float(row[j]))
            assert value == expected, (name, i)


@pytest.mark.parametrize("model", [
    dict(theta=95), dict(theta=0), dict(theta=90), dict(e=1.5), dict(e=-0.1), dict(mu=-1), dict(beta0=1.5),
    dict(radius=0), dict(radius=1), dict(gap=0.01), dict(gap=-1), dict(inertia=0), dict(t_max=0),
    dict(t_max=-1), dict(max_collisions=0), dict(theta=80, radius=0.5, gap=0),
])
def test_invalid_parameters_raise_the_cli_message(cli, model):
    proc = cli("trajectory", "--release", "0.3", *cli_options(model), check=False)
    assert proc.returncode == 2
    message = proc.stderr.strip().removeprefix("funnel: error: ")
    for call in (lambda: funnel.simulate(release=0.3, **model), lambda: funnel.ensemble(samples=4, **model),
                 lambda: funnel.geometry(**model), lambda: funnel.sweep(samples=4, **model)):
        with pytest.raises(ValueError) as err:
            call()
        assert str(err.value) == message


def test_invalid_sweep_values_raise_the_cli_message(cli, tmp_path):
    for args, kwargs in ((["--theta", "5:1:1"], dict(theta="5:1:1")), (["--theta", "10,95"], dict(theta=[10, 95])),
                         (["--mu", "1,x"], dict(mu="1,x"))):
        proc = cli("sweep", *args, "--samples", 4, "--out", tmp_path / "s.csv", check=False)
        assert proc.returncode == 2
        with pytest.raises(ValueError) as err:
            funnel.sweep(samples=4, **kwargs)
        assert str(err.value) == proc.stderr.strip().removeprefix("funnel: error: ")


# ---------------------------------------------------------------------------------------------
# Errors of the Python layer

def test_library_messages_for_non_finite_values():
    with pytest.raises(ValueError, match=r"^invalid theta = nan: valid range is 0 < theta < 90 \(degrees\)$"):
        funnel.simulate(release=0.3, theta=math.nan)
    with pytest.raises(ValueError, match=r"^invalid mu = inf: valid range is mu >= 0 \(finite\)$"):
        funnel.ensemble(samples=4, mu=math.inf)
    with pytest.raises(ValueError, match=r"^invalid max-collisions = 1.5: valid range is 1 <= max-collisions < 9e18 \(an integer\)$"):
        funnel.simulate(release=0.3, max_collisions=1.5)


@pytest.mark.parametrize("release", [-1.0, 1.0, 1.5, math.nan])
def test_release_outside_the_line_is_rejected(release):
    with pytest.raises(ValueError, match=r"valid range is -1 < release < 1 \(x0/L\)"):
        funnel.simulate(release=release)


def test_ensemble_options_are_checked():
    with pytest.raises(ValueError, match="invalid samples = 0"):
        funnel.ensemble(samples=0)
    with pytest.raises(ValueError, match="invalid release_dist = 'cone': valid values are line, disk"):
        funnel.ensemble(samples=4, release_dist="cone")
    with pytest.raises(ValueError, match="invalid threads = -1"):
        funnel.sweep(samples=4, threads=-1)
    with pytest.raises(ValueError, match="not an integer"):
        funnel.ensemble(samples=4.5)
    with pytest.raises(ValueError, match="no values"):
        funnel.sweep(samples=4, theta=[])
    with pytest.raises(ValueError, match="one-dimensional"):
        funnel.sweep(samples=4, theta=np.ones((2, 2)))
    # An integer beyond the doubles names its parameter (a bare OverflowError did not).
    with pytest.raises(ValueError, match=r"^invalid theta = 1\.0000e\+400: out of range \(beyond the largest double\); valid range is 0 < theta < 90"):
        funnel.simulate(0.3, theta=10**400)
    with pytest.raises(ValueError, match=r"^invalid theta = 1\.0000e\+400: out of range"):
        funnel.sweep(samples=4, theta=[40, 10**400])


def test_wrong_keywords_and_types_raise_type_error():
    with pytest.raises(TypeError, match="unexpected keyword argument 'angle'"):
        funnel.simulate(release=0.3, angle=60)
    with pytest.raises(TypeError, match="unexpected keyword argument 't-max'"):
        funnel.ensemble(samples=4, **{"t-max": 5})
    with pytest.raises(TypeError, match="theta must be a real number"):
        funnel.simulate(release=0.3, theta="60")
    with pytest.raises(TypeError, match="e must be a real number"):
        funnel.geometry(e=True)
    with pytest.raises(TypeError, match="theta must be a real number, not ndarray"):
        funnel.simulate(release=0.3, theta=np.array([60.0]))
    with pytest.raises(TypeError, match="e must be a real number, not ndarray"):
        funnel.geometry(e=np.array(True))


def test_zero_dimensional_arrays_are_their_numbers():
    # np.array(60.0) is the number 60 (as numpy treats it): the same bits as the float.
    a = funnel.simulate(release=np.array(0.3), theta=np.array(60.0), mu=np.array(1))
    b = funnel.simulate(release=0.3, theta=60.0, mu=1)
    assert a["duration"] == b["duration"] and a["collisions"] == b["collisions"]
    assert funnel.ensemble(samples=np.array(40), theta=np.array(50))["samples"] == 40


# ---------------------------------------------------------------------------------------------
# Shapes, dtypes and contents

def test_simulate_result_and_event_arrays():
    r = funnel.simulate(release=0.3, theta=60, events=True)
    assert set(TRAJECTORY_KEYS) <= set(r)
    assert isinstance(r["duration"], float) and isinstance(r["collisions"], int)
    events = r["events"]
    assert list(events) == ["time", "kind", "wall", "x", "y", "u_before", "v_before", "omega_before", "u_after",
                            "v_after", "omega_after", "slip_before", "regime", "j_n", "j_t", "energy_lost"]
    n = len(events["time"])
    for key in EVENT_FLOATS:
        assert events[key].dtype == np.float64 and events[key].shape == (n,), key
    for key in EVENT_TEXTS:
        assert events[key].dtype.kind == "U" and events[key].shape == (n,), key
    kinds = events["kind"]
    assert np.count_nonzero((kinds == "face") | (kinds == "edge")) == r["collisions"]
    assert np.count_nonzero(kinds == "edge") == r["edge_collisions"]
    assert kinds[-1] == "exit" and events["wall"][-1] == "none"
    assert events["time"][-1] == r["duration"]
    assert np.all(np.diff(events["time"]) >= 0)
    assert math.isclose(events["energy_lost"].sum(), r["energy_loss"], rel_tol=1e-9)
    assert "events" not in funnel.simulate(release=0.3, theta=60)


def test_ensemble_result_and_per_sample_arrays():
    r = funnel.ensemble(samples=50, theta=50, per_sample=True)
    for obs in funnel.OBSERVABLES:
        assert set(r[obs]) == set(funnel.STATISTICS)
    assert sum(r["status_counts"].values()) == 50
    ps = r["per_sample"]
    for key in ("release", "duration", "impulse", "normal_impulse", "energy_loss", "contact_time"):
        assert ps[key].dtype == np.float64 and ps[key].shape == (50,), key
    for key in ("collisions", "edge_collisions", "face_collisions", "contacts"):
        assert ps[key].dtype == np.int64 and ps[key].shape == (50,), key
    assert ps["status"].dtype.kind == "U" and ps["status"].shape == (50,)
    k = np.arange(50)
    np.testing.assert_allclose(ps["release"], -1 + (2 * k + 1) / 50, rtol=0, atol=1e-15)
    assert ps["duration"].mean() == pytest.approx(r["duration"]["mean"], rel=1e-12)
    assert ps["collisions"].sum() == r["total_collisions"]
    assert "per_sample" not in funnel.ensemble(samples=5)


def test_sweep_columns_dtypes_and_grid_order():
    s = funnel.sweep(mu=np.array([0.0, 1.0]), theta=(40, 50, 60), samples=8)
    n = 6
    assert list(s)[:18] == ["theta", "e", "mu", "beta0", "radius", "gap", "inertia", "t_max", "max_collisions",
                            "release_height", "release_u", "release_v", "release_spin", "theta_left", "theta_right",
                            "spout_length", "release_dist", "samples"]
    assert list(s)[-4:] == ["exited", "rest", "trapped", "total_collisions"]
    for name, values in s.items():
        assert values.shape == (n,), name
        if name in ("max_collisions", "samples", "exited", "rest", "trapped", "total_collisions"):
            assert values.dtype == np.int64, name
        elif name == "release_dist":
            assert values.dtype.kind == "U"
        else:
            assert values.dtype == np.float64, name
    # theta varies slowest, as in `funnel sweep`, whatever the keyword order
    np.testing.assert_array_equal(s["theta"], [40, 40, 50, 50, 60, 60])
    np.testing.assert_array_equal(s["mu"], [0, 1, 0, 1, 0, 1])
    assert np.all(s["e"] == 0.99)


def test_sweep_axis_forms():
    assert len(funnel.sweep(theta="5:85:0.5", samples=1, max_collisions=1)["theta"]) == 161
    assert funnel.sweep(theta="5:85:0.5", samples=1, max_collisions=1)["theta"][-1] == 85.0
    assert funnel.sweep(theta="30,40", samples=1)["theta"].tolist() == [30.0, 40.0]
    assert funnel.sweep(theta=np.int64(30), samples=1)["theta"].tolist() == [30.0]
    assert funnel.sweep(theta=np.arange(30, 50, 10), samples=1)["theta"].tolist() == [30.0, 40.0]
    assert funnel.sweep(max_collisions=[10, 1e8], samples=1)["max_collisions"].tolist() == [10, 100000000]


def test_sweep_equals_its_ensembles():
    s = funnel.sweep(theta=[44, 46], beta0=[0, 0.31], samples=40)
    for i in range(4):
        r = funnel.ensemble(samples=40, theta=s["theta"][i], beta0=s["beta0"][i])
        for obs in funnel.OBSERVABLES:
            for stat in funnel.STATISTICS:
                assert s[f"{obs}_{stat}"][i] == r[obs][stat]
        assert s["exited"][i] == r["status_counts"]["exited"]


def test_geometry():
    g = funnel.geometry(theta=60, radius=0.02, gap=0.1)
    t = math.radians(60)
    assert g["theta"] == 60 and g["radius"] == 0.02 and g["half_gap"] == 0.05 and not g["closed"]
    assert g["sin_t"] == pytest.approx(math.sin(t)) and g["cos_t"] == pytest.approx(math.cos(t))
    assert g["y_release"] == pytest.approx(g["y_bottom"] + 1, abs=1e-15)
    assert g["half_width"] == pytest.approx(g["y_release"] / g["tan_t"])
    # The edge point (d/2, y_b) lies at distance a outside the right centre line y = x tan(theta).
    assert -g["half_gap"] * g["sin_t"] + g["y_bottom"] * g["cos_t"] == pytest.approx(-0.02)
    assert funnel.geometry(gap=0)["closed"]
    r = funnel.simulate(release=0.25, theta=60, radius=0.02, gap=0.1)
    assert r["x0"] == 0.25 * g["half_width"] and r["y0"] == g["y_release"]


def test_defaults_and_metadata():
    d = funnel.default_params()
    assert d["theta"] == 60 and d["e"] == 0.99 and d["max_collisions"] == 100_000_000
    assert funnel.simulate(release=0.3)["params"] == d
    assert funnel.valid_range("theta") == "0 < theta < 90 (degrees)"
    assert funnel.valid_range("t_max") == "t-max > 0 (finite)"
    # Every name the refusal lists has a range, the 3D-only ones too.
    with pytest.raises(ValueError) as refused:
        funnel.valid_range("bogus")
    listed = str(refused.value).split("valid names are ")[1].split(", ")
    assert set(funnel.MODEL_PARAMETERS + funnel.MODEL_PARAMETERS_3D_ONLY) <= set(listed)
    assert all(funnel.valid_range(n) for n in listed)
    assert funnel.version() == funnel.__version__
    assert isinstance(funnel.git_commit(), str) and funnel.git_commit()


# ---------------------------------------------------------------------------------------------
# Determinism

def test_simulate_is_deterministic():
    a = funnel.simulate(release=-0.41, theta=47, events=True)
    b = funnel.simulate(release=-0.41, theta=47, events=True)
    assert a["duration"] == b["duration"]
    for key in EVENT_FLOATS:
        np.testing.assert_array_equal(a["events"][key], b["events"][key])


@pytest.mark.parametrize("dist", ["line", "disk"])
def test_ensemble_is_identical_for_any_thread_count(dist):
    one = funnel.ensemble(samples=201, theta=55, release_dist=dist, threads=1, per_sample=True)
    many = funnel.ensemble(samples=201, theta=55, release_dist=dist, threads=3, per_sample=True)
    ps_one, ps_many = one.pop("per_sample"), many.pop("per_sample")
    assert one == many
    for key in ps_one:
        np.testing.assert_array_equal(ps_one[key], ps_many[key])


def test_mirror_release_gives_mirror_trajectory():
    a = funnel.simulate(release=0.37, theta=52, events=True)
    b = funnel.simulate(release=-0.37, theta=52, events=True)
    assert a["duration"] == b["duration"] and a["collisions"] == b["collisions"]
    np.testing.assert_array_equal(a["events"]["x"], -b["events"]["x"])


def test_runs_ended_by_the_collision_cap_are_counted_and_warn():
    # A trajectory trapped at its 5th collision, far short of t_max: said, as the CLI says it.
    with pytest.warns(funnel.CappedWarning, match=r"^the run reached max_collisions \(5\) inside the funnel"):
        r = funnel.simulate(release=0.3, theta=60, max_collisions=5)
    assert r["status"] == "trapped" and r["collisions"] == 5 and r["duration"] < 10
    with pytest.warns(funnel.CappedWarning, match=r"^the run reached max_collisions \(5\)"):
        funnel.simulate(release=0.3, theta=60, max_collisions=5, space="3d")
    # Ensembles count them among the trapped (2D: mirror images included), as the CLI's JSON.
    for space in ("2d", "3d"):
        with pytest.warns(funnel.CappedWarning, match=r"^\d+ of 100 runs reached max_collisions \(50\)") as caught:
            e = funnel.ensemble(samples=100, theta=60, max_collisions=50, space=space)
        assert 50 < e["capped"] <= e["status_counts"]["trapped"], space
        assert e["stalled"] == 0
        assert str(caught[0].message).startswith(f"{e['capped']} of 100 runs"), space
    # A sweep sums them over its grid (its columns stay the CLI's CSV's); a cap that varies over
    # the grid is not quoted.
    for space in ("2d", "3d"):
        with pytest.warns(funnel.CappedWarning, match=r"^\d+ of 20 runs reached max_collisions \(50\)"):
            s = funnel.sweep(samples=10, theta=[50, 60], max_collisions=50, space=space)
        assert "_capped" not in s
    with pytest.warns(funnel.CappedWarning, match=r"^40 of 40 runs reached max_collisions inside"):
        funnel.sweep(samples=10, theta=[50, 60], max_collisions=[50, 60])
    # Under the default cap: none, and no warning (pyproject turns warnings into errors).
    e = funnel.ensemble(samples=100, theta=60)
    assert e["capped"] == 0 and e["status_counts"]["exited"] == 100
    assert funnel.simulate(release=0.3, theta=60)["status"] == "exited"
