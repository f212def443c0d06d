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
