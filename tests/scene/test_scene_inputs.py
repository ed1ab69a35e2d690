"""Scene, predict_bounces and trajectory name a bad argument (issue 29, N9 and N10)."""

import re

import numpy as np
import pytest

import contactalpha as ca
from contactalpha.engine.table import XI_MAX


@pytest.mark.parametrize(
    "kwargs, message",
    [
        ({"eps": [0.8, 0.8]}, "eps = [0.8, 0.8] is not one real number"),
        ({"eps": True}, "eps = True is not one real number"),
        ({"gravity": "9.81"}, "gravity = '9.81' is not one real number"),
        ({"mass": np.array([0.5])}, "mass = array([0.5]) is not one real number"),
    ],
)
def test_scene_fields_are_one_real_number(kwargs, message):
    with pytest.raises(ValueError, match=re.escape(message)):
        ca.Scene(**kwargs)


def test_scene_keeps_plain_numbers_as_floats():
    scene = ca.Scene(mass=np.float64(0.5), stiffness=140000000)
    assert type(scene.mass) is float and type(scene.stiffness) is float and scene.stiffness == 1.4e8


@pytest.mark.parametrize("scene", [None, "ball", {"mass": 0.5}])
def test_predict_bounces_names_a_scene_that_is_not_one(scene):
    with pytest.raises(ValueError, match="is not a Scene"):
        ca.predict_bounces(scene, "exact")


def test_predict_bounces_names_an_unknown_model():
    with pytest.raises(ValueError, match="model = 'exactt' is not a registered model"):
        ca.predict_bounces(ca.Scene(), "exactt")


@pytest.mark.parametrize(
    "max_contacts, message",
    [
        (-3, "max_contacts = -3.0 is outside the valid range"),
        (float("nan"), "max_contacts = nan is outside the valid range"),
        (0, "max_contacts = 0.0 is outside the valid range"),
        (2.5, "max_contacts = 2.5 is not one whole number"),
        (True, "max_contacts = True is a bool"),
    ],
)
def test_predict_bounces_checks_max_contacts(max_contacts, message):
    with pytest.raises(ValueError, match=re.escape(message)):
        ca.predict_bounces(ca.Scene(), "exact", max_contacts=max_contacts)


def test_exact_beyond_the_tables_xi_takes_the_solvers_alpha():
    """Issue 29, also: a contact with xi > 0.99 raised with model 'exact'; the front door falls back."""
    scene = ca.Scene(approach_speed=0.5, force=5e4, eps=0.5)
    assert scene.influence(0.5) > XI_MAX
    exact = ca.predict_bounces(scene, "exact")
    solved = ca.predict_bounces(scene, "exact_solve")
    assert exact.ok and exact.states == solved.states
    np.testing.assert_array_equal(exact.alpha, solved.alpha)
    # The solver's alpha at that xi delivers the eps asked for (an independent impact).
    assert ca.restitution(exact.alpha[0], exact.xi[0]) == pytest.approx(0.5, abs=1e-9)


@pytest.mark.parametrize(
    "kwargs, message",
    [
        ({"max_step": -0.5}, "max_step = -0.5 is outside the valid range (0.0, inf)"),
        ({"max_step": 0.0}, "max_step = 0.0 is outside the valid range (0.0, inf)"),
        ({"max_step": float("nan")}, "max_step = nan is outside the valid range"),
        ({"max_rows": 0}, "max_rows = 0.0 is outside the valid range [1,"),
        ({"max_rows": 2.5}, "max_rows = 2.5 is not one whole number"),
    ],
)
def test_trajectory_checks_its_step_and_rows(kwargs, message):
    """max_step = -0.5 integrated backwards, 0 filled 100,000 rows, max_rows = 0 gave an empty 'ok'."""
    with pytest.raises(ValueError, match=re.escape(message)):
        ca.trajectory(10.0, 0.2, **kwargs)


def test_trajectory_with_a_step_cap_ends_where_the_impact_does():
    path, result = ca.trajectory(10.0, 0.2, max_step=0.1)
    assert result.ok and np.all(np.diff(path[:, 0]) > 0) and np.all(np.diff(path[:, 0]) <= 0.1 + 1e-12)
    assert path[-1, 0] == pytest.approx(result.t_end, rel=1e-12)


@pytest.mark.parametrize("flag", ["False", "True", 0, None])
def test_exact_at_zero_must_be_a_bool(flag):
    """exact_at_zero = "False" counted as True."""
    with pytest.raises(ValueError, match=re.escape(f"exact_at_zero = {flag!r} is not a bool")):
        ca.solve_alpha(0.5, 0.0, exact_at_zero=flag)


SCENE = {"mass": 0.5, "stiffness": 1.4e8, "approach_speed": 0.5, "accel": 9.81}
API = {
    "solve_alpha": (ca.solve_alpha, {"eps": 0.5, "xi": 0.2, "rtol": 1e-12, "atol": 1e-14}),
    "impact": (ca.impact, {"alpha": 1.0, "xi": 0.2, "rtol": 1e-12, "atol": 1e-14}),
    "trajectory": (ca.trajectory, {"alpha": 1.0, "xi": 0.2, "atol": 1e-14, "max_step": 0.1}),
    "contact_parameters": (ca.contact_parameters, {"eps": 0.5, **SCENE}),
    "advise": (ca.advise, {"eps": 0.5, **SCENE}),
    "critical_speed": (ca.critical_speed, {"eps": 0.5, "mass": 0.5, "stiffness": 1.4e8, "accel": 9.81}),
    "predict_bounces": (ca.predict_bounces, {"scene": ca.Scene(), "model": "exact", "atol": 1e-14}),
}
# Arguments that take arrays (broadcast), and the two a bad value of which is tested elsewhere.
ARRAYS = {
    ("solve_alpha", "eps"),
    ("solve_alpha", "xi"),
    ("impact", "alpha"),
    ("impact", "xi"),
    ("critical_speed", "eps"),
}
CASES = [
    (name, arg)
    for name, (_, kwargs) in API.items()
    for arg in kwargs
    if (name, arg) not in ARRAYS and arg not in ("scene", "model")
]


@pytest.mark.parametrize("name, arg", CASES, ids=[f"{n}-{a}" for n, a in CASES])
@pytest.mark.parametrize("bad", [[0.5, 0.5], None], ids=["list", "None"])
def test_a_bad_argument_is_named_not_a_numpy_or_python_message(name, arg, bad):
    """Issue 29, N10: lists gave 'only 0-dimensional arrays can be converted to Python scalars',
    'float() argument must be ...' or 'setting an array element with a sequence'."""
    fn, kwargs = API[name]
    if name == "contact_parameters" and bad is not None:
        # The front door takes arrays of scenes (issue 27's batched path): a list is a batch.
        batch = fn(**{**kwargs, arg: bad})
        single = fn(**{**kwargs, arg: bad[0]})
        assert batch.xi.shape == (2,) and list(batch.ok) in ([True, True], [False, False])
        if batch.ok[0]:
            assert batch.xi[0] == batch.xi[1] == single.xi
        else:  # outside the batch evaluator's domain: NaN and the reason, with the scalar's xi
            assert np.isnan(batch.xi).all() and f"xi = {single.xi!r}" in batch.reason[0]
        return
    with pytest.raises(ValueError, match=re.escape(arg)):
        fn(**{**kwargs, arg: bad})


def test_alpha_tabulated_names_a_restitution_that_is_not_a_word():
    with pytest.raises(ValueError, match=r"restitution = \['kinematic'\] is not one of"):
        ca.alpha_tabulated(0.5, 0.2, restitution=["kinematic"])
