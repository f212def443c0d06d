"""funnel: exact event-driven simulation of a frictional, inelastic sphere falling through a funnel.

A Python front end to the C++ library, like the ``funnel`` command line:

- :func:`simulate` — one trajectory (``funnel trajectory``), optionally with its event log;
- :func:`ensemble` — statistics over release positions (``funnel ensemble``);
- :func:`sweep` — one ensemble per point of a parameter grid (``funnel sweep``);
- :func:`geometry` — the funnel's derived geometry, for plotting;
- :func:`orbit` — eigenvalues and stability of the period-2 orbit (``funnel orbit``);
- :func:`closed` — periodic orbit or rest in a closed funnel (``funnel closed``);
- :func:`retrace` — self-retracing orbits of the elastic frictionless particle (``funnel retrace``);
- :func:`paper_figure` — one figure of the paper, its data and its check (``funnel paper``).

Model parameters are keyword arguments named like the command-line options with '-' turned
into '_': theta [deg], e, mu, beta0, radius, gap, inertia, t_max, max_collisions,
release_height, release_u, release_v, release_spin (the table :data:`PARAMETERS`). Units:
H = g = m = 1 (times in sqrt(H/g), impulses in m sqrt(gH), energies in mgH). Invalid values
raise ValueError with the library's message. Results are dicts of Python numbers and 1-D
numpy arrays.

Plots of the paper's figures: ``python -m funnel.plot OUTDIR`` (module :mod:`funnel.plot`,
which imports matplotlib only when used). One trajectory: ``python -m funnel.plot trajectory``
(:mod:`funnel.trajectory`) and ``python -m funnel.animate`` (:mod:`funnel.animate`); the motion
between logged events: :mod:`funnel.motion`. See docs/python.md.
"""

import sys as _sys

try:
    import numpy as _numpy  # noqa: F401  (every result holds numpy arrays)
except ImportError as _error:
    raise ImportError(
        f"funnel needs numpy, which this Python ({_sys.executable}, {_sys.version.split()[0]}) cannot import. "
        "Use Debian's /usr/bin/python3, which has numpy and matplotlib (apt-get install python3-numpy "
        "python3-matplotlib) and for which funnel's compiled module is built, e.g. "
        "PYTHONPATH=build/python /usr/bin/python3; or install numpy for this interpreter."
    ) from _error

from ._api import (
    DEFAULT_SAMPLES,
    MODEL_PARAMETERS,
    MODEL_PARAMETERS_3D_ONLY,
    OBSERVABLE_TABLE,
    OBSERVABLES,
    OBSERVABLES_3D,
    OBSERVABLES_3D_SUMMARIZED,
    PARAMETERS,
    STATISTICS,
    CappedWarning,
    StalledWarning,
    closed,
    default_params,
    ensemble,
    geometry,
    git_commit,
    model_keywords,
    orbit,
    paper_figure,
    retrace,
    simd_path,
    simd_paths,
    simulate,
    sweep,
    valid_range,
    version,
)

__version__ = "0.1.0"

__all__ = [
    "DEFAULT_SAMPLES",
    "MODEL_PARAMETERS",
    "MODEL_PARAMETERS_3D_ONLY",
    "OBSERVABLE_TABLE",
    "OBSERVABLES",
    "OBSERVABLES_3D",
    "OBSERVABLES_3D_SUMMARIZED",
    "PARAMETERS",
    "STATISTICS",
    "CappedWarning",
    "StalledWarning",
    "closed",
    "default_params",
    "ensemble",
    "geometry",
    "git_commit",
    "model_keywords",
    "orbit",
    "paper_figure",
    "retrace",
    "simd_path",
    "simd_paths",
    "simulate",
    "sweep",
    "valid_range",
    "version",
]
