"""The documented Python API over the compiled module ``funnel._funnel``.

Model parameters are keyword arguments named like the command-line options with '-' turned
into '_': theta, e, mu, beta0, radius, gap, inertia, t_max, max_collisions, release_height,
release_u, release_v, release_spin (the library's parameter table, :data:`PARAMETERS`). Units:
H = g = m = 1 (lengths in H, times in sqrt(H/g), impulses in m sqrt(gH), energies in mgH).
"""

from __future__ import annotations

import math
import numbers
import os
import tomllib
import warnings

import numpy as np

try:
    from . import _funnel
except ImportError as _error:  # plotting works without the compiled module
    _funnel = None
    _import_error = _error
else:
    _import_error = None

#: The library's parameter table: one dict per parameter (name, key, meaning, unit, range,
#: default, integer, option), in the order of the grid's axes and of the CSV columns.
PARAMETERS = tuple(_funnel.parameters()) if _funnel is not None else ()

#: The library's observable table: one dict per observable (name, meaning, unit, count,
#: exited_only, summarized), in column order.
OBSERVABLE_TABLE = tuple(_funnel.observables()) if _funnel is not None else ()

#: Model keyword arguments, in the order of the grid's axes and of the CSV columns.
MODEL_PARAMETERS = tuple(p["key"] for p in PARAMETERS if p["option"]) or (
    "theta", "e", "mu", "beta0", "radius", "gap", "inertia", "t_max", "max_collisions", "release_height",
    "release_u", "release_v", "release_spin")

#: The model keyword arguments of the 3D funnel only (space="3d"): release_w (velocity along z),
#: release_spin_x, release_spin_y (release_spin is the spin about z) and max_ode_steps (the step
#: guard of an integrated contact).
MODEL_PARAMETERS_3D_ONLY = tuple(_funnel.parameters_3d()) if _funnel is not None else (
    "release_w", "release_spin_x", "release_spin_y", "max_ode_steps")

#: The observables of a 3D trajectory: those of 2D, then exit_z, exit_w, exit_spin_x,
#: exit_spin_y and orbits (turns about the axis).
OBSERVABLES_3D = tuple(_funnel.observables_3d()) if _funnel is not None else ()

#: Observables summarised by ensembles and sweeps, in column order (the exit ones over the
#: exited samples).
OBSERVABLES = tuple(o["name"] for o in OBSERVABLE_TABLE if o["summarized"]) or (
    "duration", "impulse", "normal_impulse", "energy_loss", "collisions", "edge_collisions", "edge_contacts",
    "contact_time", "exit_x", "exit_u", "exit_v", "exit_speed", "exit_angle", "exit_spin")

#: Observables summarised by 3D ensembles and sweeps, in column order: those of
#: :data:`OBSERVABLES_3D` but the counts that 2D summaries leave out too (face_collisions,
#: contacts, which are collisions and edge_contacts' parts).
OBSERVABLES_3D_SUMMARIZED = tuple(
    o for o in OBSERVABLES_3D if o in OBSERVABLES or o not in {t["name"] for t in OBSERVABLE_TABLE})

#: Statistics of each observable: mean, sample standard deviation, standard error, min, max.
STATISTICS = ("mean", "std", "sem", "min", "max")

#: Default number of release positions of an ensemble (docs/model.md §8).
DEFAULT_SAMPLES = 4000


def _warn_unknown_simd_path():
    """FUNNEL_SIMD naming no path this CPU runs is said once, at import, as the command line says
    it: the widest path is used, and a user comparing paths would compare one path with itself."""
    name = os.environ.get("FUNNEL_SIMD", "")
    if _funnel is None or not name:
        return
    paths = list(_funnel.simd_paths())
    if name not in paths:
        warnings.warn(f"FUNNEL_SIMD = {name!r} is not a path this CPU runs ({', '.join(paths)}); "
                      f"using {_funnel.simd_path()}", RuntimeWarning, stacklevel=2)


_warn_unknown_simd_path()


def _core():
    if _funnel is None:
        import sys
        from pathlib import Path
        built = sorted(p.name for p in Path(__file__).parent.glob("_funnel*.so"))
        raise ImportError(
            "funnel's compiled module funnel._funnel is not importable (build it with CMake and put "
            f"<build>/python on PYTHONPATH; see docs/python.md): {_import_error}"
            + (f"; found {', '.join(built)}, which must match this Python ({sys.executable}, "
               f"{sys.version.split()[0]}): use the interpreter it was built for, Debian's /usr/bin/python3"
               if built else ""))
    return _funnel


def _check_names(function, model, space="2d"):
    names = MODEL_PARAMETERS + (MODEL_PARAMETERS_3D_ONLY if space == "3d" else ())
    for name in model:
        if name in MODEL_PARAMETERS_3D_ONLY and space != "3d":
            raise ValueError(f"invalid {name.replace('_', '-')} = {model[name]!r}: {name} is a 3D option, "
                             "taken only with space=\"3d\"")
        if name not in names:
            raise TypeError(f"{function}() got an unexpected keyword argument '{name}' "
                            f"(model parameters: {', '.join(names)})")


def _space(value):
    """The space, "2d" or "3d"."""
    if value not in ("2d", "3d"):
        raise ValueError(f"invalid space = {value!r}: valid values are '2d', '3d'")
    return value


def _item(value):
    """A 0-d numpy array of reals (np.array(60.0)) as its number, as numpy itself treats it;
    anything else unchanged."""
    if isinstance(value, np.ndarray) and value.ndim == 0 and value.dtype.kind in "iuf":
        return value.item()
    return value


def _scalar(name, value):
    """A model value as float; TypeError for anything that is not a real number, ValueError
    naming the parameter for an integer beyond the doubles (10**400: OverflowError otherwise).
    A 0-d numpy array of reals is its number (_item)."""
    value = _item(value)
    if isinstance(value, (bool, np.bool_)) or not isinstance(value, numbers.Real):
        raise TypeError(f"{name} must be a real number, not {type(value).__name__}")
    try:
        return float(value)
    except OverflowError:
        try:
            text = f"; valid range is {valid_range(name)}"
        except ValueError:  # not a model parameter (max_time, release, ...): its own check has the range
            text = ""
        digits = str(abs(int(value)))  # an integer with hundreds of digits, shown as d.dddde+N
        shown = f"{'-' if value < 0 else ''}{digits[0]}.{digits[1:5]}e+{len(digits) - 1}"
        raise ValueError(f"invalid {name} = {shown}: out of range (beyond the largest double){text}") from None


def _not_nan(name, value):
    """NaN is how the library marks theta_left/theta_right unset: a NaN given would silently mean
    theta. No parameter takes NaN."""
    if math.isnan(value):
        raise ValueError(f"invalid {name.replace('_', '-')} = nan: valid range is {valid_range(name)}")
    return value


def _model(function, model, space="2d"):
    _check_names(function, model, space)
    return {name: _not_nan(name, _scalar(name, value)) for name, value in model.items()}


# The integer options' ranges, as the command line's (beyond them C++ would not even take the
# number: a pybind11 "incompatible function arguments" dump instead of the range).
_COUNT_RANGES = {
    "samples": (1, 10**9, "an integer 1 <= samples <= 10^9"),
    "threads": (0, 1024, "an integer 0 <= threads <= 1024 (0 = all cores)"),
    "wear-bins": (0, 10**4, "an integer 0 <= wear-bins <= 10^4"),
    "max_bounces": (1, 20, "an integer 1 <= max_bounces <= 20"),
    "scan_points": (16, 10**6, "an integer 16 <= scan_points <= 10^6"),
    "max_coll": (1, 9 * 10**18 - 1, "an integer 1 <= max_coll < 9e18"),
    "max_collisions": (1, 9 * 10**18 - 1, "an integer 1 <= max_collisions < 9e18"),
    "window": (1, 10**6, "an integer 1 <= window <= 10^6"),
    "seed": (0, 2**64 - 1, "an integer 0 <= seed < 2^64"),
}


def _count(name, value):
    """An integer option (samples, threads, ...) in its range; floats are accepted when integral."""
    lo, hi, text = _COUNT_RANGES.get(name, (-(2**62), 2**62, "an integer"))
    value = _item(value)
    if isinstance(value, (bool, np.bool_)):
        raise TypeError(f"{name} must be an integer, not bool")
    if isinstance(value, numbers.Integral):
        n = int(value)
    elif isinstance(value, numbers.Real) and math.isfinite(value) and float(value).is_integer():
        n = int(value)
    elif isinstance(value, numbers.Real):
        raise ValueError(f"invalid {name} = {value!r}: not an integer; valid range is {text}")
    else:
        raise TypeError(f"{name} must be an integer, not {type(value).__name__}")
    if not lo <= n <= hi:
        raise ValueError(f"invalid {name} = {n}: valid range is {text}")
    return n


def _seed(value, release_dist, velocity_sd=None, space="2d"):
    """The random seed, an integer 0 <= seed < 2^64 (None: 1). As on the command line, a seed
    given where nothing is drawn at random is refused: two seeds would look like two samples.
    velocity_sd None: the function has no random velocities (closed)."""
    if value is None:
        return 1
    seed = _count("seed", value)
    if not 0 <= seed < 2**64:
        raise ValueError(f"invalid seed = {seed}: valid range is an integer 0 <= seed < 2^64")
    velocities = velocity_sd is not None
    # Only "line" and "disk" draw no random position (another name is refused as a distribution).
    if release_dist in ("line", "disk") and not (velocities and (velocity_sd > 0 or math.isnan(velocity_sd))):
        which = ("velocities only (velocity_sd > 0: in 3d the releases are line or disk" if space == "3d"
                 else "releases or velocities only (release_dist \"uniform\" or \"gaussian\", or velocity_sd > 0"
                 if velocities else "releases only (release_dist \"uniform\" or \"gaussian\"")
        raise ValueError(f"invalid seed = {seed}: valid range is an integer 0 <= seed < 2^64, with random {which}; "
                         "these releases draw no random number)")
    return seed


def _wear_bins(value):
    """The wear bins, an integer 0 <= wear_bins <= 10^4."""
    bins = _count("wear-bins", value)
    if not 0 <= bins <= 10**4:
        raise ValueError(f"invalid wear-bins = {bins}: valid range is an integer 0 <= wear-bins <= 10^4 "
                         "(0 = no wear record)")
    return bins


def _geometry(value):
    """A funnel geometry for the core: None (the V of theta and gap), a dict laid out as a
    geometry file, or the path of a geometry TOML file (docs/cli.md, "Geometry files")."""
    if value is None or isinstance(value, dict):
        return value
    if isinstance(value, (str, os.PathLike)):
        path = os.fspath(value)
        try:
            with open(path, "rb") as f:
                data = tomllib.load(f)
        except OSError as err:
            raise ValueError(f"invalid geometry = '{path}': {err.strerror}") from None
        except tomllib.TOMLDecodeError as err:
            raise ValueError(f"invalid geometry = '{path}': {err}") from None
        data["source"] = path
        return data
    raise TypeError(f"geometry must be a dict, a path or None, not {type(value).__name__}")


def _text_columns(columns, names):
    for name in names:
        if name in columns:
            columns[name] = np.asarray(columns[name], dtype=str)
    return columns


class StalledWarning(RuntimeWarning):
    """Some 3D runs were ended by a guard before ``t_max`` (status trapped, ``stalled`` true):
    most often a sustained contact that reached ``max_ode_steps`` integrator steps: a ball orbiting
    the cone for a long time, rolling and sliding in turn, or hovering at the limit of rolling
    (docs/robustness.md, finding 22)."""


def _warn_stalled(stalled, runs, where):
    """Warns (StalledWarning) when ``stalled`` of ``runs`` 3D runs stalled, as the CLI does on
    stderr; ``where`` says where the result shows it."""
    if stalled:
        what = "the run stalled: an internal guard ended it" if runs == 1 else \
            f"{stalled} of {runs} runs stalled: an internal guard ended them"
        warnings.warn(f"{what} before t_max, most often a sustained contact that reached max_ode_steps integrator "
                      "steps: a ball that orbits the cone for a long time, rolling and sliding in turn (about 10^3 "
                      "steps per unit of time; common in shallow cones with a small mu), or one that hovers at the "
                      "limit of rolling (docs/robustness.md, finding 22); status trapped, the results stop at the "
                      f"guard ({where}). A shorter t_max or a lower max_ode_steps bounds their cost; a higher "
                      "max_ode_steps lets them go on",
                      StalledWarning, stacklevel=3)


class CappedWarning(RuntimeWarning):
    """Some runs reached the collision cap ``max_collisions`` inside the funnel (status trapped):
    their duration, impulse and energy loss stop there, short of ``t_max``."""


def _warn_capped(capped, runs, cap, stacklevel=3):
    """Warns (CappedWarning) when ``capped`` of ``runs`` runs reached the collision cap ``cap``
    inside the funnel, as the CLI does on stderr."""
    if capped:
        what = "the run reached" if runs == 1 else f"{capped} of {runs} runs reached"
        whose = "its" if runs == 1 else "their"
        cap = "" if cap is None else f" ({cap})"  # None: it varies over a sweep's grid
        warnings.warn(f"{what} max_collisions{cap} inside the funnel: {whose} status is trapped and {whose} "
                      "duration, impulse and energy loss stop at the cap, short of the time cap t_max. A higher "
                      f"max_collisions lets {'it' if runs == 1 else 'them'} go on", CappedWarning, stacklevel=stacklevel)


def _warn_capped_run(result):
    """The CappedWarning of one trajectory's result, from the engine's own flag (the binding's
    private key, removed here: the keys are those of the CLI's JSON)."""
    _warn_capped(int(result.pop("_capped")), 1, int(result["params"]["max_collisions"]), stacklevel=4)


def simulate(release, events=False, wear_bins=0, space="2d", geometry=None, **model):
    """Simulate one trajectory released at x0 = release * L.

    With ``space="3d"`` the funnel is revolved about its vertical axis (a cone with a circular
    outlet of diameter ``gap``; docs/model.md §9): the ball starts at (x0, y0, 0) and may
    also get ``release_w`` (velocity along z), ``release_spin_x`` and ``release_spin_y``
    (``release_spin`` is the spin about z). The result has the 2D keys (exit_speed |v|,
    exit_angle from the downward vertical >= 0, exit_spin about z) plus ``z0``, ``w0``,
    ``omega0`` (a 3-vector), ``exit_z``, ``exit_w``, ``exit_spin_x``, ``exit_spin_y``,
    ``orbits`` (turns about the axis, >= 0), ``orbits_signed``, ``periodic`` and ``stalled`` (ended
    by a guard before ``t_max``, most often ``max_ode_steps``: a :class:`StalledWarning` says so); its events
    add z, w_before/after and omega_x/y/z_before/after (slip_before and j_t are magnitudes).
    ``wear_bins`` is 2D only.

    Parameters
    ----------
    release : float
        Release position x0/L, -1 < release < 1 (``--release``).
    events : bool
        Also return the event log (``--events``).
    wear_bins : int
        Also record where the walls wear in that many equal bins along each wall (``--wear-bins``).
    geometry : dict, str, path or None
        The funnel's walls (``--geometry``): a dict laid out as a geometry file ({"left":
        {"vertices": [[x, y], ...], "e", "mu", "beta0"}, "right": {...}, "mirror", "bottom"}) or
        the path of such a TOML file; None for the V of theta, theta_left/right, gap and
        spout_length.
    **model
        Model parameters (theta, e, mu, beta0, radius, gap, inertia, t_max, max_collisions,
        release_height, release_u, release_v, release_spin); the others keep their defaults.
        The particle starts at rest unless release_u, release_v (velocity) or release_spin say
        otherwise.

    Returns
    -------
    dict
        As ``funnel trajectory --format json`` without "provenance": ``params`` (dict),
        ``release``, ``x0``, ``y0``, ``u0``, ``v0``, ``omega0``, ``status`` ("exited", "rest" or
        "trapped"), ``duration`` [sqrt(H/g)], ``impulse`` and ``normal_impulse`` [m sqrt(gH)],
        ``energy_loss`` [mgH], ``collisions``, ``edge_collisions``, ``face_collisions``,
        ``contacts``, ``edge_contacts`` (int), ``contact_time`` [sqrt(H/g)], and the exit state
        ``exit_x`` [H], ``exit_u``, ``exit_v``, ``exit_speed`` [sqrt(gH)], ``exit_angle``
        [degrees from the downward vertical, positive towards +x], ``exit_spin`` [sqrt(g/H)]
        (None unless it exited). With ``wear_bins``: ``wear`` = {"left": {"s", "collisions",
        "normal_impulse", "impulse" (numpy arrays), "edge": {...}, "bin_width"}, "right": ..., "bin_width"}
        (each wall's own bins; the last bin_width is the left wall's).
        With ``events=True`` also ``events``: a dict of 1-D numpy arrays of equal length, one
        entry per event: time, x, y, u_before, v_before, omega_before, u_after, v_after,
        omega_after, slip_before, j_n, j_t, energy_lost (float64), and kind ("face", "edge",
        "contact_start", "contact_end", "edge_contact_start", "edge_contact_end", "exit"), wall
        ("left", "right", "none") and regime ("none", "sliding", "sticking", "rolling") as
        arrays of str.

    Raises
    ------
    ValueError
        Invalid parameters, with the library's message, e.g.
        "invalid theta = 95: valid range is 0 < theta < 90 (degrees)".

    Examples
    --------
    >>> r = funnel.simulate(release=0.3, theta=60)
    >>> r["status"], r["duration"], r["exit_speed"]
    """
    core = _core()
    if _space(space) == "3d":
        if geometry is not None:
            raise ValueError("invalid geometry: a 2D funnel only (the 3D funnel is the cone of theta and gap)")
        if _wear_bins(wear_bins) != 0:
            raise ValueError(f"invalid wear-bins = {wear_bins}: valid range is 0 in 3d (the wear record is 2D only)")
        result = core.simulate_3d(_model("simulate", model, "3d"), _scalar("release", release), _flag("events", events))
        if events:
            _text_columns(result["events"], ("kind", "regime"))
        _warn_stalled(int(result["stalled"]), 1, "'stalled' in the result")
        _warn_capped_run(result)
        return result
    result = core.simulate(_model("simulate", model), _scalar("release", release), _flag("events", events),
                           _wear_bins(wear_bins), _geometry(geometry))
    if events:
        _text_columns(result["events"], ("kind", "wall", "regime"))
    _warn_capped_run(result)
    return result


def _gaussian(release_dist, release, release_sd):
    """(mean, sd) of the gaussian releases; ValueError if given with another distribution."""
    for name, value, valid, what in (("release", release, "-1 < release < 1", "mean"),
                                     ("release-sd", release_sd, "0 < release-sd <= 10", "standard deviation")):
        if value is not None and release_dist != "gaussian":
            raise ValueError(f"invalid {name} = {value}: valid range is {valid}, with release_dist \"gaussian\" "
                             f"only (a 2D distribution: the {what} of its x0/L)")
    return (0.0 if release is None else release), (0.1 if release_sd is None else release_sd)


def _flag(name, value):
    """A yes/no option: True or False (numpy's too); TypeError for anything else, where bool()
    would take events="no" as yes."""
    if isinstance(value, (bool, np.bool_)):
        return bool(value)
    raise TypeError(f"{name} must be True or False, not {type(value).__name__} ({value!r})")


def _progress_callback(progress, what):
    """A callable (done, total) from ``progress``: True (tqdm if installed, else a line on
    stderr), False/None (nothing) or a callable."""
    if progress is None or progress is False or (isinstance(progress, np.bool_) and not progress):
        return None
    if callable(progress):
        return progress
    _flag("progress", progress)  # True; anything else (0, "yes") is a TypeError
    try:
        from tqdm import tqdm
    except ImportError:
        import sys

        def text(done, total):
            end = "\n" if done == total else ""
            print(f"\rfunnel {what}: {done}/{total}", end=end, file=sys.stderr, flush=True)
        return text
    bar = None

    def update(done, total):
        nonlocal bar
        if bar is None:
            bar = tqdm(total=total, desc=f"funnel {what}", unit="chunk")
        bar.update(done - bar.n)
        if done == total:
            bar.close()
    return update


def ensemble(samples=DEFAULT_SAMPLES, release_dist=None, threads=0, per_sample=False, seed=None, release=None,
             release_sd=None, velocity_sd=0.0, wear_bins=0, progress=False, space="2d", geometry=None, **model):
    """Statistics of the observables over ``samples`` releases, like ``funnel ensemble``.

    With ``space="3d"`` (the funnel revolved about its axis, see :func:`simulate`) the
    releases are "disk" (the default) or "line" at z = 0, ``velocity_sd`` adds random
    horizontal velocities (u, w), and the result holds the statistics of
    :data:`OBSERVABLES_3D_SUMMARIZED` (orbits included), ``periodic`` and ``stalled`` (the counts among the
    trapped; stalled ones raise a :class:`StalledWarning`); uniform, gaussian and wear_bins are
    2D only.

    Parameters
    ----------
    samples : int
        Number of releases N, 1 <= N <= 10^9.
    release_dist : {"line", "disk", "uniform", "gaussian"} or None
        None: "line" in 2D, "disk" in 3D. "line": the 2D funnel, x0_k = L(2k + 1 - N)/N (the paper's); "disk": the axisymmetric cone
        (paper Sec. V), uniform over the disk of radius L; "uniform": x0/L uniform random in
        (-1, 1); "gaussian": x0/L normal with mean ``release`` and standard deviation
        ``release_sd``, truncated to (-1, 1).
    threads : int
        Worker threads, 0 = all cores. Results are bit-identical for any count.
    per_sample : bool
        Also return every trajectory's observables.
    seed : int or None
        Key of the counter-based random numbers (uniform, gaussian, velocity_sd): sample k's
        random numbers depend on (seed, k) only. None: 1. As on the command line, a seed given
        where nothing is drawn at random ("line" or "disk" releases without velocity_sd) raises
        ValueError: two seeds would look like two samples.
    release, release_sd : float or None
        Mean and standard deviation of x0/L for "gaussian" (None: 0 and 0.1); refused with
        another distribution, where they would mean nothing.
    velocity_sd : float
        Standard deviation [sqrt(gH)] of a random velocity added to each component of the
        release velocity (release_u, release_v).
    wear_bins : int
        Record the per-sample mean wear of the walls in that many bins per wall.
    progress : bool or callable
        True shows a progress bar (tqdm, if installed; else a line on stderr); a callable is
        called with (done, total) work units. Ctrl-C interrupts the run (KeyboardInterrupt).
    geometry : dict, str, path or None
        The funnel's walls, as for :func:`simulate`.
    **model
        Model parameters, as for :func:`simulate`.

    Returns
    -------
    dict
        As ``funnel ensemble --format json`` without "provenance": ``params``,
        ``release_dist``, ``seed``, ``velocity_sd``, ``samples``, one dict {"mean", "std",
        "sem", "min", "max"} per observable of :data:`OBSERVABLES` (the exit ones over the
        exited samples, None when none exited), ``status_counts`` {"exited", "rest",
        "trapped"}, ``total_collisions``, ``simulated_collisions`` (those actually computed:
        mirror-symmetric ensembles simulate half); with ``wear_bins`` the ``wear`` (as in
        :func:`simulate`, per-sample means). With ``per_sample=True`` also ``per_sample``: a
        dict of 1-D arrays of length N in sample order: release (x0/L), u0, v0, status (str)
        and every observable (exit ones NaN where the sample did not exit).

    Examples
    --------
    >>> r = funnel.ensemble(theta=46, samples=400)
    >>> r["duration"]["mean"], r["exit_speed"]["mean"], r["status_counts"]["exited"]
    """
    core = _core()
    if _space(space) == "3d":
        if geometry is not None:
            raise ValueError("invalid geometry: a 2D funnel only (the 3D funnel is the cone of theta and gap)")
        if _wear_bins(wear_bins) != 0:
            raise ValueError(f"invalid wear-bins = {wear_bins}: valid range is 0 in 3d (the wear record is 2D only)")
        release_dist = "disk" if release_dist is None else str(release_dist)
        _gaussian(release_dist, release, release_sd)
        velocity_sd = _scalar("velocity_sd", velocity_sd)
        result = core.ensemble_3d(_model("ensemble", model, "3d"), _count("samples", samples), release_dist,
                                  _count("threads", threads), _flag("per_sample", per_sample),
                                  _seed(seed, release_dist, velocity_sd, "3d"), velocity_sd,
                                  _progress_callback(progress, "ensemble"))
        if per_sample:
            _text_columns(result["per_sample"], ("status",))
        _warn_stalled(result["stalled"], result["samples"],
                      "'stalled' for each sample" if per_sample else "the count 'stalled'; each sample's with per_sample")
        _warn_capped(result["capped"], result["samples"], int(result["params"]["max_collisions"]))
        return result
    release_dist = "line" if release_dist is None else str(release_dist)
    release, release_sd = _gaussian(release_dist, release, release_sd)
    velocity_sd = _scalar("velocity_sd", velocity_sd)
    result = core.ensemble(_model("ensemble", model), _count("samples", samples), release_dist,
                           _count("threads", threads), _flag("per_sample", per_sample),
                           _seed(seed, release_dist, velocity_sd),
                           _scalar("release", release), _scalar("release_sd", release_sd),
                           velocity_sd, _wear_bins(wear_bins),
                           _progress_callback(progress, "ensemble"), _geometry(geometry))
    if per_sample:
        _text_columns(result["per_sample"], ("status",))
    _warn_capped(result["capped"], result["samples"], int(result["params"]["max_collisions"]))
    return result


def _axis_values(name, value):
    """Values of one sweep axis from a number, a sequence, an array or a "a,b"/"start:stop:step" text."""
    if isinstance(value, str):
        return list(_core().parse_values(name, value))
    return [_not_nan(name, v) for v in _axis_numbers(name, value)]


def _axis_numbers(name, value):
    if isinstance(value, (numbers.Real, np.generic)) and not isinstance(value, (bool, np.bool_)):
        return [_scalar(name, value)]
    if isinstance(value, (list, tuple)) and any(isinstance(v, (bool, np.bool_)) for v in value):
        raise TypeError(f"{name} values must be real numbers, not bool")
    array = np.asarray(value)
    if array.dtype == np.bool_:
        raise TypeError(f"{name} values must be real numbers, not bool")
    if array.ndim == 0:
        return [_scalar(name, array.item())]
    if array.ndim != 1:
        raise ValueError(f"invalid {name}: a sweep axis must be one-dimensional, got shape {array.shape}")
    return [_scalar(name, v) for v in array.tolist()]


def sweep(samples=DEFAULT_SAMPLES, release_dist=None, threads=0, seed=None, release=None, release_sd=None,
          velocity_sd=0.0, progress=False, space="2d", geometry=None, **model):
    """One ensemble per point of a parameter grid, like ``funnel sweep``.

    With ``space="3d"`` every point is a 3D ensemble as in :func:`ensemble` (release_dist
    "disk" by default); the columns are the 3D parameters and the statistics of
    :data:`OBSERVABLES_3D_SUMMARIZED`.

    Each model keyword takes a number, a sequence or 1-D array of numbers, or a text
    "a,b,c" or "start:stop:step" (inclusive, as on the command line). The grid is the
    Cartesian product over :data:`MODEL_PARAMETERS` in that order (the last varies fastest),
    whatever the keyword order. The ensemble options are as for :func:`ensemble`.

    Returns
    -------
    dict
        One 1-D numpy array per CSV column of ``funnel sweep``, same names and order, one
        element per grid point: the parameters (float64; max_collisions int64),
        release_dist (str), samples (int64), ``<observable>_<stat>`` (float64; NaN for an exit
        observable of a point where nothing exited) for the observables of
        :data:`OBSERVABLES` and the stats mean, std, sem, min, max, then exited, rest,
        trapped, total_collisions (int64).

    Examples
    --------
    >>> s = funnel.sweep(theta="40:50:1", mu=[0, 1], samples=400)
    >>> s["theta"], s["duration_mean"]
    """
    core = _core()
    if _space(space) == "3d":
        if geometry is not None:
            raise ValueError("invalid geometry: a 2D funnel only (the 3D funnel is the cone of theta and gap)")
        _check_names("sweep", model, "3d")
        release_dist = "disk" if release_dist is None else str(release_dist)
        _gaussian(release_dist, release, release_sd)
        velocity_sd = _scalar("velocity_sd", velocity_sd)
        axes = [(name, _axis_values(name, model[name])) for name in MODEL_PARAMETERS + MODEL_PARAMETERS_3D_ONLY
                if name in model]
        result = _text_columns(core.sweep_3d(axes, _count("samples", samples), release_dist,
                                             _count("threads", threads), _seed(seed, release_dist, velocity_sd, "3d"),
                                             velocity_sd, _progress_callback(progress, "sweep")), ("release_dist",))
        _warn_stalled(int(result["stalled"].sum()), int(result["samples"].sum()), "the column 'stalled'")
        _warn_sweep_capped(result)
        return result
    release_dist = "line" if release_dist is None else str(release_dist)
    release, release_sd = _gaussian(release_dist, release, release_sd)
    velocity_sd = _scalar("velocity_sd", velocity_sd)
    _check_names("sweep", model)
    axes = [(name, _axis_values(name, model[name])) for name in MODEL_PARAMETERS if name in model]
    result = core.sweep(axes, _count("samples", samples), release_dist, _count("threads", threads),
                        _seed(seed, release_dist, velocity_sd), _scalar("release", release),
                        _scalar("release_sd", release_sd), velocity_sd, _progress_callback(progress, "sweep"),
                        _geometry(geometry))
    _warn_sweep_capped(result)
    return _text_columns(result, ("release_dist",))


def _warn_sweep_capped(result):
    """The CappedWarning of a sweep: its runs the collision cap ended, summed over the grid (the
    binding's private count, removed here: the columns are those of the CLI's CSV)."""
    caps = np.unique(result["max_collisions"])
    _warn_capped(int(result.pop("_capped")), int(result["samples"].sum()), int(caps[0]) if len(caps) == 1 else None,
                 stacklevel=4)


def geometry(geometry=None, **model):
    """Derived geometry of the funnel (origin where the two centre lines meet; units of H).

    Returns
    -------
    dict
        theta [deg], sin_t, cos_t, tan_t, radius (a), half_gap (d/2), closed (bool), y_bottom
        (y_b, the edges' height and exit level), y_release (y_0 = y_b + H0), half_width
        (L = y_0 / tan(theta)), y_face_end and x_face_end (C*, lower end of the face region;
        the left one is at -x_face_end). The lower edge points are (+-half_gap, y_bottom).
        For any funnel (also the V) also: source ("v" or the geometry's), symmetric (bool),
        y_exit (the exit level), bottom (the height release_height is measured from),
        x_release_mid (middle of the release line: x0 = x_release_mid + release * half_width)
        and walls {"left", "right"}: each wall's surface as (x, y)
        vertices from the top (0.1 above the release line) down to its lower end. With
        ``geometry`` (as for :func:`simulate`), or a V with two different wall angles or a spout,
        the V's own entries describe the V of ``theta`` only; the walls (their lower ends are the
        edge points) and y_exit describe the funnel itself. A V whose theta_left and theta_right
        are equal is the symmetric V of that angle, and its entries are that angle's.
    """
    return _core().geometry(_model("geometry", model), _geometry(geometry))


def simd_path(path=None):
    """The engine's path for a V funnel's trajectories; with ``path``, choose it first.

    The paths are "scalar" (one trajectory at a time) and, where the CPU runs them, "sse4",
    "avx2" and "avx512" (2, 4 or 8 trajectories in the lanes of a SIMD vector). Every path gives
    the same results bit for bit; the default is the widest (or the environment variable
    FUNNEL_SIMD's). Returns the path in use. A path this CPU does not run raises ValueError
    naming the valid ones (:func:`simd_paths`). Not to be changed while a run is in progress.
    """
    core = _core()
    if path is not None:
        if not isinstance(path, str) or not core.set_simd_path(path):
            raise ValueError(f"invalid simd path = {path!r}: valid values on this CPU are {', '.join(core.simd_paths())}")
    return core.simd_path()


def simd_paths():
    """The engine's paths this CPU runs, narrowest first: ["scalar", "sse4", "avx2", "avx512"] or fewer."""
    return list(_core().simd_paths())


def default_params():
    """The library's default parameters as a dict (the keys of a result's ``params``); as
    keyword arguments: :func:`model_keywords`."""
    return _core().default_params()


def model_keywords(params):
    """The model keyword arguments that run a result's ``params`` again.

    A record's ``params`` is every parameter as used; not all of it is keywords: p_c and
    eps_rest are the library's fixed thresholds, a parameter without a value (None or NaN: the
    V's under a geometry file, theta with both walls' angles) was not used, and theta_left and
    theta_right equal to theta are the V's own angle. This keeps the rest, so that
    ``funnel.ensemble(**funnel.model_keywords(r["params"]), samples=...)`` reruns ``r``'s funnel
    and model (give ``geometry=``, ``space=`` and the ensemble's options again as well).

    >>> r = funnel.ensemble(theta_right=50, samples=400)
    >>> funnel.ensemble(**funnel.model_keywords(r["params"]), samples=400)["duration"] == r["duration"]
    True
    """
    keys = set(MODEL_PARAMETERS) | set(MODEL_PARAMETERS_3D_ONLY)
    out = {k: v for k, v in dict(params).items()
           if k in keys and v is not None and not (isinstance(v, float) and math.isnan(v))}
    for side in ("theta_left", "theta_right"):
        if side in out and "theta" in out and out[side] == out["theta"]:
            del out[side]
    return out


def valid_range(name):
    """Text of a parameter's valid range, e.g. valid_range("theta") -> "0 < theta < 90 (degrees)"."""
    text = _core().valid_range(str(name))
    if not text:
        names = dict.fromkeys([p["key"] for p in PARAMETERS] + list(MODEL_PARAMETERS_3D_ONLY))  # in order, once
        raise ValueError(f"invalid name = {name!r}: not a model parameter; valid names are {', '.join(names)}")
    return text


def version():
    """Version of the compiled library, e.g. "0.1.0"."""
    return _core().version()


def git_commit():
    """Git commit of the sources the module was built from, or "unknown"."""
    return _core().git_commit()


def orbit(theta, beta0=0.0, inertia=0.4, radius=0.01, y_star=0.5):
    """Eigenvalues and stability of the period-2 orbit (e = 1, sticking), like ``funnel orbit``.

    Parameters
    ----------
    theta : float, sequence, 1-D array or "start:stop:step"
        Wall angle(s) in degrees.
    beta0, inertia, radius : float
        Walton's maximum tangential restitution, I/(m a^2) and a/H.
    y_star : float
        Orbit height for the Jacobians (the eigenvalues do not depend on it).

    Returns
    -------
    dict
        theta (n,), eigenvalues (n, 4) complex128 sorted by decreasing modulus, modulus (n, 4),
        stable (n,) bool, jacobian_max_rel_diff (n,): the largest disagreement of the paper's
        printed Jacobian with finite differences.

    Examples
    --------
    >>> o = funnel.orbit([44, 46], beta0=0.31)
    >>> o["stable"]          # array([False,  True])
    """
    thetas = _axis_values("theta", theta)
    if not thetas:
        raise ValueError(f"invalid theta: no values; valid range is {valid_range('theta')}")
    if len(thetas) > 10**6:
        raise ValueError(f"invalid theta: {len(thetas)} values; valid range is at most 10^6 (as funnel orbit)")
    return _core().orbit(thetas, _scalar("beta0", beta0), _scalar("inertia", inertia),
                         _scalar("radius", radius), _scalar("y_star", y_star))


def closed(samples=DEFAULT_SAMPLES, release_dist="line", threads=0, max_time=None, max_coll=None,
           window=20, slip_tol=1e-6, height_tol=1e-6, seed=None, release=None, release_sd=None, geometry=None,
           **model):
    """Long-time state of every release in a closed funnel (gap 0), like ``funnel closed``.

    As there, e defaults to 1 (the paper's Figs. 11 and 12: with e < 1 there is no periodic
    orbit, and each release ends at rest or is undecided), and the caps are max_time (default
    1e4) and max_coll (default 10^7), which the model's names t_max and max_collisions also set
    (giving both names of one cap is an error).
    seed, release and release_sd are those of :func:`ensemble` (the random and gaussian
    releases); geometry (as for :func:`simulate`) must close: both walls end at one point.
    Ctrl-C stops the run within a task of releases and raises KeyboardInterrupt.

    A release is ``periodic`` once ``window`` consecutive collisions alternate walls, have
    |slip| <= slip_tol * speed and repeat the previous height within height_tol (relative; in a
    funnel that is not mirror symmetric, the height two collisions before, on the same wall);
    ``rest`` when it lost all its energy; ``undecided`` if max_time or max_coll came first.

    Returns
    -------
    dict
        params (with the caps as t_max and max_collisions), geometry, release_dist (with seed for
        random releases, release_mean and release_sd for gaussian ones), options {max_time, max_collisions,
        window, slip_tol, height_tol}, periodic_fraction (float), state_counts {periodic, rest,
        undecided}, samples, and per release (n,): release (x0/L), state (str), x_last_over_L,
        x_prev_over_L, y_last, y_prev (the last two collisions' positions: 0 at rest, NaN for one
        a cap left unmade), collisions (int64), time.

    Examples
    --------
    >>> c = funnel.closed(theta=50, e=1, mu=0.1, samples=400)
    >>> c["periodic_fraction"]
    """
    model = dict(model)  # (e defaults to 1 in the library's closed(), where not given)
    caps = {}
    for name, alias, value, default in (("max_time", "t_max", max_time, 1e4),
                                        ("max_coll", "max_collisions", max_coll, 10_000_000)):
        from_alias = alias in model
        if from_alias and value is not None:
            raise ValueError(f"invalid {alias} = {model[alias]}: valid range is one of {alias} and {name}, "
                             f"not both (both set the cap; {name} = {value})")
        cap = model.pop(alias) if from_alias else (default if value is None else value)
        given = alias if from_alias else name
        if name == "max_time" and isinstance(cap, numbers.Real) and not 0 < cap < math.inf:
            raise ValueError(f"invalid {given} = {cap}: valid range is {given} > 0 (finite)")
        caps[name] = (given, cap)
    release_dist = "line" if release_dist is None else str(release_dist)
    release, release_sd = _gaussian(release_dist, release, release_sd)
    result = _core().closed(_model("closed", model), _count("samples", samples), release_dist,
                            _count("threads", threads), _scalar(*caps["max_time"]),
                            _count(*caps["max_coll"]), _count("window", window),
                            _scalar("slip_tol", slip_tol), _scalar("height_tol", height_tol), _seed(seed, release_dist),
                            _scalar("release", release), _scalar("release_sd", release_sd), _geometry(geometry))
    return result


def retrace(theta, max_bounces=6, scan_points=1000, turns="wall", radius=0.01, gap=0.0, threads=0):
    """Self-retracing orbits of the elastic frictionless particle (e = 1, mu = 0), like ``funnel retrace``.

    Released at rest, the particle turns back after k <= max_bounces collisions, either by hitting a
    wall perpendicularly ("wall" turn) or by rising vertically to rest at a second point of the
    release height ("rest" turn), retraces its path and comes back to rest at the release point.
    Every release x0/L in (-1, 1) with such an orbit is found (mirror images included), with its
    period and the stability of the reduced (area-preserving) collision map.

    Parameters
    ----------
    theta : float, sequence, 1-D array or "start:stop:step"
        Wall angle(s) in degrees.
    max_bounces : int
        K, the largest number of collisions up to the turn, 1 <= K <= 20.
    scan_points : int
        Grid points on x0/L in (-1, 0) before refinement, 16 <= N <= 10^6.
    turns : {"wall", "wall,rest"}
        Which turns to find.
    radius, gap : float
        a/H and d/H; gap 0 is the closed funnel, gap > 2a keeps the orbits that stay above the
        faces' lower ends.
    threads : int
        Worker threads over the angles, 0 = all cores; results are bit-identical for any count.

    Returns
    -------
    dict
        ``radius``, ``gap``; ``orbits``: one 1-D array per column of ``funnel retrace --format csv``
        (theta, release = x0/L, sequence (str, e.g. "LRL"), turn (str), bounces, collisions_per_period,
        period [sqrt(H/g)], trace, stable (bool, |trace| < 2), y0 [H], turn_x (x/L of the turn),
        min_height [H], residual [rad], return_position_error [H], return_speed [sqrt(gH)]);
        ``windows``: sequence, turn, bounces, window ("exists" or "stable"), theta_from, theta_to,
        points.

    Examples
    --------
    >>> r = funnel.retrace(60)
    >>> r["orbits"]["sequence"], r["orbits"]["release"], r["orbits"]["stable"]
    """
    thetas = _axis_values("theta", theta)
    if len(thetas) > 10**5:  # as funnel retrace: about 0.5 ms of a core per angle, every orbit held in memory
        raise ValueError(f"invalid theta: {len(thetas)} angles; valid range is at most 100000 angles (each is a scan "
                         "of scan_points releases, and its orbits are held in memory): use a coarser grid, or split it")
    if turns not in ("wall", "wall,rest", "rest,wall", "all"):
        raise ValueError(f"invalid turns = {turns!r}: valid values are wall, wall,rest (or all)")
    result = _core().retrace(thetas, _scalar("radius", radius), _scalar("gap", gap),
                             _count("max_bounces", max_bounces), _count("scan_points", scan_points),
                             turns != "wall", _count("threads", threads))
    _text_columns(result["orbits"], ("sequence", "turn"))
    _text_columns(result["windows"], ("sequence", "turn", "window"))
    return result


def _paper_dir():
    """The figure definitions: $FUNNEL_PAPER_DIR, else an installation's share/funnel/paper
    (found above the package), else the source tree's paper/."""
    if os.environ.get("FUNNEL_PAPER_DIR"):
        return os.environ["FUNNEL_PAPER_DIR"]
    here = os.path.dirname(os.path.abspath(__file__))
    parent = os.path.dirname(here)
    while parent != os.path.dirname(parent):
        candidate = os.path.join(parent, "share", "funnel", "paper")
        if os.path.isdir(candidate):
            return candidate
        parent = os.path.dirname(parent)
    return _core().source_paper_dir


def _csv_columns(text):
    """The columns of a CSV text: float arrays where every value is a number, else lists of str."""
    import csv
    import io
    rows = list(csv.reader(io.StringIO(text)))
    columns = {}
    for i, name in enumerate(rows[0] if rows else []):
        values = [row[i] for row in rows[1:]]
        try:
            columns[name] = np.array([float(v) for v in values])
        except ValueError:
            columns[name] = values
    return columns


def paper_figure(figure, quick=False, threads=0, paper_dir=None, progress=False):
    """The data of one figure of ``funnel paper`` and the check of the paper's claim on it,
    computed by the same library module (the numbers are the CLI's, bit for bit).

    Parameters
    ----------
    figure : str
        A figure id ("fig03", "fig11", "figshape", ...: the names of paper/*.toml) or the path of
        a figure definition (a TOML file, docs/paper.md).
    quick : bool
        The definition's [quick] preview (coarse grids, few samples), as ``funnel paper --quick``.
    threads : int
        Worker threads, 0 = all cores; results are bit-identical for any count.
    paper_dir : str, optional
        Where figure ids are looked up (default: $FUNNEL_PAPER_DIR, an installation's
        share/funnel/paper, else the source tree's paper/).
    progress : bool or callable
        True: a progress bar (tqdm if installed); a callable gets (done, total). Ctrl-C is
        honoured when the figure's computation ends.

    Returns
    -------
    dict
        id, kind, title, caption; ``csv``: the CSV text ``funnel paper`` writes to
        ``<out>/<id>/<id>.csv``; ``columns``: that table as a dict (float arrays, lists of str
        for text columns); ``check``: {"claim", "measured", "holds"}; ``meta``: the figure's
        extra metadata (panels, ...), as in ``<id>.json``.

    Examples
    --------
    >>> f = funnel.paper_figure("fig11", quick=True)
    >>> f["check"]["holds"], f["columns"]["x_last_over_L"][:5]
    """
    import json
    if _count("threads", threads) < 0:
        raise ValueError(f"invalid threads = {threads}: valid range is an integer >= 0 (0 = all cores)")
    figure = os.fspath(figure)
    path = figure
    if not figure.endswith(".toml"):
        base = os.fspath(paper_dir) if paper_dir is not None else _paper_dir()
        path = os.path.join(base, figure + ".toml")
        if not os.path.isfile(path):
            known = sorted(f[:-5] for f in os.listdir(base) if f.startswith("fig") and f.endswith(".toml")) \
                if os.path.isdir(base) else []
            raise ValueError(f"invalid figure = {figure!r}: no {path}; valid: {', '.join(known) or '(none found)'}")
    result = _core().paper_figure(path, _flag("quick", quick), _count("threads", threads),
                                  _progress_callback(progress, "paper " + os.path.basename(path)[:-5]))
    result["columns"] = _csv_columns(result["csv"])
    result["check"] = json.loads(result["check"])
    result["meta"] = json.loads(result["meta"])
    return result
