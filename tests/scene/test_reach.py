"""An unreachable target names the nearest reachable one and what would reach it (issue 32, item 10)."""

import math
import re
from dataclasses import dataclass

import pytest

import contactalpha as ca
from contactalpha import cli
from contactalpha.adapters.base import Delivered, Refinement
from contactalpha.adapters.contract import DropScene
from contactalpha.laws import get_law
from contactalpha.parameters import reach


@dataclass(frozen=True)
class ToySettings:
    timestep: float = 0.01
    tol: float = 1e-3


class ToyEngine:
    """Zero damping delivers e_N = 1 - h omega (a step's dissipation); damping z takes z off it."""

    name = "toy"
    law = get_law("kelvin_voigt")
    settings = ToySettings()

    def timestep(self, settings):
        return settings.timestep

    def delivered(self, scene, damping, settings=None):
        settings = self.settings if settings is None else settings
        omega = math.sqrt(scene.stiffness / scene.mass)
        return Delivered(max(0.0, 1.0 - settings.timestep * omega) - damping, 0.0, 10, True)


def test_remedies_find_the_largest_stiffness_and_step_that_reach_the_target():
    toy, scene, target = ToyEngine(), DropScene(0.5, 2e3, 0.5), 0.8
    found = reach.remedies(toy, scene, target)
    # Closed form: 1 - h sqrt(k/m) >= target  <=>  k <= m ((1 - target)/h)^2,  h <= (1 - target)/omega.
    k_star = 0.5 * ((1.0 - target) / 0.01) ** 2
    h_star = (1.0 - target) / math.sqrt(2e3 / 0.5)
    resolution = reach.SHRINK ** (0.5**reach.BISECTIONS)  # the scan's last bracket, as a ratio
    assert resolution * k_star <= found["stiffness"] <= k_star
    assert resolution * h_star <= found["timestep"] <= h_star
    # A stiffness whose rest penetration m a / k exceeds the radius is no remedy: for e_N = 0.95 the
    # toy needs k <= 12.5 N/m, but below m a / R = 98.1 N/m the ball would sink deeper than it is large.
    assert math.isnan(reach.remedies(toy, scene, 0.95)["stiffness"])


def test_the_message_names_the_nearest_target_and_the_remedies():
    toy, scene = ToyEngine(), DropScene(0.5, 2e3, 0.5)
    ref = Refinement(math.nan, 0.3675444679663241, 0.1, 0.2, 3, "unreachable")
    err = reach.unreachable_on_drops(toy, scene, 0.8, ref)
    assert isinstance(err, ValueError) and err.nearest == ref.e_n
    text = str(err)
    assert "nearest the target that it delivered is 0.367544" in text
    assert f"a stiffness <= {err.remedies['stiffness']:.4g} N/m at this step" in text
    assert f"a step <= {err.remedies['timestep']:.3g} s at this stiffness" in text


def test_eps_zero_without_a_load_is_unreachable_and_a_load_reaches_it(capsys):
    scene = dict(mass=0.5, stiffness=1.4e8, approach_speed=0.5)
    with pytest.raises(reach.UnreachableTarget, match="any load reaches eps = 0"):
        ca.contact_parameters(eps=0.0, accel=0.0, **scene)
    assert ca.contact_parameters(eps=0.0, accel=9.81, **scene).eps == pytest.approx(0.0, abs=1e-6)
    argv = ["params", "--eps", "0", "--mass", "0.5", "--stiffness", "1.4e8", "--speed", "0.5", "--accel", "0"]
    assert cli.main(argv) == reach.EXIT_UNREACHABLE == 3
    err = capsys.readouterr().err  # a cold numba cache adds its compile lines before the verdict
    verdicts = [line for line in err.splitlines() if line.startswith("contactalpha: unreachable:")]
    assert len(verdicts) == 1 and verdicts[0].startswith("contactalpha: unreachable: eps = 0.0 needs a load")


def test_help_documents_the_exit_status(capsys):
    with pytest.raises(SystemExit):
        cli.main(["params", "-h"])
    text = " ".join(capsys.readouterr().out.split())
    assert f"{reach.EXIT_UNREACHABLE} no damping reaches the target" in text


@pytest.mark.integration
def test_mujoco_at_a_coarse_step_says_what_reaches_the_target_and_that_does(capsys):
    pytest.importorskip("mujoco")
    argv = ["params", "--engine", "mujoco", "--refine", "--e-n", "0.95", "--mass", "0.5", "--speed", "0.5"]
    argv += ["--accel", "9.81"]
    with pytest.warns(Warning):  # the coarse contact's own warning
        assert cli.main([*argv, "--stiffness", "5e5"]) == reach.EXIT_UNREACHABLE
    err = capsys.readouterr().err
    verdicts = [line for line in err.splitlines() if line.startswith("contactalpha: unreachable:")]
    assert len(verdicts) == 1  # beside it, at most the progress lines of a slow machine
    stiffness = float(re.search(r"a stiffness <= ([0-9.e+]+) N/m", err).group(1))
    assert stiffness < 5e5
    # The stiffness it names does reach the target on MuJoCo's own drops.
    assert cli.main([*argv, "--stiffness", repr(stiffness), "--json"]) == 0
    out = capsys.readouterr().out
    assert re.search(r"delivers 0\.95\d*", out) or re.search(r"delivers 0\.949\d*", out)
