"""The contract every engine adapter keeps, and the drop scene they all share.

An engine adapter is one module in ``contactalpha.adapters`` holding one object that implements
``EngineAdapter`` (usually by deriving from ``adapters.base.Adapter``, or from
``adapters.stepped.SteppingAdapter`` for a fixed-step engine, which write the derived parts once
for every engine); the engine's record (``adapters.record.Engine``) holds it, and
``contactalpha.adapters.registry.ENGINES`` lists the records.  The front door
(``contactalpha.parameters.front_door``), the command line, the engines study and the tests iterate
that list, so adding an engine is that module plus one line there (``docs/adding-an-engine.md``).

The parts of the contract:

- ``name``: the registry key and the command line's ``--engine`` choice;
- ``law``: the contact law the engine applies (a value of ``contactalpha.laws``' registry);
- ``module``: the Python module of the engine (``import`` tells whether it is installed) and
  ``version()``;
- ``parameters(damping, scene, settings=None)``: the engine's own parameters (its names, its units) that make
  it apply the law with the law's damping parameter ``damping`` (alpha for Hunt-Crossley, the
  damping ratio zeta for the spring-dashpot laws) in ``scene``; numpy arrays go through;
- ``law_damping(scene, target, restitution)``: the law's exact damping parameter for a target
  restitution in ``scene`` (``contactalpha.laws``), with the scene's load factor;
- ``build_drop(scene, params, settings)``: the drop scene built in the engine, the ball at
  touchdown at ``scene.approach_speed``;
- ``run(model, scene, settings)``: the engine's own integration, sampled (``Samples``);
- ``measure(samples, scene)``: the restitutions measured from those samples (``MeasuredImpact``);
- ``static_penetration(scene)``: the deformation at rest under the load, found in the engine
  (the check of the stiffness conversion);
- ``settings``: the default settings (a frozen dataclass) of ``build_drop`` and ``run``;
- ``timestep(settings)``: the engine's fixed step in s, or None for an error-controlled one;
- ``delivered(scene, damping, settings=None)``: the e_N the engine delivers with the law's damping
  (``adapters.base.Delivered``: the mean over touchdown phases for a stepping engine);
- ``calibrate(scene, target, start=None, settings=None, progress=None)``: the parameters refined
  on the engine's own drops, ``(parameters, Refinement, Delivered)``; ``progress`` hears of each drop.

``missing_parts`` names whatever part an object lacks or whose signature differs from the
Protocol's (its parameters, in order, with a default where the Protocol has one; any further
parameter needs a default), and ``parameters`` when it does not take numpy arrays of scenes
(``array_problem``: the batched front door passes them); ``check_adapter`` raises on it.
"""

import inspect
import math
from dataclasses import dataclass, field
from typing import Protocol, runtime_checkable

import numpy as np

from contactalpha.laws import get_law
from contactalpha.validation import check_positive, check_range


@dataclass(frozen=True)
class DropScene:
    """A sphere of ``mass`` dropped on the ground under ``gravity`` plus a constant push ``force``.

    Attributes
    ----------
    mass : kg (> 0).
    stiffness : the contact law's stiffness: N/m for the n = 1 laws, N/m^1.5 for the Hertz ones.
    approach_speed : speed at touchdown, m/s (> 0).
    gravity : m/s^2 (>= 0), downward.
    force : constant downward push on the ball, N (>= 0).
    radius : the sphere's radius, m (> 0): geometry only, except in OpenSim's stiffness.
    """

    mass: float
    stiffness: float
    approach_speed: float
    gravity: float = 9.81
    force: float = 0.0
    radius: float = 0.05

    def __post_init__(self):
        for name in ("mass", "stiffness", "approach_speed", "radius"):
            object.__setattr__(self, name, float(check_positive(name, getattr(self, name))))
        for name in ("gravity", "force"):
            object.__setattr__(
                self, name, float(check_range(name, getattr(self, name), 0.0, math.inf, hi_open=True))
            )

    @property
    def accel(self):
        """Acceleration of the whole load ``g + F/m``, m/s^2."""
        return self.gravity + self.force / self.mass


@dataclass
class Samples:
    """States at report times: ``t`` (s), ``delta`` (m), ``delta_dot`` (m/s); ``seconds`` of wall clock.

    ``extra`` holds what an adapter measures beside the states (steps in contact, warnings).
    """

    t: np.ndarray
    delta: np.ndarray
    delta_dot: np.ndarray
    seconds: float = 0.0
    extra: dict = field(default_factory=dict)


@runtime_checkable
class EngineAdapter(Protocol):
    """What every engine adapter provides (see the module docstring)."""

    name: str
    law: object
    module: str
    settings: object

    def version(self) -> str:
        """The engine's version string; ImportError with the install hint when it is missing."""

    def parameters(self, damping, scene, settings=None) -> dict:
        """The engine's parameters, in its names and units, for the law's ``damping`` in ``scene``."""

    def law_damping(self, scene, target, restitution="kinematic", settings=None):
        """``(DampingSolution, xi)``: the law's exact damping for ``target`` in ``scene``."""

    def build_drop(self, scene, params, settings):
        """The drop built in the engine, the ball at touchdown at ``scene.approach_speed``."""

    def run(self, model, scene, settings) -> Samples:
        """Run the engine on ``model`` and return its sampled states."""

    def measure(self, samples, scene):
        """``MeasuredImpact`` of the first impact in ``samples``."""

    def static_penetration(self, scene) -> float:
        """Deformation (m) at which the engine's contact carries the load ``m a`` at rest."""

    def timestep(self, settings):
        """The engine's fixed step (s), or None when its integrator controls its error."""

    def delivered(self, scene, damping, settings=None):
        """``Delivered``: the e_N the engine delivers with the law's ``damping`` in ``scene``."""

    def calibrate(self, scene, target, start=None, settings=None, progress=None):
        """``(parameters, Refinement, Delivered)``: parameters refined on the engine's own drops.

        ``progress`` (optional) is called with a line as each drop in the engine starts.
        """


# The contract's parts: attributes (data) and methods (callables).
DATA_PARTS = ("name", "law", "module", "settings")
METHOD_PARTS = (
    "version",
    "parameters",
    "law_damping",
    "build_drop",
    "run",
    "measure",
    "static_penetration",
    "timestep",
    "delivered",
    "calibrate",
)


def signature_differs(method, part):
    """True when ``method`` (bound) cannot be called as the Protocol's ``part`` is.

    Its leading parameters must be the Protocol's, by name and in order, with a default wherever
    the Protocol has one; any parameter after them needs a default.
    """
    want = list(inspect.signature(getattr(EngineAdapter, part)).parameters.values())[1:]
    try:
        have = list(inspect.signature(method).parameters.values())
    except (TypeError, ValueError):
        return True
    if len(have) < len(want):
        return not any(p.kind is p.VAR_POSITIONAL for p in have)
    for w, h in zip(want, have[: len(want)], strict=True):
        if h.name != w.name or h.kind not in (h.POSITIONAL_ONLY, h.POSITIONAL_OR_KEYWORD):
            return True
        if w.default is not w.empty and h.default is h.empty:
            return True
    return any(
        p.default is p.empty and p.kind not in (p.VAR_POSITIONAL, p.VAR_KEYWORD) for p in have[len(want) :]
    )


@dataclass(frozen=True)
class _ProbeScenes:
    """What the front door passes to ``parameters``: checked values, scalars or arrays."""

    mass: object
    stiffness: object
    approach_speed: object
    radius: object


# Two scenes ``array_problem`` probes ``parameters`` with, and the law's damping of each.
_PROBE = {
    "mass": (0.5, 2.0),
    "stiffness": (1.0e5, 4.0e6),
    "approach_speed": (0.5, 1.5),
    "radius": (0.02, 0.05),
}
_PROBE_DAMPING = (0.1, 0.3)


def array_problem(adapter):
    """Why ``adapter.parameters`` does not take numpy arrays of scenes row by row ("" when it does).

    Two scenes go in as arrays; each entry of the block must be that of the scene's own call,
    bit for bit: the row ``i`` (the leading axis) of an array, or one value for every scene.
    """
    scenes = [_ProbeScenes(*(v[i] for v in _PROBE.values())) for i in range(2)]
    batch_scene = _ProbeScenes(*(np.array(v) for v in _PROBE.values()))
    try:
        batch = adapter.parameters(np.array(_PROBE_DAMPING), batch_scene)
        ones = [adapter.parameters(d, s) for d, s in zip(_PROBE_DAMPING, scenes, strict=True)]
    except Exception as err:  # what an engine's own code raises on arrays is its own
        return f"it raises {type(err).__name__} on numpy arrays of scenes ({err})"
    for i, one in enumerate(ones):
        if set(one) != set(batch):
            return f"its keys differ between one scene {sorted(one)} and a batch {sorted(batch)}"
        for key, value in one.items():
            got = np.asarray(batch[key])
            row = got if got.ndim == 0 else got[i] if got.shape[0] == 2 else None
            want = np.asarray(value)
            if row is None or row.shape != want.shape or not _same(row, want):
                return f"its {key!r} for a batch of 2 scenes is not each scene's own (row {i})"
    return ""


def _same(a, b):
    if a.dtype.kind in "fc" or b.dtype.kind in "fc":
        return bool(np.array_equal(a.astype(float), b.astype(float), equal_nan=True))
    return bool(np.array_equal(a, b))


def missing_parts(adapter):
    """Names of the contract's parts that ``adapter`` lacks.

    A method must be callable with the Protocol's signature (``signature_differs``), and
    ``parameters`` must take numpy arrays of scenes (``array_problem``).
    """
    missing = [p for p in DATA_PARTS if getattr(adapter, p, None) is None]
    for p in METHOD_PARTS:
        method = getattr(adapter, p, None)
        if not callable(method) or signature_differs(method, p):
            missing.append(p)
    # An impulse engine (``impulse`` set) is answered at its step only, from the scene's load, by
    # ``parameters.impulse``: its ``parameters`` never sees a batch of load-free block scenes.
    if "parameters" not in missing and getattr(adapter, "impulse", None) is None and array_problem(adapter):
        missing.append("parameters")
    return missing


def check_adapter(adapter):
    """Return ``adapter`` if it keeps the contract; TypeError naming the missing parts otherwise."""
    missing = missing_parts(adapter)
    if missing:
        why = (
            array_problem(adapter)
            if "parameters" in missing and callable(getattr(adapter, "parameters", None))
            else ""
        )
        raise TypeError(
            f"engine adapter {adapter!r} misses part(s) of the contract or has them with another "
            f"signature (adapters.contract.EngineAdapter): {', '.join(missing)}"
            + (f"; parameters: {why}" if why else "")
        )
    return adapter


def drop(adapter, scene, params, settings=None):
    """One drop in the engine: ``(MeasuredImpact, Samples)`` from the adapter's three steps."""
    settings = adapter.settings if settings is None else settings
    model = adapter.build_drop(scene, params, settings)
    samples = adapter.run(model, scene, settings)
    return adapter.measure(samples, scene), samples


def law_damping(law, scene, target, restitution="kinematic", *, per_unit_mass=False):
    """The law's exact damping for ``target`` in ``scene`` (``law.damping_for``) and the load factor.

    Parameters
    ----------
    law : contactalpha.laws.ContactLaw or str
    scene : DropScene
    target : float
        Target restitution (Newton's e_N by default).
    restitution : {"kinematic", "energetic"}
    per_unit_mass : bool
        True for a law written per unit mass (MuJoCo's): it sees mass 1 and stiffness k/m.

    Returns
    -------
    (DampingSolution, float)
        The law's solution (``.damping``, ``.status``) and the load factor xi.
    """
    law = get_law(law)
    m, k = (1.0, scene.stiffness / scene.mass) if per_unit_mass else (scene.mass, scene.stiffness)
    xi = float(law.scene_load_factor(m, k, scene.approach_speed, scene.accel))
    return law.damping_for(target, xi, restitution), xi
