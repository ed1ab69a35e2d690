"""Compile (or load from numba's cache) every kernel the workflow's jobs run, once, and time it.

A fresh clone has an empty numba cache.  Without a warm-up, the first jobs of
``snakemake -c2`` (the surface chunks, Fig. 9, the ball) each compile the same
kernels at the same time, and a cold compile of the impact and solver kernels
alone costs about 20 s of CPU per process.  The workflow's ``numba_warmup`` job
runs :func:`warm_up` once before them; they then load the compiled code from
the cache (``engine/jitcache.py`` keys it on the package sources, so an edit
recompiles).  Its timings are the compile times the benchmarks report apart.

Each entry point is called with a tiny valid input through its public or
kernel-level function (``laws``: every contact law, scalar and batched, both
restitutions): its scalar path and its array path (one jitted row loop,
whichever number of threads runs it: ``engine/threads.py``).  Values are not
checked here: the tests do that.
"""

import dataclasses
import time
from typing import Any

import numpy as np

from contactalpha.engine import boundary, driver, exact, firstcall, solver, table
from contactalpha.engine.scaling import influence_factor
from contactalpha.models import closed_form, registry, shen
from contactalpha.scene import ball, threshold

# One point inside every kernel's domain: eps, xi; scene-level kernels take the paper's ball.
EPS, XI = 0.5, 0.2
BALL = ball.Scene()
# A scene's parameters for each engine's step map (its slots by name), and its front door's scene.
_WARM_PARAMS = {
    "mujoco": {"stiffness": 4e4, "damping": 80.0, "impedance": 0.9},
    "pybullet": {"mass": 0.5, "stiffness_ball": 2e3, "damping_ball": 1.0, "stiffness_ground": 2e3,
                 "damping_ground": 1.0, "breaking": 1.7e-3},
    "drake": {"mass": 0.5, "stiffness_ball": 2e4, "dissipation_ball": 0.5, "stiffness_ground": 2e4,
              "dissipation_ground": 0.5},
}  # fmt: skip
_WARM_SCENE: dict[str, Any] = {
    "mass": 0.5,
    "stiffness": 2e4,
    "approach_speed": 0.5,
    "accel": 9.81,
    "e_N": 0.5,
}
# The sphere's radius, m, for an engine whose map reads it (``Stepper.needs_radius``).
_WARM_RADIUS = 0.05


def _points(n, value):
    """``n`` copies of ``value``: an array input."""
    return np.full(n, value)


def _impact():
    driver.impact(1.0, XI)
    driver.impact(_points(2, 1.0), XI)
    driver.trajectory(1.0, XI)


def _solver():
    for restitution in ("energetic", "kinematic"):
        solver.solve_alpha(EPS, XI, restitution=restitution)
        solver.solve_alpha(_points(2, EPS), XI, restitution=restitution)


def _tables():
    for restitution in ("energetic", "kinematic"):
        table.alpha_tabulated(EPS, XI, restitution=restitution)
        table.alpha_tabulated(_points(2, EPS), XI, restitution=restitution)


def _models():
    for name, model in registry.MODELS.items():
        if model.solver:
            continue  # the solver: part "engine" warms it, and this part must not compile it again
        registry.alpha(_points(2, EPS), XI, model=name)
    closed_form.alpha_closed_form(EPS, XI)
    shen.eq40_gradient(_points(2, EPS), XI)  # the Eq. 40 refit's Jacobian
    exact.alpha_exact(_points(1, EPS))
    exact.restitution_exact(_points(1, 1.0))


def _boundary():
    boundary.separation_boundary(_points(1, XI))
    threshold.critical_speed(EPS, BALL.mass, BALL.stiffness, BALL.gravity)


def _laws():
    # Every contact law's first calls through the front door, scalar and batched, both
    # restitutions (the batch takes the tables, the scalar the family's exact solver), and the
    # closed-form forward map of the piecewise-linear laws.
    from contactalpha.laws import LAWS
    from contactalpha.parameters.front_door import contact_parameters

    scene: dict[str, Any] = {"mass": 0.5, "stiffness": 1.0e6, "approach_speed": 0.5, "accel": 9.81}
    batch = {name: _points(2, value) for name, value in scene.items()}
    for law in LAWS:
        for key in ("eps", "e_N"):
            one: dict[str, Any] = {key: EPS}
            contact_parameters(**one, **scene, law=law.name)
            contact_parameters(**{key: _points(2, EPS)}, **batch, law=law.name)
            if law.fast is not None and law.fast.exact_inverse is not None:
                restitution = "kinematic" if key == "e_N" else "energetic"
                law.fast_restitution(_points(2, 0.3), _points(2, XI), restitution)


def _stepping():
    # Every engine's kernels apart (``stepping.kernels.for_engine``): its drops, its phase mean drop
    # by drop and the inverse on it, its piecewise-affine mean and the batch inverse where it has
    # them, and its front door at the step, one scene and a batch (what ``tune`` solves too).
    from contactalpha.parameters.front_door import contact_parameters
    from contactalpha.stepping.batch_inverse import solve_batch
    from contactalpha.stepping.delivered import at_phases, over_phase
    from contactalpha.stepping.inverse import damping_for
    from contactalpha.stepping.registry import STEPPERS

    for s in STEPPERS:
        p, h = s.pack(**_WARM_PARAMS[s.name]), s.timestep
        s.drop(p, h, 0.3, 0.5, 9.81, 1000)
        at_phases(s.name, p, h, _points(2, 0.5), 0.5, 9.81)
        over_phase(s.name, p, h, 0.5, 9.81)
        damping_for(s.name, p, h, 0.5, 9.81, 0.5)
        if s.affine:
            solve_batch(s, np.tile(p, (2, 1)), h, _points(2, 0.5), _points(2, 9.81), _points(2, 0.5))
        if s.from_block is not None:
            scene = {**_WARM_SCENE, "radius": _WARM_RADIUS} if s.needs_radius else _WARM_SCENE
            contact_parameters(**scene, engine=s.name, timestep=h)
            batch: dict[str, Any] = {name: _points(2, value) for name, value in scene.items()}
            contact_parameters(**batch, engine=s.name, timestep=h)


def _scene():
    # The paper's ball (Sect. 6) for a few milliseconds: its kernel calls from Python.
    ball.simulate(dataclasses.replace(BALL, t_end=0.01), "exact")


# Label -> warm-up call, in the order the workflow's jobs first need them.
ENTRY_POINTS = {
    "impact": _impact,
    "solver": _solver,
    "tables": _tables,
    "models": _models,
    "boundary": _boundary,
    "scene": _scene,
    "laws": _laws,
    "stepping": _stepping,
    "scaling": lambda: influence_factor(BALL.mass, BALL.stiffness, BALL.approach_speed, BALL.gravity),
}


# The warm-up in two parts, for two processes at once (the workflow's two jobs): the impact
# kernel, the solver and the table lookups (which reuse much of their code), and the models,
# the separation boundary and the ball, which compile some of it again.  Measured on an empty
# cache, the two at once on 2 cores: 15.3 and 13.1 s; other splits: 16.1/15.9 s (the boundary
# with the lookups) and 17.5/13.5 s (the boundary and the ball with the impact kernel).
PARTS = {
    "engine": ("impact", "solver", "tables", "stepping"),
    "models": ("models", "boundary", "scene", "scaling", "laws"),
}


def warm_up(entry_points=None, progress=None):
    """Call every entry point once and return the seconds each took.

    Parameters
    ----------
    entry_points : iterable of str, optional
        Keys of ``ENTRY_POINTS`` (default: all), e.g. a value of ``PARTS``.
    progress : callable, optional
        Called with ``(label, seconds)`` after each entry point.

    Returns
    -------
    dict
        ``{label: seconds}``: compile time on a cold cache, load time on a warm one.

    Raises
    ------
    ValueError
        For an unknown entry point name.
    """
    names = list(ENTRY_POINTS if entry_points is None else entry_points)
    unknown = [n for n in names if n not in ENTRY_POINTS]
    if unknown:
        raise ValueError(f"unknown warm-up entry points {unknown}; valid: {sorted(ENTRY_POINTS)}")
    seconds = {}
    for name in names:
        t0 = time.perf_counter()
        with firstcall.compiled_only():  # the scalar paths too, not their Python twins
            ENTRY_POINTS[name]()
        seconds[name] = time.perf_counter() - t0
        if progress is not None:
            progress(name, seconds[name])
    return seconds
