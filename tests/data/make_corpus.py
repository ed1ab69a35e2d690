"""The number corpus: every number the public API gives on a fixed set of inputs, bit for bit.

Regenerate (only when a change of numbers is meant; say why in the commit) from the repository
root::

    python tests/data/make_corpus.py

It writes ``tests/data/corpus.json``: ``{part: {key: [kind, shape, values]}}`` with every float as
``float.hex`` (exact; NaN as "nan"), so a corpus compares bit for bit and its diff reads by key
(the test compares shape and values; ``kind``, the Python type, is for the reader).
``tests/test_corpus.py`` recomputes each part with the code of the day and compares.  Parts:

- ``default``: ``contact_parameters`` for every law of ``contactalpha.LAWS`` (scalar, both
  restitutions, a force, a batch with a row no damping reaches) and for every engine of each law
  (``engine=``), at the step of every steppable engine (``timestep=``: scalar and batch, both
  restitutions, the engine's default step and a given one), ``alpha`` for every model of
  ``models.registry.ALL_MODELS``, ``critical_speed`` for every law and ``predict_bounces``;
- ``model_file``: ``mechanism.read_contact`` and ``mechanism.tune``'s reduced-model answer (no
  engine loop, no check drop) on the shipped test models; needs MuJoCo and Drake;
- ``jax``: the JAX front door ``contactalpha.xla.contact_parameters`` for every law, float64;
  needs JAX.

A part whose engine is missing here is kept as it is in the file (a note on stderr).  Keys name
the law, engine or model they come from, so a law, an engine or a model added later only adds
keys, which the test leaves alone.
"""

import dataclasses
import importlib.util
import json
import sys
import warnings
from pathlib import Path

import numpy as np

HERE = Path(__file__).resolve().parent
CORPUS = HERE / "corpus.json"
# Entries that differ on a host of another SIMD level (``host_level``), by level and part.
HOSTS = HERE / "corpus_hosts.json"
MODELS = HERE / "models"

# One scene per law: mass (kg), approach speed (m/s), load (m/s^2), radius (m); the stiffness by
# the law's exponent (N/m^1.5 for n = 3/2, N/m for n = 1).
MASS, SPEED, ACCEL, RADIUS, FORCE = 0.5, 0.5, 9.81, 0.05, 3.0
STIFFNESS = {1.0: 1e5, 1.5: 1.4e8}
# A batch: three scenes and a row (e_N = 0.999 at a heavy load) where no damping may reach.
BATCH_TARGETS = (0.3, 0.6, 0.9, 0.999)
BATCH_SPEEDS = (0.2, 0.5, 1.0, 0.05)
BATCH_ACCELS = (9.81, 9.81, 100.0, 2000.0)
# At the step: a soft contact of several steps at every engine's default step, and a given step.
STEP_STIFFNESS, STEP_SPEED = 1e4, 0.5
TIMESTEPS = ("default", 5e-4)
STEP_TARGETS = (0.3, 0.6, 0.9)
STEP_SPEEDS = (0.4, 0.5, 1.0)
# alpha(eps, xi) of every model: one point and a row of points.
ALPHA_POINT = (0.6, 0.3)
ALPHA_ROW = ((0.2, 0.6, 0.95), (0.0, 0.3, 0.9))


# ---- values to tokens ------------------------------------------------------------------------
# Fields of prose (why a row has no answer): wording, not numbers; ``ok``/``reached`` and the
# statuses carry the fact.
PROSE = ("reason", "unreachable")


def _token(x):
    """One scalar as an exact, comparable token (floats by ``float.hex``; NaN is "nan")."""
    if x is None:
        return "none"
    if isinstance(x, bool | np.bool_):
        return f"bool:{bool(x)}"
    if isinstance(x, int | np.integer):
        return f"int:{int(x)}"
    if isinstance(x, float | np.floating):
        return float(x).hex()
    if isinstance(x, str | np.str_):
        return f"str:{x}"
    raise TypeError(f"corpus: no token for {type(x).__name__} {x!r}")


def leaves(prefix, value, out):
    """Flatten ``value`` into ``out[key] = [kind, shape, tokens]`` under ``prefix``."""
    if dataclasses.is_dataclass(value) and not isinstance(value, type):
        for f in dataclasses.fields(value):
            if f.name not in PROSE:
                leaves(f"{prefix}/{f.name}", getattr(value, f.name), out)
    elif isinstance(value, dict):
        for k in sorted(value, key=str):
            leaves(f"{prefix}/{k}", value[k], out)
    elif isinstance(value, np.ndarray) or hasattr(value, "__array__") and not isinstance(value, str):
        a = np.asarray(value)
        out[prefix] = [f"array:{a.dtype.kind}", list(a.shape), [_token(x) for x in a.ravel().tolist()]]
    elif isinstance(value, tuple | list):
        flat = [v for v in value if not isinstance(v, tuple | list | dict | np.ndarray)]
        if len(flat) == len(value):
            out[prefix] = [type(value).__name__, [len(value)], [_token(x) for x in value]]
        else:
            for i, v in enumerate(value):
                leaves(f"{prefix}/{i}", v, out)
    else:
        out[prefix] = [type(value).__name__, [], [_token(value)]]


# ---- the cases: (part, key, call) ---------------------------------------------------------------
# Parts: "default" runs in the README's test command (no engine, no JAX, formula-speed paths);
# "heavy" holds the package's own slow paths (an eps batch at the step, the linear law's critical
# speed), run with the integration tests.
def _stiffness(law):
    return STIFFNESS[law.exponent]


def _reads_radius(law):
    from contactalpha.adapters.registry import check_radius_used

    try:
        check_radius_used(law, RADIUS)
    except ValueError:
        return False
    return True


def _law_cases(ca, law):
    k = _stiffness(law)
    geometry = {"radius": RADIUS} if _reads_radius(law) else {}
    scene = dict(mass=MASS, stiffness=k, approach_speed=SPEED, **geometry)
    batch = dict(approach_speed=np.array(BATCH_SPEEDS), accel=np.array(BATCH_ACCELS))
    calls = {
        "e_N": dict(e_N=0.6, accel=ACCEL),
        "eps": dict(eps=0.6, accel=ACCEL),
        "force": dict(e_N=0.8, force=FORCE),
        "unloaded": dict(eps=0.4, accel=0.0),
        "batch_e_N": dict(e_N=np.array(BATCH_TARGETS), **batch),
        "batch_eps": dict(eps=np.array(BATCH_TARGETS), **batch),
    }
    for case, kw in calls.items():
        call = _call(ca.contact_parameters, **{**scene, **kw}, law=law.name)
        yield "default", f"law/{law.name}/{case}", call
    three = dict(e_N=np.array(BATCH_TARGETS[:3]), approach_speed=np.array(BATCH_SPEEDS[:3]), accel=ACCEL)
    for engine in ca.contact_parameters(e_N=0.6, accel=ACCEL, **scene, law=law.name).engines:
        yield (
            "default",
            f"engine/{engine}/scalar",
            _call(ca.contact_parameters, e_N=0.6, accel=ACCEL, engine=engine, **scene),
        )
        yield (
            "default",
            f"engine/{engine}/batch",
            _call(ca.contact_parameters, **{**scene, **three}, engine=engine),
        )


def _step_cases(ca, engine):
    from contactalpha.adapters.registry import adapter
    from contactalpha.stepping.registry import stepper

    reads = _reads_radius(adapter(engine).law) or stepper(engine).needs_radius
    scene = dict(
        mass=MASS,
        stiffness=STEP_STIFFNESS,
        accel=ACCEL,
        engine=engine,
        **({"radius": RADIUS} if reads else {}),
    )
    for h in TIMESTEPS:
        for restitution in ("e_N", "eps"):
            key = f"step/{engine}/{h}/{restitution}"
            yield (
                "default",
                f"{key}/scalar",
                _call(
                    ca.contact_parameters,
                    approach_speed=STEP_SPEED,
                    timestep=h,
                    **{restitution: 0.6},
                    **scene,
                ),
            )
            # An eps target's batch is solved one scene at a time on the map's phase sweeps.
            part = "heavy" if restitution == "eps" else "default"
            batch = {"approach_speed": np.array(STEP_SPEEDS), restitution: np.array(STEP_TARGETS)}
            yield part, f"{key}/batch", _call(ca.contact_parameters, timestep=h, **batch, **scene)


def _model_cases(ca):
    from contactalpha.models.registry import ALL_MODELS

    row = [np.array(r) for r in ALPHA_ROW]
    for name, model in ALL_MODELS.items():
        for restitution in model.restitutions:
            key = f"alpha/{name}/{restitution}"
            kw = dict(model=name, restitution=restitution)
            yield "default", f"{key}/point", _call(ca.alpha, *ALPHA_POINT, **kw)
            yield "default", f"{key}/row", _call(ca.alpha, *row, **kw)


def _threshold_cases(ca):
    row = np.array(BATCH_TARGETS[:3])
    for law in ca.LAWS:
        k = _stiffness(law)
        # The linear law's threshold integrates impacts in a bisection: the heavy part.
        part = "heavy" if law.name == "hunt_crossley_linear" else "default"
        key = f"critical_speed/{law.name}"
        yield part, f"{key}/point", _call(ca.critical_speed, 0.6, MASS, k, ACCEL, law=law.name)
        yield part, f"{key}/row", _call(ca.critical_speed, row, MASS, k, ACCEL, law=law.name)
    for model in ("exact", "hunt_crossley", "closed_form"):
        yield "default", f"bounces/{model}", _call(ca.predict_bounces, ca.Scene(), model)


def _call(fn, *args, **kwargs):
    return lambda: fn(*args, **kwargs)


def package_cases():
    """``(part, key, call)`` of the package's own numbers (no engine, no JAX): "default" and "heavy"."""
    import contactalpha as ca
    from contactalpha.stepping.registry import STEPPER_NAMES

    for law in ca.LAWS:
        yield from _law_cases(ca, law)
    for engine in STEPPER_NAMES:
        yield from _step_cases(ca, engine)
    yield from _model_cases(ca)
    yield from _threshold_cases(ca)
    yield from _impulse_cases(ca)


def _impulse_cases(ca):
    """The impulse engines (no continuous block): answered at their default step, on their maps."""
    from contactalpha.parameters.impulse import impulse_engines

    scene = dict(mass=MASS, stiffness=STIFFNESS[1.5], approach_speed=SPEED)
    for engine in impulse_engines():
        call = _call(ca.contact_parameters, e_N=0.6, accel=ACCEL, engine=engine, timestep="default", **scene)
        yield "heavy", f"engine/{engine}/scalar", call


def evaluate(cases):
    """``{key: entry}`` of ``(part, key, call)`` cases (warnings silenced: the numbers are the point)."""
    out = {}
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        for _, key, call in cases:
            leaves(key, call(), out)
    return out


def part_of(name):
    """``{key: entry}`` of one package part."""
    return evaluate(c for c in package_cases() if c[0] == name)


# ---- the model-file part: the reader and the reduced model's tuning ----------------------------
# (file, pair, qvel, forces, engines to tune for with their stiffness in N/m; None: the model's own)
MODEL_FILES = (
    ("pendulum.xml", ("wall", "tip"), (1.6,), {"arm": (-20.0, 0.0, 0.0)}, {"mujoco": None}),
    ("leg.xml", ("floor", "foot"), (-0.8, 0, 0), {}, {"mujoco": 5e4}),
    ("pendulum.sdf", ("wall", "tip"), (1.6,), {"arm": (-20.0, 0.0, 0.0)}, {"drake": 5e4}),
    ("arm.urdf", ("floor", "tip"), (1.6,), {}, {"drake": 4e4, "pybullet": 4e4}),
)
MODEL_FILE_TARGETS = (0.3, 0.6)


def model_file_part():
    """``{key: entry}`` of the model-file part (needs MuJoCo and Drake to read, PyBullet to tune)."""
    from contactalpha.mechanism import read_contact, tune

    out = {}
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        for name, pair, qvel, forces, engines in MODEL_FILES:
            path = MODELS / name
            contact = read_contact(path, pair, qvel=qvel, forces=forces)
            leaves(f"read/{name}", _portable(contact), out)
            for engine, k in engines.items():
                for target in MODEL_FILE_TARGETS:
                    got = tune(path, pair, target, qvel=qvel, forces=forces, engine=engine, stiffness=k)
                    fields = ("parameters", "delivered", "timestep", "reached", "discrete")
                    for f in fields:
                        leaves(f"tune/{name}/{engine}/{target}/{f}", getattr(got, f), out)
    return out


def _portable(contact):
    """The contact's numbers without its path (the checkout's folder)."""
    return {f.name: getattr(contact, f.name) for f in dataclasses.fields(contact) if f.name != "model"}


# ---- the JAX part: the batched front door --------------------------------------------------------
JAX_MASSES = (0.5, 1.0, 0.2)
JAX_SPEEDS = (0.5, 0.3, 1.2)
JAX_TARGETS = (0.6, 0.9, 0.3)


def jax_part():
    """``{key: entry}`` of the JAX front door, float64 (needs JAX)."""
    import jax

    jax.config.update("jax_enable_x64", True)
    import contactalpha as ca
    from contactalpha import xla

    out = {}
    for law in ca.LAWS:
        for restitution in ("kinematic", "energetic"):
            scene = (
                np.array(JAX_MASSES),
                _stiffness(law),
                np.array(JAX_SPEEDS),
                ACCEL,
                np.array(JAX_TARGETS),
            )
            got = xla.contact_parameters(*scene, law=law.name, restitution=restitution)
            leaves(f"xla/{law.name}/{restitution}", jax.tree_util.tree_map(np.asarray, got), out)
    return out


# Each part: how to make it and the modules it needs.
PARTS = {
    "default": (lambda: part_of("default"), ()),
    "heavy": (lambda: part_of("heavy"), ()),
    "model_file": (model_file_part, ("mujoco", "pydrake", "pybullet")),
    "jax": (jax_part, ("jax",)),
}


def missing(part):
    """The modules a part needs that are not installed here."""
    return [m for m in PARTS[part][1] if importlib.util.find_spec(m) is None]


def load():
    """The stored corpus, ``{part: {key: entry}}``."""
    return json.loads(CORPUS.read_text(encoding="utf-8"))


def host_level():
    """This host's SIMD level as NumPy dispatches its vectorised functions (``X86_V4``, ...).

    NumPy and numba pick their code by the CPU at run time, and a last bit that differs between
    levels is spread to thousands of ulp by a root-find downstream.  So bits are compared
    between hosts of one level.
    """
    import platform

    try:
        from numpy._core._multiarray_umath import __cpu_features__ as features
    except ImportError:  # an older NumPy
        return platform.machine()
    levels = [name for name in ("X86_V2", "X86_V3", "X86_V4") if features.get(name)]
    return levels[-1] if levels else platform.machine()


def load_hosts():
    """``{"made_on": level of corpus.json, "levels": {level: {part: {key: entry}}}}``."""
    if not HOSTS.exists():
        return {"made_on": None, "levels": {}}
    return json.loads(HOSTS.read_text(encoding="utf-8"))


def expected(part, level=None):
    """The entries of ``part`` this host must give: the corpus, with its level's overrides.

    ``None`` when this host's level is neither the corpus's nor one recorded here.
    """
    hosts = load_hosts()
    level = level or host_level()
    base = load()[part]
    if level == hosts["made_on"]:
        return base
    if level not in hosts["levels"]:
        return None
    return base | hosts["levels"][level].get(part, {})


def record_host(level=None):
    """Store the entries this host's level gives differently from corpus.json (same code)."""
    level = level or host_level()
    hosts, stored = load_hosts(), load()
    if level == hosts["made_on"]:
        raise SystemExit(f"make_corpus: {level} made corpus.json; nothing to record")
    overrides = {}
    for part, (make, _) in PARTS.items():
        if missing(part):
            raise SystemExit(f"make_corpus: {part} needs {', '.join(missing(part))}: install it first")
        got = make()
        overrides[part] = {k: got[k] for k in stored[part] if k in got and got[k][1:] != stored[part][k][1:]}
        print(f"make_corpus: {level} {part}: {len(overrides[part])} entries differ", file=sys.stderr)
    hosts["levels"][level] = overrides
    HOSTS.write_text(json.dumps(hosts, indent=1, sort_keys=True) + "\n", encoding="utf-8")


def main(path=CORPUS):
    stored = load() if CORPUS.exists() else {}
    corpus = {}
    for part, (make, _) in PARTS.items():
        lacking = missing(part)
        if lacking:
            print(f"make_corpus: {part}: {', '.join(lacking)} not installed; kept as stored", file=sys.stderr)
            if part in stored:
                corpus[part] = stored[part]
            continue
        corpus[part] = make()
        print(f"make_corpus: {part}: {len(corpus[part])} entries", file=sys.stderr)
    Path(path).write_text(dumps(corpus), encoding="utf-8")


def dumps(corpus):
    """The corpus as JSON with one entry a line (a change of numbers reads as a diff by key)."""
    lines = []
    for part in sorted(corpus):
        entries = corpus[part]
        body = ",\n".join(f"  {json.dumps(k)}: {json.dumps(entries[k])}" for k in sorted(entries))
        lines.append(f"{json.dumps(part)}: {{\n{body}\n}}")
    return "{\n" + ",\n".join(lines) + "\n}\n"


if __name__ == "__main__":
    if sys.argv[1:] == ["--host"]:
        record_host()
    else:
        main(sys.argv[1] if len(sys.argv) > 1 else CORPUS)
