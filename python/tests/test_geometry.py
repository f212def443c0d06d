"""Any 2D funnel from Python: geometry= as a dict or a TOML path, the V's shortcuts, errors."""
import math
from pathlib import Path

import numpy as np
import pytest

import funnel

ROOT = Path(__file__).resolve().parents[2]
LINED = ROOT / "examples" / "geometry" / "lined.toml"
HOPPER = {"mirror": True, "left": {"vertices": [[-2.0, 1.6], [-0.5, 0.734], [-0.1, -0.365]]}}


def test_a_dict_and_its_toml_file_give_the_same_funnel(tmp_path):
    path = tmp_path / "hopper.toml"
    path.write_text("mirror = true\n[left]\nvertices = [[-2.0, 1.6], [-0.5, 0.734], [-0.1, -0.365]]\n")
    a = funnel.ensemble(samples=300, geometry=HOPPER)
    b = funnel.ensemble(samples=300, geometry=path)
    assert a["duration"] == b["duration"]
    assert a["simulated_collisions"] * 2 == a["total_collisions"]  # mirror symmetric: half simulated


def test_a_free_fall_on_the_axis_of_a_symmetric_profile():
    r = funnel.simulate(release=0.0, geometry=HOPPER)
    assert r["status"] == "exited" and r["collisions"] == 0
    assert r["exit_speed"] == pytest.approx(math.sqrt(2.0), rel=1e-14)


def test_per_wall_materials_from_a_file_change_the_result():
    lined = funnel.ensemble(samples=400, geometry=LINED)
    same = funnel.ensemble(samples=400, geometry={"left": {"vertices": [[-2.0, 1.6], [-0.5, 0.734], [-0.1, -0.365]]},
                                                  "right": {"vertices": [[0.9, 1.6], [0.6, 0.3], [0.35, 0.3],
                                                                         [0.1, -0.365]]}})
    assert lined["energy_loss"]["mean"] != same["energy_loss"]["mean"]
    assert lined["status_counts"]["rest"] > 0  # some stop on the ledge


def test_geometry_describes_the_walls_for_drawing():
    g = funnel.geometry(geometry=LINED)
    assert g["source"] == str(LINED)
    assert not g["symmetric"]
    assert g["walls"]["right"][-1] == [0.1, -0.365]
    assert g["y_exit"] == -0.365
    v = funnel.geometry(theta_left=40, theta_right=50, spout_length=0.2)
    assert len(v["walls"]["left"]) == 3 and not v["symmetric"]
    assert v["walls"]["left"][-1][1] == v["y_exit"]  # the spout's lower end
    assert v["walls"]["left"][-2][1] - v["y_exit"] == pytest.approx(0.2, abs=1e-15)


def test_a_v_written_out_as_its_vertices_is_the_v_bit_for_bit():
    v = dict(theta_left=40, theta_right=50, spout_length=0.2)
    g = funnel.geometry(**v)
    profile = {"left": {"vertices": g["walls"]["left"]}, "right": {"vertices": g["walls"]["right"]},
               "bottom": g["bottom"]}
    a = funnel.ensemble(samples=300, per_sample=True, **v)
    b = funnel.ensemble(samples=300, per_sample=True, geometry=profile)
    assert np.array_equal(a["per_sample"]["duration"], b["per_sample"]["duration"])
    assert np.array_equal(a["per_sample"]["exit_x"], b["per_sample"]["exit_x"])


def test_sweeps_take_a_geometry_and_the_shortcuts():
    s = funnel.sweep(e=[0.5, 0.9], samples=40, geometry=HOPPER)
    assert s["e"].tolist() == [0.5, 0.9]
    t = funnel.sweep(theta_right=[45, 55], theta_left=40, samples=40)
    assert t["theta_right"].tolist() == [45.0, 55.0]
    assert np.all(t["theta_left"] == 40.0)


def test_a_material_every_wall_sets_for_itself_is_refused():
    # Both walls of lined.toml set mu: mu=... would change nothing, and a sweep over it would
    # label equal rows apart. Its left wall leaves e to the parameter, which goes with the file.
    with pytest.raises(ValueError, match=r"invalid mu = 0\.5: valid range is not with a geometry "
                                         r"file whose walls all set their own mu .*left 0\.1, right 1\.2"):
        funnel.simulate(release=0.3, geometry=LINED, mu=0.5)
    with pytest.raises(ValueError, match="whose walls all set their own mu"):
        funnel.ensemble(samples=20, geometry=LINED, mu=0.5)
    with pytest.raises(ValueError, match="whose walls all set their own mu"):
        funnel.sweep(mu=[0, 1], samples=20, geometry=LINED)
    s = funnel.sweep(e=[0.5, 0.9], samples=200, geometry=LINED)
    assert s["duration_mean"][0] != s["duration_mean"][1]
    # The parameters the file replaces have no value (not the default V's): NaN in a sweep's
    # columns, None in a result's params; e, which the left wall takes, keeps its value.
    for unused in ("theta", "gap", "theta_left", "theta_right", "spout_length", "mu"):
        assert np.all(np.isnan(s[unused])), unused
    assert s["e"].tolist() == [0.5, 0.9]
    params = funnel.simulate(release=0.3, geometry=LINED)["params"]
    assert params["theta"] is None and params["mu"] is None and params["e"] == 0.99
    assert funnel.simulate(release=0.3)["params"]["theta"] == 60.0


def test_bad_geometries_name_the_key_and_the_rule(tmp_path):
    with pytest.raises(ValueError, match="geometry left segment 0-1"):
        funnel.simulate(release=0.0, geometry={"mirror": True,
                                               "left": {"vertices": [[-1, 1], [-1.5, 0.5], [-0.1, 0]]}})
    with pytest.raises(ValueError, match="unknown key 'left.vertice'"):
        funnel.simulate(release=0.0, geometry={"mirror": True, "left": {"vertice": [[-1, 1], [0, 0]]}})
    with pytest.raises(ValueError, match="no such file|No such file"):
        funnel.simulate(release=0.0, geometry=tmp_path / "missing.toml")
    with pytest.raises(TypeError):
        funnel.simulate(release=0.0, geometry=3)
    with pytest.raises(ValueError, match="spout-length"):
        funnel.simulate(release=0.0, geometry=HOPPER, spout_length=0.1)


def test_a_trajectory_plot_draws_the_profile(tmp_path):
    from funnel.trajectory import plot_trajectory, simulate_for_plot
    result, g = simulate_for_plot(0.3, geometry=str(LINED))
    fig = plot_trajectory(result, g)
    ax = fig.axes[0]
    xs = np.concatenate([line.get_xdata() for line in ax.lines])
    assert np.isclose(xs, 0.35).any()  # the ledge's inner end is drawn
