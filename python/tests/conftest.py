"""Shared fixtures: the funnel command-line binary, for comparing the Python API with it."""

import json
import os
import subprocess
from pathlib import Path

import pytest


def _find_binary():
    path = os.environ.get("FUNNEL_BINARY")
    if path:
        return Path(path)
    # Run by hand: the binary of the build whose package is imported (<build>/python/funnel).
    import funnel
    candidate = Path(funnel.__file__).resolve().parents[2] / "funnel"
    return candidate if candidate.is_file() else None


@pytest.fixture(scope="session")
def cli():
    """Runs `funnel ARGS...` and returns its parsed JSON output (or the raw text with json=False)."""
    binary = _find_binary()
    if binary is None or not binary.is_file():
        pytest.skip("the funnel binary is unknown: set FUNNEL_BINARY")

    def run(*args, json_output=True, check=True):
        proc = subprocess.run([str(binary), *map(str, args)], capture_output=True, text=True)
        if check and proc.returncode != 0:
            raise AssertionError(f"funnel {' '.join(map(str, args))} failed: {proc.stderr}")
        if not check:
            return proc
        return json.loads(proc.stdout) if json_output else proc.stdout

    return run


@pytest.fixture
def ctrl_c():
    """``ctrl_c(call)``: runs ``call()`` while Ctrl-C (SIGINT) arrives 1 s in, and asserts that it
    raised KeyboardInterrupt within ``within`` seconds of its start (keyword, default 6)."""
    import signal
    import threading
    import time

    def run(call, within=6.0):
        timer = threading.Timer(1.0, lambda: os.kill(os.getpid(), signal.SIGINT))
        start = time.monotonic()
        timer.start()
        try:
            with pytest.raises(KeyboardInterrupt):
                call()
        finally:
            timer.cancel()
        assert time.monotonic() - start < within

    return run
