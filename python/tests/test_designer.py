"""The designer's outputs in Python: exit state, wear, release control, random ensembles,
progress and interruption."""

import math
import signal
import time

import numpy as np
import pytest

import funnel


def test_exit_state_balances_the_energy_and_is_none_when_trapped():
    r = funnel.simulate(release=-0.4, theta=50, e=0.9, mu=0.5, release_spin=3.0)
    assert r["status"] == "exited"
    g = funnel.geometry(theta=50)
    kinetic = 0.5 * (r["exit_u"] ** 2 + r["exit_v"] ** 2) + 0.5 * 0.4 * 0.01**2 * r["exit_spin"] ** 2
    e0 = g["y_release"] + 0.5 * 0.4 * 0.01**2 * 3.0**2
    assert kinetic + g["y_bottom"] == pytest.approx(e0 - r["energy_loss"], rel=1e-12)
    assert r["exit_speed"] == pytest.approx(math.hypot(r["exit_u"], r["exit_v"]), rel=1e-15)
    trapped = funnel.simulate(release=0.3, t_max=1.0)
    assert trapped["status"] == "trapped" and trapped["exit_speed"] is None


def test_straight_throw_through_the_gap():
    r = funnel.simulate(release=0.0, release_v=-0.7, release_height=1.5)
    speed = math.sqrt(0.49 + 3.0)
    assert r["duration"] == pytest.approx(speed - 0.7, rel=1e-14)
    assert r["exit_speed"] == pytest.approx(speed, rel=1e-14)
    assert r["collisions"] == 0


def test_wear_arrays_sum_to_the_totals():
    r = funnel.simulate(release=0.55, theta=35, e=0.4, wear_bins=9)
    w = r["wear"]
    assert w["left"]["impulse"].shape == (9,) and w["left"]["s"][0] == pytest.approx(w["bin_width"] / 2)
    total = sum(w[s]["impulse"].sum() + w[s]["edge"]["impulse"] for s in ("left", "right"))
    assert total == pytest.approx(r["impulse"], rel=1e-12)
    e = funnel.ensemble(samples=200, theta=60, wear_bins=5)
    normal = sum(e["wear"][s]["normal_impulse"].sum() + e["wear"][s]["edge"]["normal_impulse"]
                 for s in ("left", "right"))
    assert normal == pytest.approx(e["normal_impulse"]["mean"], rel=1e-12)


def test_each_wall_of_an_asymmetric_funnel_is_binned_over_its_own_length():
    # 30 and 70 degrees: walls 1/sin(30) and 1/sin(70) long up to the release height.
    w = funnel.ensemble(samples=40, theta_left=30, theta_right=70, wear_bins=10)["wear"]
    for side, angle in (("left", 30), ("right", 70)):
        length = 1 / math.sin(math.radians(angle))
        assert w[side]["bin_width"] * 10 == pytest.approx(length, rel=1e-12), side
        assert w[side]["s"][-1] == pytest.approx(0.95 * length, rel=1e-12), side
    assert w["bin_width"] == w["left"]["bin_width"]


def test_random_ensembles_do_not_depend_on_threads_and_match_the_cli(cli):
    kw = dict(samples=150, release_dist="gaussian", release=0.1, release_sd=0.4, velocity_sd=0.02, seed=11, theta=48)
    a = funnel.ensemble(threads=1, **kw)
    b = funnel.ensemble(threads=2, **kw)
    assert a == b
    assert a["seed"] == 11 and a["simulated_collisions"] == a["total_collisions"]
    ref = cli("ensemble", "--samples", 150, "--release-dist", "gaussian", "--release", 0.1, "--release-sd", 0.4,
              "--velocity-sd", 0.02, "--seed", 11, "--theta", 48)
    del ref["provenance"]
    assert a == ref
    ps = funnel.ensemble(per_sample=True, **kw)["per_sample"]
    assert np.all(np.abs(ps["release"]) < 1) and np.std(ps["u0"]) > 0


def test_bad_options_raise_with_the_library_message():
    with pytest.raises(ValueError, match=r"^invalid release-sd = 0: valid range is 0 < release-sd <= 10"):
        funnel.ensemble(release_dist="gaussian", release_sd=0.0)
    with pytest.raises(ValueError, match=r"^invalid seed = -1"):
        funnel.ensemble(seed=-1)
    with pytest.raises(ValueError, match=r"^invalid release-height = -1"):
        funnel.simulate(release=0.0, release_height=-1.0)
    with pytest.raises(ValueError, match=r"^invalid wear-bins = -3"):
        funnel.simulate(release=0.0, wear_bins=-3)


def test_a_seed_where_nothing_is_random_is_refused_as_on_the_command_line():
    # Python took seed=5 with line releases and ran seed 1's ensemble: two seeds, one sample.
    refusal = r"^invalid seed = 5: valid range is an integer 0 <= seed < 2\^64, with random releases or velocities only"
    with pytest.raises(ValueError, match=r"^invalid seed = 5: .* with random releases only \(release_dist"):
        funnel.closed(theta=50, samples=20, seed=5)  # closed() has no random velocities
    for run in (lambda: funnel.ensemble(samples=20, seed=5), lambda: funnel.sweep(theta=[40, 50], samples=20, seed=5)):
        with pytest.raises(ValueError, match=refusal):
            run()
    assert "seed" not in funnel.ensemble(samples=20)
    for run in (lambda: funnel.ensemble(samples=20, seed=5, space="3d", t_max=20),
                lambda: funnel.sweep(theta=50, samples=20, seed=5, space="3d", t_max=20)):
        with pytest.raises(ValueError, match=r"with random velocities only \(velocity_sd > 0: in 3d the releases are line or disk"):
            run()
    with pytest.raises(ValueError, match=r"^invalid release_dist = 'Uniform'"):  # the distribution, not the seed
        funnel.ensemble(samples=20, release_dist="Uniform", seed=3)
    # Where something is drawn, the seed keys it: None is seed 1.
    a = funnel.ensemble(samples=40, release_dist="uniform", per_sample=True)
    b = funnel.ensemble(samples=40, release_dist="uniform", seed=1, per_sample=True)
    c = funnel.ensemble(samples=40, release_dist="uniform", seed=2, per_sample=True)
    assert a["seed"] == 1 and a["per_sample"]["release"].tobytes() == b["per_sample"]["release"].tobytes()
    assert c["seed"] == 2 and c["per_sample"]["release"].tobytes() != a["per_sample"]["release"].tobytes()
    assert funnel.ensemble(samples=20, velocity_sd=0.01, seed=5)["seed"] == 5


def test_theta_with_both_walls_angles_and_disk_releases_in_an_asymmetric_funnel_are_refused():
    both = r"^invalid theta = 40: valid range is not with both theta-left and theta-right"
    with pytest.raises(ValueError, match=both):
        funnel.ensemble(samples=20, theta=40, theta_left=30, theta_right=35)
    with pytest.raises(ValueError, match=both):
        funnel.sweep(samples=20, theta=[40, 50], theta_left=30, theta_right=35)
    assert funnel.ensemble(samples=20, theta_left=30, theta_right=35)["params"]["theta"] is None
    assert np.isnan(funnel.sweep(samples=20, theta_left=[30, 40], theta_right=35)["theta"]).all()
    disk = r"^invalid release-dist = disk: valid range is line, uniform or gaussian in a funnel that is not mirror symmetric"
    for run in (lambda: funnel.ensemble(samples=20, release_dist="disk", theta_right=50),
                lambda: funnel.sweep(samples=20, release_dist="disk", theta_left=[40, 50]),
                lambda: funnel.closed(samples=20, release_dist="disk", theta_right=50)):
        with pytest.raises(ValueError, match=disk):
            run()
    assert funnel.ensemble(samples=20, release_dist="disk", theta_left=50, theta_right=50)["samples"] == 20


def test_progress_reports_every_work_unit():
    seen = []
    funnel.ensemble(samples=400, progress=lambda done, total: seen.append((done, total)))
    assert seen and seen[-1][0] == seen[-1][1] and [d for d, _ in seen] == sorted(d for d, _ in seen)
    funnel.sweep(theta=[40, 50], samples=50, progress=True)  # tqdm or a text line, never an error


def test_ctrl_c_interrupts_a_long_ensemble():
    def interrupt(done, total):
        signal.raise_signal(signal.SIGINT)

    start = time.monotonic()
    with pytest.raises(KeyboardInterrupt):
        funnel.ensemble(samples=2_000_000, theta=46, threads=1, progress=interrupt)
    assert time.monotonic() - start < 30  # the whole run takes minutes


@pytest.mark.parametrize("run", ["ensemble", "sweep"])
def test_ctrl_c_stops_the_chunk_under_way(run):
    # 5e6 elastic frictionless releases: a chunk (a 256th of them) ran to its end before Ctrl-C
    # was raised, about 10 s here; the lanes now stop at their next round.
    import threading
    timer = threading.Timer(0.5, signal.raise_signal, (signal.SIGINT,))
    timer.start()
    try:
        with pytest.raises(KeyboardInterrupt):
            start = time.monotonic()
            getattr(funnel, run)(samples=5_000_000, theta=46, e=1, mu=0, threads=1)
    finally:
        timer.cancel()
    assert time.monotonic() - start < 5  # 0.03 s after the signal on the development machine


@pytest.mark.parametrize("space", ["2d", "3d"])
def test_ctrl_c_interrupts_one_endless_trajectory(space):
    # An elastic frictionless ball bouncing for t_max = 1e9 (hundreds of millions of collisions):
    # simulate() could not be interrupted at all.
    import threading
    timer = threading.Timer(0.3, signal.raise_signal, (signal.SIGINT,))
    start = time.monotonic()
    timer.start()
    try:
        with pytest.raises(KeyboardInterrupt):
            funnel.simulate(0.3, space=space, theta=46, e=1, mu=0, t_max=1e9, max_collisions=8e18)
    finally:
        timer.cancel()
    assert time.monotonic() - start < 30  # the whole run takes hours
    # Without Ctrl-C the same call, shorter, is the same trajectory with and without its events.
    quiet = funnel.simulate(0.3, space=space, theta=46, e=1, mu=0, t_max=2e3)
    logged = funnel.simulate(0.3, space=space, theta=46, e=1, mu=0, t_max=2e3, events=True)
    assert quiet["duration"] == logged["duration"] and quiet["collisions"] == logged["collisions"] > 1000


def test_the_tables_describe_every_parameter_and_observable():
    keys = [p["key"] for p in funnel.PARAMETERS if p["option"]]
    assert list(keys) == list(funnel.MODEL_PARAMETERS)
    assert "release_height" in keys and "exit_speed" in funnel.OBSERVABLES
    assert all(p["range"] for p in funnel.PARAMETERS)
    r = funnel.simulate(release=0.2)
    assert all(o["name"] in r for o in funnel.OBSERVABLE_TABLE)


def test_the_wear_figure_is_made_and_drawn(cli, tmp_path):
    import json

    from funnel import plot
    cli("paper", "--quick", "--no-plots", "--only", "figwear", "--out", tmp_path, json_output=False)
    meta = json.loads((tmp_path / "figwear" / "figwear.json").read_text())
    assert meta["check"]["holds"] is True and meta["beyond_paper"] is True
    totals = {t["theta"]: t for t in meta["totals"]}
    assert totals[46.0]["impulse_per_particle"] > 2 * totals[44.0]["impulse_per_particle"]
    assert plot.main([str(tmp_path)]) == 0
    png = tmp_path / "figwear" / "figwear.png"
    assert png.stat().st_size > 10_000
    assert "Beyond the paper" in (tmp_path / "index.html").read_text()


def test_the_gaussians_mean_and_spread_are_refused_with_another_distribution():
    with pytest.raises(ValueError, match=r"^invalid release-sd = 0.2: valid range is 0 < release-sd <= 10, with release_dist \"gaussian\" only"):
        funnel.ensemble(samples=20, release_sd=0.2)
    with pytest.raises(ValueError, match=r"^invalid release = 0.5: valid range is -1 < release < 1, with release_dist"):
        funnel.sweep(samples=20, theta=[40, 50], release_dist="uniform", release=0.5)
    with pytest.raises(ValueError, match=r"^invalid release = 0.5: valid range is -1 < release < 1, with release_dist"):
        funnel.ensemble(samples=20, space="3d", release=0.5)
    g = funnel.ensemble(samples=50, release_dist="gaussian", release=0.5, release_sd=0.2)
    assert g["release"] == 0.5 and g["release_sd"] == 0.2
    assert funnel.ensemble(samples=50, release_dist="gaussian")["release_sd"] == 0.1


def test_bad_values_found_by_an_audit_of_the_python_interface():
    # Each was accepted, changed silently, or failed with a pybind11 dump instead of the range.
    def refused(call, error, message):
        with pytest.raises(error, match=message):
            call()

    refused(lambda: funnel.sweep(samples=20, threads=1, space="3d", max_collisions=[2, 2.5]), ValueError,
            r"^invalid max-collisions = 2.5: valid range is 1 <= max-collisions < 9e18 \(an integer\)")  # ran uncapped
    refused(lambda: funnel.simulate(0.3, theta_right=math.nan), ValueError, r"^invalid theta-right = nan")  # = theta
    refused(lambda: funnel.sweep(samples=10, theta=[40, True]), TypeError, "not bool")  # ran at 1 degree
    refused(lambda: funnel.closed(samples=20, threads=-1), ValueError, r"^invalid threads = -1: valid range")
    refused(lambda: funnel.closed(samples=20, window=10**7), ValueError, r"^invalid window = 10000000")
    refused(lambda: funnel.closed(samples=20, slip_tol=math.inf), ValueError, r"^invalid slip_tol = inf")
    refused(lambda: funnel.orbit([]), ValueError, r"^invalid theta: no values")
    refused(lambda: funnel.orbit(45, y_star=math.inf), ValueError, r"^invalid y-star = inf")
    refused(lambda: funnel.paper_figure("fig10", quick=True, threads=1025), ValueError, r"^invalid threads = 1025")
    refused(lambda: funnel.valid_range("bogus"), ValueError, r"^invalid name = 'bogus'")
    refused(lambda: funnel.ensemble(samples=2**63), ValueError, r"^invalid samples = 9223372036854775808: valid range")
    refused(lambda: funnel.ensemble(samples=1.5), ValueError, r"^invalid samples = 1.5: not an integer; valid range")
    refused(lambda: funnel.sweep(samples=10, threads=1, theta="1:89:0.01", mu="0:1:0.001"), ValueError,
            r"^invalid grid: 8809801 points; valid range is at most 2e\+06 points")
    refused(lambda: funnel.geometry(geometry={"left": {"vertices": [[-1, 1], [-0.1, 0]]}, "mirror": "yes"}),
            ValueError, r"^invalid geometry mirror = 'yes': valid values are true, false")
    assert funnel.valid_range("theta") == "0 < theta < 90 (degrees)"


def test_yes_no_options_take_only_true_or_false():
    # bool() took events="no" as yes, and progress=0 showed a bar.
    with pytest.raises(TypeError, match=r"events must be True or False, not str"):
        funnel.simulate(0.3, events="no")
    with pytest.raises(TypeError, match=r"per_sample must be True or False"):
        funnel.ensemble(samples=10, per_sample=1)
    with pytest.raises(TypeError, match=r"progress must be True or False"):
        funnel.ensemble(samples=10, progress=0)
    assert "events" in funnel.simulate(0.3, events=np.bool_(True))
    assert funnel.closed(samples=8, release_dist=None)["state_counts"]  # None is the default line, as elsewhere


def test_closed_takes_a_wedge_whose_walls_set_their_own_e():
    # closed()'s default e = 1 is not a given e (it was refused: "invalid e = 1").
    wedge = {"left": {"vertices": [[-1.0, 1.2], [0.0, 0.0]], "e": 1.0, "mu": 0.5}, "mirror": True}
    r = funnel.closed(samples=4, threads=1, geometry=wedge)
    assert r["periodic_fraction"] == 1.0 and r["params"]["e"] is None
    with pytest.raises(ValueError, match=r"^invalid e = 0.5: valid range is not with a geometry"):
        funnel.closed(samples=4, e=0.5, geometry=wedge)
    assert funnel.closed(samples=4, theta=60, mu=1)["params"]["e"] == 1.0  # the V: e = 1 by default


def test_a_geometry_dict_takes_numpy_numbers():
    # np.float32(0.1) or np.int64(1) were "not a number".
    walls = {"left": {"vertices": [[np.int64(-1), 1.0], [-0.1, np.float32(0.0)]], "mu": np.float32(0.5)},
             "mirror": True}
    plain = {"left": {"vertices": [[-1, 1.0], [-0.1, 0.0]], "mu": float(np.float32(0.5))}, "mirror": True}
    assert funnel.simulate(0.3, geometry=walls)["duration"] == funnel.simulate(0.3, geometry=plain)["duration"]
    # and 0-d arrays of reals, as the model's parameters take them (numpy's arrays of vertices too)
    zero_d = {"left": {"vertices": np.array([[-1, 1.0], [-0.1, 0.0]]), "mu": np.array(np.float32(0.5))},
              "mirror": True, "bottom": np.array(0.0)}
    assert funnel.simulate(0.3, geometry=zero_d)["duration"] == funnel.simulate(0.3, geometry=plain)["duration"]
    with pytest.raises(ValueError, match=r"^invalid geometry left.mu = array\(True\): valid range is a number$"):
        funnel.simulate(0.3, geometry={"left": {"vertices": [[-1, 1], [-0.1, 0]], "mu": np.array(True)}, "mirror": True})
    with pytest.raises(ValueError, match=r"^invalid geometry left.vertices\[1\] = True: valid range is a number$"):
        funnel.simulate(0.3, geometry={"left": {"vertices": [[-1, 1], [-0.1, True]]}, "mirror": True})
    # Each names the key, the value and what is valid (they named the key only).
    for walls, message in (({"left": [[-1, 1], [-0.1, 0]], "mirror": True}, r"left = \[\[-1, 1\], \[-0.1, 0\]\]: valid range is a dict"),
                           ({"left": {"vertices": "abc"}, "mirror": True}, r"left.vertices = 'abc': valid range is a list"),
                           ({"left": {"vertices": [[-1, 1], "xy"]}, "mirror": True}, r"left.vertices\[1\] = 'xy': valid range is a pair"),
                           ({"left": {"vertices": [[-1, 1], [-0.1, 0]]}, "mirror": True, "bottom": "low"},
                            r"bottom = 'low': valid range is a number")):
        with pytest.raises(ValueError, match="^invalid geometry " + message):
            funnel.simulate(0.3, geometry=walls)


def test_a_results_params_run_again_through_model_keywords():
    # **r["params"] failed (p_c, eps_rest are no keywords; the walls' angles came with theta).
    kw = funnel.model_keywords(funnel.default_params())
    assert kw["theta"] == 60 and "p_c" not in kw and "theta_left" not in kw and "theta_right" not in kw
    for model in ({"theta": 48, "mu": 0.3}, {"theta_right": 50}, {"theta_left": 30, "theta_right": 35},
                  {"spout_length": 0.2, "e": 0.9}):
        r = funnel.ensemble(samples=40, **model)
        again = funnel.ensemble(samples=40, **funnel.model_keywords(r["params"]))
        assert again["params"] == r["params"] and again["duration"] == r["duration"], model
    r3 = funnel.simulate(0.3, space="3d", release_w=0.02, t_max=30)
    again3 = funnel.simulate(0.3, space="3d", t_max=30, **{k: v for k, v in funnel.model_keywords(r3["params"]).items()
                                                           if k != "t_max"})
    assert again3["duration"] == r3["duration"] and again3["params"] == r3["params"]
