"""Rest prediction: the bounce sequence of a ball under a constant load, with no time stepping.

A ball that leaves the ground at speed ``u`` under the constant acceleration ``a``
lands again after ``2 u / a`` at the same speed ``u`` (an exact parabola), and the
outcome of each impact depends only on ``(eps, xi_i)``, with ``xi_i`` the influence
factor of the load at that impact's approach speed (Eq. 10).  So the sequence is a
map from one approach speed to the next: ``v_{i+1} = e_N(eps, xi_i) v_i``, with the
kinematic restitution ``e_N`` and the contact duration of each impact from the impact
kernel (one scaled impact each, no flight integrated, no recorded path).  It ends at
the first impact that does not separate (``scene.ball``'s proof: the scaled energy is
then negative and can only fall); with the exact alpha that is the first approach
below ``threshold.critical_speed``.

This is the model of the paper's case A (Eq. 24: the load kept in the contact).
"""

from dataclasses import dataclass

import numpy as np

from contactalpha.engine.codes import (
    END_STATES,
    OK,
    OUT_STATE,
    OUT_STATUS,
    OUT_T_END,
    OUT_V_END,
    SEPARATION,
    STATUS,
)
from contactalpha.engine.driver import ATOL, RTOL
from contactalpha.engine.table import XI_MAX
from contactalpha.laws import DEFAULT_LAW, get_law
from contactalpha.models import ALL_MODELS, MODELS
from contactalpha.validation import check_count, check_tolerances

from . import ball
from .law_scene import law_predict_bounces

# Scaled time step cap of the prediction's contacts: none (nothing is recorded or plotted).
NO_STEP_CAP = np.inf
# A tabulated model and the solver form of the same alpha, used for a contact whose xi is beyond
# the table's XI_MAX (slow impacts under a large load), as the front door (contact_parameters) does.
SOLVER_FORM = {"exact": "exact_solve"}
# Largest ``max_contacts``: far beyond any sequence that comes to rest.
MAX_CONTACTS_LIMIT = 10**9


@dataclass(frozen=True)
class BouncePrediction:
    """The bounce sequence of a scene and a model, contact by contact (physical units).

    Attributes
    ----------
    scene, model : what was predicted.
    approach_speeds : m/s, one per contact.
    xi, alpha : influence factor and the model's alpha of each contact.
    states : end-state name of each contact (``codes.END_STATES``).
    rebound_speeds : m/s (0 for a contact that does not separate).
    contact_durations : s (inf for a contact that creeps to rest).
    flight_durations : s, the parabola after each separating contact.
    status : "ok", or why the sequence stopped early (then ``time_to_rest`` is NaN).
    """

    scene: ball.Scene
    model: str
    approach_speeds: np.ndarray
    xi: np.ndarray
    alpha: np.ndarray
    states: tuple[str, ...]
    rebound_speeds: np.ndarray
    contact_durations: np.ndarray
    flight_durations: np.ndarray
    time_to_rest: float
    status: str

    @property
    def contacts(self):
        """Number of contacts, the final non-separating one included (``BallRun.count``)."""
        return len(self.states)

    @property
    def bounces(self):
        """Number of contacts that end with the ball leaving the ground (``BallRun.rebounds``)."""
        return sum(s == END_STATES[SEPARATION] for s in self.states)

    @property
    def ok(self):
        """True when the sequence ran to rest."""
        return self.status == STATUS[OK]


def predict_bounces(
    scene: ball.Scene,
    model: str,
    *,
    rtol: float = RTOL,
    atol: float = ATOL,
    max_contacts: int = ball.MAX_COLLISIONS,
    law: str | None = None,
) -> BouncePrediction:
    """Bounce sequence of ``scene`` with ``model``'s alpha until the ball rests (case A), no time stepping.

    Parameters
    ----------
    scene : scene.ball.Scene
        Its ``t_end`` is ignored: the sequence runs until a contact does not separate.
    model : str
        Name in ``models.MODELS``; alpha is the model at each contact's ``(eps, xi_i)``.  A
        contact of the tabulated ``"exact"`` beyond the table's ``xi`` (``table.XI_MAX``) takes
        the solver's alpha (``"exact_solve"``, the same alpha to ~1e-7), as ``contact_parameters``.
    rtol, atol : float
        Tolerances of each contact's impact kernel (scaled units).
    max_contacts : int
        Guard against a runaway sequence, a whole number >= 1; reaching it sets ``status``.
    law : str or ContactLaw, optional
        The contact law (``contactalpha.laws``); default Hunt-Crossley n = 3/2.  Another law
        takes a model of that law (``models.ALL_MODELS``) and returns a dict of arrays
        (``scene.law_scene.law_predict_bounces``; the scene's stiffness in the law's units).

    Returns
    -------
    BouncePrediction
        ``time_to_rest`` counts from the first touchdown to the end of the last contact
        (``inf`` if it creeps to rest), as ``ball.simulate``'s ``end_time``.
    """
    if not isinstance(scene, ball.Scene):
        raise ValueError(f"scene = {scene!r:.80} is not a Scene; valid: a contactalpha.Scene(...)")
    if law is not None and get_law(law).name != DEFAULT_LAW:
        if not isinstance(model, str) or model not in ALL_MODELS:
            raise ValueError(
                f"model = {model!r:.80} is not a registered model; valid: {', '.join(sorted(ALL_MODELS))}"
            )
        return law_predict_bounces(scene, model, law, max_contacts)
    if not isinstance(model, str) or model not in MODELS:
        raise ValueError(
            f"model = {model!r:.80} is not a registered model; valid: {', '.join(sorted(MODELS))}"
        )
    rtol, atol = check_tolerances(rtol, atol)
    max_contacts = check_count("max_contacts", max_contacts, 1, MAX_CONTACTS_LIMIT)
    rows: dict[str, list] = {k: [] for k in ("v", "xi", "alpha", "state", "v_out", "contact", "flight")}
    speed, t, status = float(scene.approach_speed), 0.0, STATUS[OK]
    while True:
        if len(rows["v"]) >= max_contacts:
            status = f"more than {max_contacts} contacts"
            break
        name = model if scene.influence(speed) <= XI_MAX else SOLVER_FORM.get(model, model)
        alpha = ball.contact_alpha(scene, speed, name, "A")
        _, out, _, _, ts = ball.run_contact(scene, speed, alpha, "A", rtol, atol, NO_STEP_CAP)
        code, stat = int(out[OUT_STATE]), int(out[OUT_STATUS])
        rows["v"].append(speed)
        rows["xi"].append(scene.influence(speed))
        rows["alpha"].append(alpha)
        rows["state"].append(END_STATES[code])
        rows["contact"].append(out[OUT_T_END] * ts)
        t = t + out[OUT_T_END] * ts
        if stat != OK:
            status = STATUS[stat]
            break
        if code != SEPARATION:
            rows["v_out"].append(0.0)
            break
        speed = -out[OUT_V_END] * speed
        rows["v_out"].append(speed)
        flight = 2.0 * speed / scene.accel
        rows["flight"].append(flight)
        t += flight
    return BouncePrediction(
        scene=scene,
        model=model,
        approach_speeds=np.array(rows["v"]),
        xi=np.array(rows["xi"]),
        alpha=np.array(rows["alpha"]),
        states=tuple(rows["state"]),
        rebound_speeds=np.array(rows["v_out"]),
        contact_durations=np.array(rows["contact"]),
        flight_durations=np.array(rows["flight"]),
        time_to_rest=float(t) if status == STATUS[OK] else np.nan,
        status=status,
    )
