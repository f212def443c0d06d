"""funnel.orbit and funnel.closed (paper Sec. IV, Figs. 10-12) against the command line."""

import numpy as np
import pytest

import funnel


def test_orbit_matches_cli_and_has_documented_arrays(cli):
    py = funnel.orbit("44:46:1", beta0=0.31)
    ref = cli("orbit", "--theta", "44:46:1", "--beta0", "0.31")
    assert py["theta"].tolist() == [44.0, 45.0, 46.0]
    assert py["eigenvalues"].shape == (3, 4) and py["eigenvalues"].dtype == np.complex128
    assert py["modulus"].shape == (3, 4) and py["modulus"].dtype == np.float64
    assert py["stable"].dtype == np.bool_
    for i, point in enumerate(ref["points"]):
        for k, ev in enumerate(point["eigenvalues"]):
            assert py["eigenvalues"][i, k] == complex(ev["real"], ev["imag"])
            assert py["modulus"][i, k] == ev["modulus"]
        assert bool(py["stable"][i]) == point["stable"]
        assert py["jacobian_max_rel_diff"][i] == point["jacobian_max_rel_diff"]


def test_orbit_is_stable_exactly_above_45_degrees():
    o = funnel.orbit(np.arange(5.0, 86.0, 1.0), beta0=0.0)
    above = o["theta"] > 45.0
    below = o["theta"] < 45.0
    assert o["stable"][above].all()
    assert not o["stable"][below].any()
    # One eigenvalue is 1 at every angle.
    assert np.all(np.min(np.abs(o["eigenvalues"] - 1.0), axis=1) < 1e-8)


def test_orbit_rejects_bad_input():
    with pytest.raises(ValueError, match="invalid theta = 95"):
        funnel.orbit(95.0)
    with pytest.raises(ValueError, match=r"invalid theta = 1e-08: valid range is 1e-3 <= theta < 90"):
        funnel.orbit(1e-8)
    with pytest.raises(ValueError, match="y-star"):
        funnel.orbit(60.0, y_star=-1.0)
    with pytest.raises(ValueError, match="invalid radius = 1: valid range is 1e-100 <= radius < 1"):
        funnel.orbit(60.0, radius=1.0)
    # The funnel's gap plays no part in the orbit: a radius above half the default gap is fine.
    assert funnel.orbit(60.0, radius=0.02)["stable"].all()


def test_closed_matches_cli(cli):
    py = funnel.closed(theta=50, e=1, mu=0.1, samples=60, threads=2)
    ref = cli("closed", "--theta", "50", "--e", "1", "--mu", "0.1", "--samples", "60", "--threads", "1")
    assert py["periodic_fraction"] == ref["periodic_fraction"]
    assert py["state_counts"] == ref["state_counts"]
    assert py["state"] == ref["per_sample"]["state"]
    assert py["x_last_over_L"].tolist() == ref["per_sample"]["x_last_over_L"]
    assert py["collisions"].dtype == np.int64 and py["collisions"].shape == (60,)
    # The caps it ran with, reported as funnel closed reports them.
    assert py["options"] == ref["options"]
    for key in ("t_max", "max_collisions"):
        assert py["params"][key] == ref["params"][key]


def test_closed_reports_the_caps_it_used():
    c = funnel.closed(theta=50, e=1, mu=0.01, samples=8, t_max=50.0, max_coll=123456)
    assert c["params"]["t_max"] == 50.0 and c["options"]["max_time"] == 50.0
    assert c["params"]["max_collisions"] == 123456 and c["options"]["max_collisions"] == 123456
    assert c["time"].max() <= 50.0
    with pytest.raises(ValueError, match="invalid max_time = inf: valid range is max_time > 0"):
        funnel.closed(theta=50, samples=8, max_time=float("inf"))
    # The collision cap is named as given, with the range it is checked against.
    for name in ("max_coll", "max_collisions"):
        with pytest.raises(ValueError, match=rf"^invalid {name} = 10000000000000000000: valid range is an integer "
                                             rf"1 <= {name} < 9e18$"):
            funnel.closed(theta=50, samples=8, **{name: 10**19})
    with pytest.raises(ValueError, match=r"^invalid t_max = 1\.0000e\+400: out of range"):
        funnel.closed(theta=50, samples=8, t_max=10**400)


def test_closed_takes_the_releases_and_the_geometry_funnel_closed_takes(cli, tmp_path):
    # seed, release and release_sd as funnel closed's --seed, --release, --release-sd (they were
    # missing: uniform and gaussian releases were stuck at seed 1, mean 0, sd 0.1).
    for dist, extra, args in (("uniform", {"seed": 7}, ["--seed", "7"]),
                              ("gaussian", {"seed": 3, "release": 0.2, "release_sd": 0.05},
                               ["--seed", "3", "--release", "0.2", "--release-sd", "0.05"])):
        py = funnel.closed(theta=50, mu=0.1, samples=30, release_dist=dist, **extra)
        ref = cli("closed", "--theta", "50", "--mu", "0.1", "--samples", "30", "--release-dist", dist, *args)
        assert py["release"].tolist() == ref["per_sample"]["release"], dist
        assert py["state"] == ref["per_sample"]["state"], dist
        assert py["seed"] == extra["seed"] and py["release_dist"] == dist
        # The same record on both sides (the CLI's lacked the seed, Python's the sample count).
        assert ref["seed"] == py["seed"] and ref["samples"] == py["samples"] == 30
        if dist == "gaussian":  # its mean beside the column of the releases
            assert py["release_mean"] == ref["release_mean"] == 0.2 and py["release_sd"] == ref["release_sd"] == 0.05
    other = funnel.closed(theta=50, mu=0.1, samples=30, release_dist="uniform", seed=8)
    assert other["release"].tolist() != funnel.closed(theta=50, mu=0.1, samples=30, release_dist="uniform",
                                                      seed=7)["release"].tolist()
    with pytest.raises(ValueError, match="release_dist \"gaussian\" only"):
        funnel.closed(samples=4, release=0.2)
    # A closed geometry (both walls end at one point), as funnel closed --geometry.
    walls = {"mirror": True, "left": {"vertices": [[-1.2, 1.4], [-0.4, 0.7], [0.0, 0.0]]}}
    path = tmp_path / "closed.toml"
    path.write_text("mirror = true\n[left]\nvertices = [[-1.2, 1.4], [-0.4, 0.7], [0.0, 0.0]]\n")
    py = funnel.closed(samples=20, mu=0.1, geometry=walls)
    ref = cli("closed", "--samples", "20", "--mu", "0.1", "--geometry", str(path))
    assert py["state"] == ref["per_sample"]["state"]
    assert py["geometry"]["walls"] == ref["geometry"]["walls"]
    with pytest.raises(ValueError, match="closed funnel"):
        funnel.closed(samples=4, geometry={"mirror": True, "left": {"vertices": [[-1, 1], [-0.1, 0]]}})
    # One cap, one name.
    with pytest.raises(ValueError, match="invalid t_max = 20: valid range is one of t_max and max_time"):
        funnel.closed(samples=4, t_max=20, max_time=30)
    with pytest.raises(ValueError, match="invalid t_max = -1: valid range is t_max > 0"):
        funnel.closed(samples=4, t_max=-1)


def test_ctrl_c_interrupts_closed(ctrl_c):
    ctrl_c(lambda: funnel.closed(samples=400000, theta=50, mu=0.01, threads=2))  # about 14 s uninterrupted


def test_closed_fraction_grows_with_friction_and_rejects_a_gap():
    low = funnel.closed(theta=50, e=1, mu=0.01, samples=200)["periodic_fraction"]
    high = funnel.closed(theta=50, e=1, mu=1.0, samples=200)["periodic_fraction"]
    assert low < 0.6 < 0.98 < high
    with pytest.raises(ValueError, match="gap"):
        funnel.closed(gap=0.04, samples=10)
