"""space="3d": the axisymmetric funnel from Python, against the command line and the 2D engine."""

import math

import numpy as np
import pytest

import funnel


def test_simulate_3d_matches_cli_bit_for_bit(cli):
    model = dict(theta=55.0, release_w=0.07, release_spin_x=3.0, release_spin=-2.0)
    py = funnel.simulate(0.4, events=True, space="3d", **model)
    out = cli("trajectory", "--space", "3d", "--release", "0.4", "--events", "--theta", "55", "--release-w", "0.07",
              "--release-spin-x", "3", "--release-spin-z", "-2")
    for key in ("duration", "impulse", "energy_loss", "exit_z", "exit_w", "orbits", "orbits_signed"):
        assert py[key] == out[key], key
    assert py["collisions"] == out["collisions"]
    assert py["params"]["release_w"] == 0.07
    events = py["events"]
    assert len(events["time"]) == len(out["events"])
    for key in ("z", "w_after", "omega_x_after", "omega_y_after", "omega_z_after"):
        assert np.array_equal(events[key], [e[key] for e in out["events"]]), key
    assert py["orbits"] > 0.0


def test_in_plane_release_gives_the_2d_trajectory():
    for theta in (40.0, 60.0):
        a = funnel.simulate(0.35, theta=theta, release_spin=1.5)
        b = funnel.simulate(0.35, theta=theta, release_spin=1.5, space="3d")
        assert a["status"] == b["status"]
        assert a["collisions"] == b["collisions"]
        for key in ("duration", "impulse", "energy_loss", "exit_u", "exit_v", "exit_spin"):
            assert math.isclose(a[key], b[key], rel_tol=1e-12, abs_tol=1e-15), key
        assert b["exit_z"] == 0.0 and b["orbits"] == 0.0


def test_ensemble_3d_at_rest_is_the_paper_cone_and_seeded_velocities_repeat():
    cone2d = funnel.ensemble(samples=64, release_dist="disk", theta=50)
    cone3d = funnel.ensemble(samples=64, theta=50, space="3d")  # disk by default in 3D
    assert cone3d["release_dist"] == "disk"
    assert math.isclose(cone2d["duration"]["mean"], cone3d["duration"]["mean"], rel_tol=1e-12)
    a = funnel.ensemble(samples=32, velocity_sd=0.03, seed=4, threads=2, space="3d", per_sample=True)
    b = funnel.ensemble(samples=32, velocity_sd=0.03, seed=4, threads=1, space="3d")
    assert a["duration"] == b["duration"] and a["orbits"] == b["orbits"]
    assert a["per_sample"]["w0"].shape == (32,)
    assert np.std(a["per_sample"]["w0"]) > 0.0
    # Counts are int64, as in 2D and the CLI's JSON, and the integrator's steps are reported.
    for count in ("collisions", "edge_collisions", "face_collisions", "contacts", "edge_contacts"):
        assert a["per_sample"][count].dtype == np.int64, count
    assert a["per_sample"]["duration"].dtype == np.float64
    assert isinstance(a["ode_steps"], int) and a["ode_steps"] == b["ode_steps"] > 0


def test_sweep_3d_has_the_3d_columns():
    s = funnel.sweep(samples=16, theta=[45, 55], release_w=[0.0, 0.05], space="3d")
    assert s["theta"].tolist() == [45, 45, 55, 55]
    assert s["release_w"].tolist() == [0.0, 0.05, 0.0, 0.05]
    assert "orbits_mean" in s and "exit_w_mean" in s
    assert s["release_dist"].tolist() == ["disk"] * 4 and s["samples"].tolist() == [16] * 4


def test_sweep_3d_has_the_columns_of_the_cli_csv_in_order(cli, tmp_path):
    s = funnel.sweep(samples=8, theta=[40, 50], space="3d", threads=1)
    cli("sweep", "--samples", 8, "--theta", "40,50", "--space", "3d", "--threads", 1, "--out", tmp_path / "s.csv",
        json_output=False)
    header = (tmp_path / "s.csv").read_text().splitlines()[0].split(",")
    assert list(s) == header


def test_options_of_the_other_space_are_refused():
    with pytest.raises(ValueError, match="release-w = 0.1.*3D"):
        funnel.simulate(0.3, release_w=0.1)
    with pytest.raises(ValueError, match="wear-bins"):
        funnel.simulate(0.3, wear_bins=4, space="3d")
    with pytest.raises(ValueError, match="release_dist = 'uniform'"):
        funnel.ensemble(samples=8, release_dist="uniform", space="3d")
    with pytest.raises(ValueError, match="space"):
        funnel.simulate(0.3, space="4d")
    with pytest.raises(ValueError, match="release-spin-x = nan"):
        funnel.simulate(0.3, release_spin_x=float("nan"), space="3d")


def test_3d_runs_report_progress_and_stop_on_ctrl_c():
    import signal
    import time

    seen = []
    quiet = funnel.ensemble(samples=64, space="3d", theta=60, threads=1)
    shown = funnel.ensemble(samples=64, space="3d", theta=60, threads=1,
                            progress=lambda done, total: seen.append((done, total)))
    assert seen and seen[-1][0] == seen[-1][1] and [d for d, _ in seen] == sorted(d for d, _ in seen)
    assert shown["duration"] == quiet["duration"]  # watching changes nothing
    points = []
    funnel.sweep(samples=16, space="3d", theta=[44, 46], progress=lambda done, total: points.append(total))
    assert points and points[-1] == 2  # two points of 16 samples: one block each

    def interrupt(done, total):
        signal.raise_signal(signal.SIGINT)

    # About 3 ms per trajectory here: the whole run would take minutes.
    start = time.monotonic()
    with pytest.raises(KeyboardInterrupt):
        funnel.ensemble(samples=200_000, space="3d", theta=60, velocity_sd=0.1, threads=1, progress=interrupt)
    assert time.monotonic() - start < 30


def test_ctrl_c_interrupts_a_3d_ensemble_whose_tasks_take_long(ctrl_c):
    # Ctrl-C is noticed ten times a second, not only when a task of 128 balls ends, and a long
    # integrated contact stops too: in this closed cone a few balls roll round the axis close
    # to the vertex for seconds each (the whole run takes about 20 s).
    ctrl_c(lambda: funnel.ensemble(samples=400, space="3d", theta=50, e=0.9, mu=0.2, gap=0, t_max=60,
                                   velocity_sd=0.2, seed=9, threads=2))


def test_ctrl_c_interrupts_balls_that_hand_over_between_the_face_and_the_rim(ctrl_c):
    # At 46 degrees balls thrown gently sideways orbit across C*, handing over between the face
    # and the rim thousands of times in contacts too short to look at the flag themselves: the
    # hand-overs look at it (Ctrl-C was raised a minute late; the whole run takes minutes).
    ctrl_c(lambda: funnel.ensemble(samples=20000, space="3d", theta=46, velocity_sd=0.03, threads=2))


#: A ball hovering at the limit of rolling on an 86-degree cone (docs/robustness.md, finding 22):
#: with the default guard its contact takes 2e7 integrator steps, about 20 s.
STEEP_STICK_SLIP = dict(theta=86.01593143426537, e=0.14390672371155014, mu=0.8610508103691801,
                        beta0=-0.15092973196734505, radius=0.00022010929764117512, gap=0.0004446501503738709,
                        t_max=66.4595276798649, release_spin=1.7457709304520292,
                        release_spin_x=-20.732256122143752, release_spin_y=17.483654399884536)


def test_a_run_stopped_by_the_step_guard_is_stalled_and_warns():
    with pytest.warns(funnel.StalledWarning, match="the run stalled"):
        t = funnel.simulate(0.6557602573781002, space="3d", max_ode_steps=5000, **STEEP_STICK_SLIP)
    assert t["status"] == "trapped" and t["stalled"] is True
    assert t["duration"] < STEEP_STICK_SLIP["t_max"]
    assert t["params"]["max_ode_steps"] == 5000
    import warnings
    with warnings.catch_warnings():
        warnings.simplefilter("error")  # an ordinary run warns of nothing
        plain = funnel.simulate(0.4, space="3d", theta=60, release_w=0.05)
    assert plain["stalled"] is False
    with pytest.warns(funnel.StalledWarning, match=r"of 61 runs stalled"):
        e = funnel.ensemble(samples=61, space="3d", theta=50, e=0.9, mu=0.2, gap=0, t_max=60, velocity_sd=0.2,
                            seed=9, max_ode_steps=20000)
    assert 0 < e["stalled"] <= e["status_counts"]["trapped"]
    with pytest.warns(funnel.StalledWarning):
        each = funnel.ensemble(samples=61, space="3d", theta=50, e=0.9, mu=0.2, gap=0, t_max=60, velocity_sd=0.2,
                               seed=9, max_ode_steps=20000, per_sample=True)
    assert int(np.sum(each["per_sample"]["stalled"])) == e["stalled"]
    with pytest.warns(funnel.StalledWarning, match=r"of 122 runs stalled"):
        s = funnel.sweep(samples=61, space="3d", theta=50, e=0.9, mu=0.2, gap=0, t_max=60, velocity_sd=0.2, seed=9,
                         max_ode_steps=[20000, 40000])
    assert s["stalled"][0] == e["stalled"] and s["stalled"][1] < s["stalled"][0]
    assert s["max_ode_steps"].dtype == np.int64
    with pytest.raises(ValueError, match="max-ode-steps"):
        funnel.simulate(0.3, max_ode_steps=5000)  # 2D
    assert "max_ode_steps" in funnel.MODEL_PARAMETERS_3D_ONLY


def test_the_summarised_3d_observables_are_the_ensembles_and_sweeps_statistics():
    # OBSERVABLES_3D is a trajectory's: face_collisions and contacts are not summarised (as in 2D).
    e = funnel.ensemble(samples=12, space="3d", t_max=20)
    assert [o for o in funnel.OBSERVABLES_3D if o in e] == list(funnel.OBSERVABLES_3D_SUMMARIZED)
    assert set(funnel.OBSERVABLES_3D) - set(funnel.OBSERVABLES_3D_SUMMARIZED) == {"face_collisions", "contacts"}
    s = funnel.sweep(samples=12, space="3d", theta=50, t_max=20)
    assert [o for o in funnel.OBSERVABLES_3D_SUMMARIZED if o + "_mean" in s] == list(funnel.OBSERVABLES_3D_SUMMARIZED)
    assert set(funnel.OBSERVABLES) <= set(funnel.OBSERVABLES_3D_SUMMARIZED)
