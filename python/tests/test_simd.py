"""The engine's SIMD paths from Python: every path gives the same results, bit for bit."""

import numpy as np
import pytest

import funnel


def test_every_path_gives_the_same_per_sample_results():
    paths = funnel.simd_paths()
    assert paths[0] == "scalar"
    before = funnel.simd_path()
    assert before in paths
    try:
        results = {}
        for path in paths:
            assert funnel.simd_path(path) == path
            r = funnel.ensemble(theta=46, samples=301, per_sample=True, threads=1)
            results[path] = r
        reference = results["scalar"]["per_sample"]
        for path, r in results.items():
            for key, column in reference.items():
                got = r["per_sample"][key]
                if isinstance(column, np.ndarray) and column.dtype.kind == "f":
                    # Bit for bit: the same bytes, NaN for NaN.
                    assert got.tobytes() == column.tobytes(), (path, key)
                else:
                    assert np.array_equal(got, column), (path, key)
    finally:
        funnel.simd_path(before)
    assert funnel.simd_path() == before


def test_an_unknown_path_names_the_valid_ones():
    with pytest.raises(ValueError, match=r"invalid simd path = 'avx1024': valid values on this CPU are scalar"):
        funnel.simd_path("avx1024")


def test_a_misspelt_funnel_simd_is_said_once_at_import():
    # As the command line says it: a misspelt path was used silently as the widest one.
    import os
    import subprocess
    import sys
    code = "import warnings; warnings.simplefilter('default'); import funnel; print(funnel.simd_path())"
    env = dict(os.environ, PYTHONPATH=os.pathsep.join(sys.path))
    odd = subprocess.run([sys.executable, "-c", code], env=dict(env, FUNNEL_SIMD="avx1024"),
                         capture_output=True, text=True, check=True)
    assert odd.stderr.count("FUNNEL_SIMD = 'avx1024' is not a path this CPU runs (scalar") == 1, odd.stderr
    assert odd.stdout.strip() == funnel.simd_paths()[-1]
    known = subprocess.run([sys.executable, "-c", code], env=dict(env, FUNNEL_SIMD="scalar"),
                           capture_output=True, text=True, check=True)
    assert "FUNNEL_SIMD" not in known.stderr and known.stdout.strip() == "scalar"


def test_the_bench_picture_draws_a_bar_per_path_and_refuses_other_json(tmp_path):
    import subprocess
    import sys

    from funnel.plot_bench import bars

    bench = {
        "reference_ensemble": {"samples": 1000},
        "reference_ensemble_by_path": [
            {"path": "scalar", "lanes": 1, "threads": 1, "wall_time_s": 1.0, "computed_collisions_per_second": 1.5e7},
            {"path": "avx2", "lanes": 4, "threads": 2, "wall_time_s": 0.2, "computed_collisions_per_second": 7.5e7},
        ],
    }
    assert bars(bench) == [("scalar (1 lane), 1 thread", 1.5e7), ("avx2 (4 lanes), 2 threads", 7.5e7)]
    source = tmp_path / "bench.json"
    source.write_text(__import__("json").dumps(bench))
    out = tmp_path / "bench.png"
    run = subprocess.run([sys.executable, "-m", "funnel.plot", "bench", str(source), "--out", str(out)],
                         capture_output=True, text=True)
    assert run.returncode == 0, run.stderr
    assert out.read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"
    source.write_text('{"reference_ensemble": {}}')
    bad = subprocess.run([sys.executable, "-m", "funnel.plot", "bench", str(source), "--out", str(tmp_path / "x.png")],
                         capture_output=True, text=True)
    assert bad.returncode == 2
    assert "no 'reference_ensemble_by_path'" in bad.stderr
    assert not (tmp_path / "x.png").exists()
    # A missing file or one that is not JSON is named with what is valid (the bare OSError or
    # json's "Expecting value" before).
    for path, said in ((tmp_path / "none.json", "No such file or directory"), (tmp_path / "words.json", "not JSON")):
        if path.name == "words.json":
            path.write_text("xx")
        bad = subprocess.run([sys.executable, "-m", "funnel.plot", "bench", str(path), "--out", str(tmp_path / "y.png")],
                             capture_output=True, text=True)
        assert bad.returncode == 2
        assert f"error: invalid bench = '{path}': {said}" in bad.stderr, bad.stderr
        assert "valid values are the JSON" in bad.stderr
