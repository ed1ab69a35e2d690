"""The ball's answers for any contact law but the default: advice, critical speed, bounce sequence.

``advise``, ``critical_speed`` and ``predict_bounces`` take ``law=`` and hand every law but the
default (Hunt-Crossley, n = 3/2, whose own code stays as it was) to the functions here
(``contact_parameters``' path for such a law is ``parameters.one_scene``).  A scene's
``stiffness`` is the law's physical one: N/m for the linear laws (MuJoCo's soft contact included),
N/m^1.5 for the Hertz laws; its load enters as the scaled load ``A = a delta_s / v^2`` of the
law's own scaling (``ContactLaw.load``).
"""

from dataclasses import asdict, dataclass

import numpy as np

from contactalpha.engine.codes import NO_BRACKET, OK, STATUS
from contactalpha.laws import get_law
from contactalpha.laws.maps import damping_for_unchecked


@dataclass(frozen=True)
class LawVerdict:
    """One registered model of a law in one scene: its damping, what it delivers, whether adequate."""

    name: str
    uses_xi: bool
    damping: float
    delivered: float
    state: str
    error: float
    adequate: bool


@dataclass(frozen=True)
class LawAdvice:
    """``advise`` for a law of the family: the exact damping and every model of that law, judged."""

    law: str
    eps: float
    restitution: str
    xi: float
    tol: float
    exact_damping: float
    exact_state: str
    models: tuple
    cheapest: str | None

    def to_dict(self):
        """Plain data (for ``--json``)."""
        return asdict(self)


def law_advise(law, value, restitution, mass, stiffness, approach_speed, accel, tol):
    """Judge every registered model of ``law`` in the delivered restitution (see ``advise``)."""
    from contactalpha import models

    law = get_law(law)
    xi = float(law.scene_load_factor_unchecked(mass, stiffness, approach_speed, accel))
    exact = damping_for_unchecked(law, value, xi, restitution)
    verdicts = []
    for model in models.REGISTRY:
        if model.law != law.name or restitution not in model.restitutions:
            continue
        if model.impedance is not None and model.impedance != law.impedance:
            verdicts.append(LawVerdict(model.name, model.uses_xi, np.nan, np.nan, "failed", np.nan, False))
            continue  # solved for another impedance than the scene's
        try:
            p = float(models.alpha(value, xi, model=model.name, restitution=restitution))
        except (ValueError, RuntimeError):
            verdicts.append(LawVerdict(model.name, model.uses_xi, np.nan, np.nan, "failed", np.nan, False))
            continue
        r = law.impact(p, xi)
        got = float(r.eps if restitution == "energetic" else r.e_n)
        good = abs(got - value) <= tol and (str(r.state) == "separation") == (
            str(exact.state) == "separation"
        )
        verdicts.append(LawVerdict(model.name, model.uses_xi, p, got, str(r.state), abs(got - value), good))
    # Formulas before solvers: the first adequate model that ignores nothing it needs.
    ranked = sorted((v for v in verdicts if v.adequate), key=lambda v: (v.uses_xi, v.error))
    return LawAdvice(
        law=law.name,
        eps=value,
        restitution=restitution,
        xi=xi,
        tol=tol,
        exact_damping=float(exact.damping),
        exact_state=str(exact.state),
        models=tuple(verdicts),
        cheapest=ranked[0].name if ranked else None,
    )


def _separates(law, value, restitution, A, settings):
    """(True if the law's exact damping for ``value`` at scaled load ``A`` separates, or None; status).

    ``value`` and ``settings`` checked.
    """
    sol = damping_for_unchecked(law, value, law.load_factor_unchecked(A), restitution, settings)
    if not sol.ok:
        return None, str(sol.status)
    return str(sol.state) == "separation", STATUS[OK]


# Bisection steps on ln A for the boundary (2^-60 of the bracket's width).
BOUNDARY_BISECTIONS = 60
# Where the damping's inverse fails inside a bracket this narrow in ln A (the restitution jumps at
# the boundary, so the inverse can miss its tolerance right next to it), the bracket's middle is
# the answer: A_b to this relative error, the critical speed to (n + 1) / (2 n) of it.
BOUNDARY_LN_TOL = 1e-6
# Loads the boundary is searched between; where the inverse fails at the upper end (very large
# loads), the upper end steps down by factors of LOAD_BRACKET_STEP until it succeeds.
LOAD_BRACKET = (1e-8, 1e6)
LOAD_BRACKET_STEP = 10.0


def _boundary_load(law, eps, restitution, settings):
    """Scaled load ``A_b`` above which the law's exact damping for ``eps`` stops separating: (A_b, status).

    ``eps`` and ``settings`` checked (``laws.maps.check_target``, ``check_settings``).
    """
    lo = np.log(LOAD_BRACKET[0])
    s_lo, status = _separates(law, eps, restitution, LOAD_BRACKET[0], settings)
    if s_lo is None:
        return np.nan, status
    if not s_lo:
        return np.nan, STATUS[NO_BRACKET]
    hi = np.log(LOAD_BRACKET[1])
    while True:
        s_hi, status = _separates(law, eps, restitution, np.exp(hi), settings)
        if s_hi is not None or hi - np.log(LOAD_BRACKET_STEP) <= lo:
            break
        hi -= np.log(LOAD_BRACKET_STEP)
    if s_hi is None:
        return np.nan, status
    if s_hi:
        return np.nan, STATUS[NO_BRACKET]
    for _ in range(BOUNDARY_BISECTIONS):
        mid = 0.5 * (lo + hi)
        s, status = _separates(law, eps, restitution, np.exp(mid), settings)
        if s is None and hi - lo <= BOUNDARY_LN_TOL:
            break  # the inverse fails next to the boundary (the restitution jumps there): inside the bracket
        if s is None:
            return np.nan, status
        lo, hi = (mid, hi) if s else (lo, mid)
    return float(np.exp(0.5 * (lo + hi))), STATUS[OK]


def law_critical_speed(law, eps, mass, stiffness, accel, **settings):
    """Speeds (m/s) below which the law's exact damping for ``eps`` no longer separates, and statuses.

    Takes checked inputs (``scene.threshold.critical_speed_status`` checks them): flat ``eps``.
    """
    law = get_law(law)
    out = np.zeros(eps.shape)
    status = np.full(eps.shape, STATUS[OK], dtype=object)
    n = law.exponent
    unit = law.length_scale_unchecked(mass, stiffness, 1.0)  # delta_s ~ v^(2/(n+1)), so A ~ v^(-2n/(n+1))
    for i, value in enumerate(eps):
        if value == 1.0:
            continue
        A_b, status[i] = _boundary_load(law, float(value), "energetic", settings)
        out[i] = (accel * unit / A_b) ** ((n + 1.0) / (2.0 * n))
    return out, status


def law_predict_bounces(scene, model, law, max_contacts=1000):
    """Bounce sequence of ``scene`` under ``law`` with ``model``'s damping at each contact (case A).

    Returns a dict of arrays: approach speeds, load factors, dampings, end states, rebound speeds,
    contact and flight durations (s), and the time to rest (s; inf if it creeps to rest).
    """
    from contactalpha import models

    law = get_law(law)
    found = models.ALL_MODELS.get(model)
    if found is None or found.law != law.name:
        valid = ", ".join(m.name for m in models.REGISTRY if m.law == law.name)
        raise ValueError(f"model {model!r} is not a model of law {law.name!r}; valid: {valid}")
    restitution = found.restitutions[0]
    m, k, a = scene.mass, scene.stiffness, scene.accel
    rows: dict[str, list] = {key: [] for key in ("v", "xi", "p", "state", "v_out", "contact", "flight")}
    speed, t = float(scene.approach_speed), 0.0
    while len(rows["v"]) < max_contacts:
        xi = float(law.load_factor(law.load(m, k, speed, a)))
        p = float(models.alpha(scene.eps, xi, model=model, restitution=restitution))
        r = law.impact(p, xi)
        contact = float(r.t_end) * float(law.length_scale(m, k, speed)) / speed
        for key, val in (("v", speed), ("xi", xi), ("p", p), ("state", str(r.state)), ("contact", contact)):
            rows[key].append(val)
        t += contact
        if str(r.state) != "separation":
            rows["v_out"].append(0.0)
            break
        speed = float(r.e_n) * speed
        rows["v_out"].append(speed)
        rows["flight"].append(2.0 * speed / a)
        t += 2.0 * speed / a
    out: dict[str, np.ndarray | tuple | float] = {
        key: np.array(val) for key, val in rows.items() if key != "state"
    }
    out["states"] = tuple(rows["state"])
    out["time_to_rest"] = t
    return out
