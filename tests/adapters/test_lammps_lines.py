"""LAMMPS's lines, pair rules and damping styles, against closed forms read from LAMMPS's source.

No LAMMPS needed: the numbers are LAMMPS's formulas written out here (``gran_sub_mod.cpp``,
``gran_sub_mod_damping.cpp``), never the adapter's code path.
"""

import math

import numpy as np
import pytest
from scipy.integrate import quad

from contactalpha.adapters import lammps_granular as lg
from contactalpha.adapters.contract import DropScene
from contactalpha.dem.species import Species, Wall, species_table

# The bead: d = 5 mm, E = 1e7 Pa, nu = 0.3, rho = 2500.
R, E, NU, RHO = 2.5e-3, 1e7, 0.3, 2500.0
MASS = 4.0 / 3.0 * math.pi * R**3 * RHO
K = 4.0 / 3.0 * (E / (2.0 * (1.0 - NU * NU))) * math.sqrt(R)  # mix_stiffnessE_wall, 4/3 E* sqrt(R)


def test_coeff_restitution_damp_is_lammps_formula():
    # GranSubModDampingCoeffRestitution::init, with its constants as written there.
    root_three_by_two, two_root_five_by_six = 1.22474487139158894067, 1.82574185835055380345
    for e in (0.05, 0.3, 0.5, 0.9, 0.999):
        ln = math.log(e)
        want = -root_three_by_two * two_root_five_by_six * ln / math.sqrt(math.pi**2 + ln * ln)
        style = lg.damping_style("coeff_restitution")
        assert float(style.damp_of(e)) == pytest.approx(want, rel=1e-14)
        assert float(style.coefficient_of(want)) == pytest.approx(e, rel=1e-12)


def test_coefficient_out_of_range_is_nan():
    assert math.isnan(float(lg.damping_style("coeff_restitution").coefficient_of(math.sqrt(5.0))))


def test_pair_rules_are_lammps_mixing():
    e1, n1, e2, n2 = 6.3e10, 0.23, 2e11, 0.3
    assert float(lg.effective_modulus(e1, n1, e2, n2)) == pytest.approx(
        1.0 / ((1 - n1**2) / e1 + (1 - n2**2) / e2), rel=1e-15
    )
    # A wall and an explicit line read two bodies of one material: E / (2 (1 - nu^2)).
    assert float(lg.effective_modulus(E, NU)) == pytest.approx(E / (2.0 * (1.0 - NU**2)), rel=1e-15)
    e_star = float(lg.effective_modulus(e1, n1, e2, n2))
    line = float(lg.line_modulus(e_star, 0.26))
    assert line / (2.0 * (1.0 - 0.26**2)) == pytest.approx(e_star, rel=1e-15)
    assert float(lg.effective_radius(1e-3, 3e-3)) == pytest.approx(0.75e-3, rel=1e-15)
    assert float(lg.effective_radius(1e-3)) == 1e-3  # a flat wall
    assert float(lg.hertz_stiffness(E / 1.82, R)) == pytest.approx(K, rel=1e-14)


def test_contact_time_constant_is_hertz_integral():
    integral = quad(lambda x: 1.0 / math.sqrt(1.0 - x**2.5), 0.0, 1.0, limit=200)[0]
    assert lg.HERTZ_CONTACT_TIME == pytest.approx(2.0 * integral, rel=1e-9)


def test_parameters_give_the_material_back():
    scene = DropScene(MASS, K, 0.2, 9.81, 0.0, R)
    p = lg.ADAPTER.parameters(0.5676184048399849, scene)
    assert p["youngs_modulus"] == pytest.approx(E, rel=1e-13)
    assert p["density"] == pytest.approx(RHO, rel=1e-13)
    assert p["diameter"] == pytest.approx(2 * R, rel=1e-15)
    # beta = damp for the Tsuji styles; coeff_restitution's e of that damp
    ln = math.log(p["coefficient"])
    assert math.sqrt(5.0) * -ln / math.sqrt(math.pi**2 + ln * ln) == pytest.approx(
        0.5676184048399849, rel=1e-12
    )


def test_wall_line_is_lammps_syntax():
    scene = DropScene(MASS, K, 0.2, 9.81, 0.0, R)
    words = lg.ADAPTER.lines(0.4, scene).split()
    assert words[:5] == ["fix", "wall", "all", "wall/gran", "granular"]
    assert words[5] == "hertz/material"
    assert float(words[6]) == pytest.approx(E, rel=1e-13)
    assert float(words[8]) == NU
    assert words[9:13] == ["tangential", "linear_nohistory", "0", "0"]
    assert words[13:15] == ["damping", "coeff_restitution"]
    assert words[15:] == ["limit_damping", "zplane", "0.0", "NULL"]
    unfloored = lg.UNFLOORED.lines(0.4, scene).split()
    assert "limit_damping" not in unfloored and unfloored[-3:] == ["zplane", "0.0", "NULL"]
    assert lg.pair_line(1, 2, 1e7, 0.5, 0.3, "tsuji", False).split()[:4] == [
        "pair_coeff",
        "1",
        "2",
        "hertz/material",
    ]


def test_a_style_outside_the_adapters_law_is_refused():
    from dataclasses import replace

    scene = DropScene(MASS, K, 0.2, 9.81, 0.0, R)
    with pytest.raises(ValueError, match="viscoelastic"):
        lg.ADAPTER.parameters(0.3, scene, replace(lg.ADAPTER.settings, damping="viscoelastic"))
    with pytest.raises(ValueError, match="valid choices"):
        lg.damping_style("hooke")


SOFT = Species("soft", radius=2.5e-3, density=2500.0, youngs_modulus=1e7, poisson=0.3)
HARD = Species("hard", radius=1.5e-3, density=7800.0, youngs_modulus=5e7, poisson=0.25)


def test_species_table_pair_rules():
    t = species_table([SOFT, HARD], [[0.5, 0.7], [0.7, 0.9]], 0.05, accel=9.81,
                      walls=[Wall("floor", 2e7, 0.35)], wall_restitution=[[0.6], [0.8]])  # fmt: skip
    p, w = t.pairs, t.wall_pairs
    m1, m2 = SOFT.mass, HARD.mass
    assert p.mass[0, 1] == pytest.approx(m1 * m2 / (m1 + m2), rel=1e-15)
    assert p.r_star[0, 1] == pytest.approx(2.5e-3 * 1.5e-3 / 4e-3, rel=1e-15)
    e_star = 1.0 / ((1 - 0.09) / 1e7 + (1 - 0.0625) / 5e7)
    assert p.stiffness[0, 1] == pytest.approx(4 / 3 * e_star * math.sqrt(p.r_star[0, 1]), rel=1e-14)
    assert p.modulus[0, 0] == pytest.approx(1e7, rel=1e-14) and p.modulus[1, 1] == pytest.approx(
        5e7, rel=1e-14
    )
    assert np.array_equal(p.coefficient, p.coefficient.T)
    e_wall = 1.0 / ((1 - 0.09) / 1e7 + (1 - 0.35**2) / 2e7)
    assert w.mass[0, 0] == m1 and w.r_star[0, 0] == SOFT.radius
    assert w.modulus[0, 0] / (2 * (1 - 0.09)) == pytest.approx(e_wall, rel=1e-14)
    text = t.lammps_input()
    assert text.count("pair_coeff") == 3 and text.count("wall/gran granular") == 2
    assert "group soft type 1" in text and "fix floor_hard hard wall/gran" in text


def test_species_table_refuses_bad_input():
    with pytest.raises(ValueError, match="symmetric"):
        species_table([SOFT, HARD], [[0.5, 0.7], [0.6, 0.9]], 0.05)
    with pytest.raises(ValueError, match="limit_damping"):
        species_table([SOFT], 0.5, 0.05, damping="hooke")
    with pytest.raises(ValueError, match="wall_restitution"):
        species_table([SOFT], 0.5, 0.05, walls=[Wall("floor", 2e7, 0.35)])
    with pytest.raises(ValueError, match="target"):
        species_table([SOFT], 1.5, 0.05)
