"""Round trips in the stepping engines (MuJoCo, Drake's discrete plant, PyBullet) at their own step.

For each target e_N and scaled load ``A = a / (omega v)`` (omega^2 = k/m) a drop scene is built
whose contact spans ``steps`` of the engine's default step (``scene_for``).  Three parameter sets
go into the engine, and the mean e_N over touchdown phases is measured (``adapters.stepped``):

- ``law``: the continuous law's exact inverse at the scene's load (``ContactLaw.damping_for``);
- ``refined``: that damping refined by secant steps on the engine's own drops (``calibrate``);
- ``usual``: the engine's usual mapping of a restitution, a registered model (``USUAL``:
  ``contactalpha.models.engine_mappings``): MuJoCo's dampratio and Bullet's damping by the classic
  ``zeta = -ln e / sqrt(pi^2 + ln^2 e)``, Drake's bound "1/d is the bounce speed", ``alpha = 1/e``.
"""

import math
import time
import warnings

import numpy as np
import xarray as xr

from contactalpha.adapters.contract import DropScene
from contactalpha.adapters.registry import adapter, installed
from contactalpha.adapters.stepped import ContactStepsWarning
from contactalpha.models.registry import ALL_MODELS

# Engines with a fixed step, and the steps their test scenes' contacts span (Bullet's and Drake's
# implicit steps lose too much at 30 even without damping: e_N = 0.8 is then out of reach).
STEPS = {"mujoco": 30, "drake": 60, "pybullet": 60}
TARGETS = (0.2, 0.5, 0.8)
LOADS = (0.05, 0.3, 0.6)


# Engine -> the registered model of its usual mapping of a restitution to the law's damping.
USUAL = {"mujoco": "mujoco_dampratio", "drake": "drake_bound", "pybullet": "classic_zeta"}
# Per-scene variables: name -> (units, meaning).
FIELDS = {
    "xi": ("1", "the law's load factor of the scene"),
    "damping_law": ("1", "the law's exact damping parameter (continuous)"),
    "e_n_law": ("1", "mean e_N the engine delivers with the law's damping"),
    "damping_refined": ("1", "damping refined on the engine's drops (NaN: target unreachable)"),
    "e_n_refined": ("1", "mean e_N the engine delivers with the refined damping"),
    "damping_usual": ("1", "damping of the engine's usual mapping"),
    "e_n_usual": ("1", "mean e_N the engine delivers with the usual mapping"),
    "spread": ("1", "max - min of e_N over touchdown phases, refined damping"),
    "contact_steps": ("1", "steps in contact, refined damping"),
    "iterations": ("1", "engine evaluations of the refinement"),
    "seconds": ("s", "wall time of the adapter for the scene (law, refinement, check)"),
}


def scene_for(engine, A, steps=None, mass=0.5, gravity=9.81):
    """Drop scene whose contact spans ``steps`` of the engine's step, with scaled load ``A``.

    omega = pi / (steps h); the approach speed makes gravity alone A = 0.05; a push adds the rest.
    """
    a = adapter(engine)
    h = a.timestep(a.settings)
    omega = math.pi / ((steps or STEPS[engine]) * h)
    v = gravity / (0.05 * omega)
    return DropScene(mass, mass * omega**2, v, gravity, mass * (A * omega * v - gravity), 0.05)


def round_trips(engine, targets=TARGETS, loads=LOADS):
    """Every (target, load) of ``engine``; a Dataset over ``target`` and ``load`` (``FIELDS``)."""
    a = adapter(engine)
    if not installed(a):
        raise ImportError(f"{engine} is not installed")
    shape = (len(targets), len(loads))
    out = {name: np.full(shape, np.nan) for name in FIELDS}
    for i, e in enumerate(targets):
        for j, A in enumerate(loads):
            sc = scene_for(engine, A)
            start = time.perf_counter()
            law = a.law if engine != "mujoco" else a.law.with_impedance(a.settings.impedance)
            xi = float(law.load_factor(A))
            p_law = float(law.damping_for(e, xi, "kinematic").damping)
            with warnings.catch_warnings():
                warnings.simplefilter("ignore", ContactStepsWarning)
                _, ref, got = a.calibrate(sc, e, p_law)
            seconds = time.perf_counter() - start
            model = ALL_MODELS[USUAL[engine]]
            p_usual = float(model.fn(np.array(e), np.array(xi)))
            usual = a.delivered(sc, p_usual)
            values = {
                "xi": xi,
                "damping_law": p_law,
                "e_n_law": ref.e_n_start,
                "damping_refined": ref.damping,
                "e_n_refined": got.e_n if math.isfinite(ref.damping) else np.nan,
                "damping_usual": p_usual,
                "e_n_usual": usual.e_n,
                "spread": got.spread,
                "contact_steps": got.contact_steps,
                "iterations": ref.iterations,
                "seconds": seconds,
            }
            for name, value in values.items():
                out[name][i, j] = value
    ds = xr.Dataset(
        {
            name: (("target", "load"), out[name], {"units": u, "long_name": d})
            for name, (u, d) in FIELDS.items()
        },
        coords={
            "target": ("target", list(targets), {"long_name": "target e_N"}),
            "load": ("load", list(loads), {"long_name": "scaled load A = a / (omega v)"}),
        },
    )
    ds.attrs.update(
        engine=engine,
        law=a.law.name,
        damping=a.law.damping,
        version=a.version(),
        timestep=a.timestep(a.settings),
        steps_per_contact=STEPS[engine],
    )
    return ds
