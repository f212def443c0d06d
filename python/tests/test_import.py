"""What `import funnel` says when the interpreter cannot run it (no numpy, another Python)."""

import os
import shutil
import subprocess
import sys

import pytest


def _run(python, code):
    """Runs `python -c code` with this session's PYTHONPATH (the package under test)."""
    return subprocess.run([python, "-c", code], capture_output=True, text=True, env=dict(os.environ))


def test_without_numpy_the_message_names_this_interpreter_and_debians():
    # numpy made unimportable, as in an interpreter that does not have it.
    proc = _run(sys.executable, "import sys; sys.modules['numpy'] = None\nimport funnel")
    assert proc.returncode != 0
    last = proc.stderr.strip().splitlines()[-1]
    assert last.startswith("ImportError: funnel needs numpy"), proc.stderr
    assert sys.executable in last and "/usr/bin/python3" in last and "apt-get install python3-numpy" in last


def test_without_the_compiled_module_the_message_names_the_build_and_the_interpreter():
    proc = _run(sys.executable, "import sys; sys.modules['funnel._funnel'] = None\n"
                                "import funnel\nfunnel.simulate(release=0.3)")
    assert proc.returncode != 0
    last = proc.stderr.strip().splitlines()[-1]
    assert "funnel's compiled module funnel._funnel is not importable" in last, proc.stderr
    assert "_funnel.cpython" in last and sys.executable in last and "/usr/bin/python3" in last


def test_plain_python3_on_path_without_numpy_is_told_which_interpreter_to_use():
    # A newcomer's `python3` (e.g. a pyenv shim) that has no numpy; skipped where it has numpy.
    python = shutil.which("python3")
    if python is None or os.path.realpath(python) == os.path.realpath(sys.executable):
        pytest.skip("python3 on PATH is the interpreter under test")
    if _run(python, "import numpy").returncode == 0:
        pytest.skip(f"{python} has numpy: nothing to explain")
    proc = _run(python, "import funnel")
    assert "funnel needs numpy" in proc.stderr and "/usr/bin/python3" in proc.stderr, proc.stderr
