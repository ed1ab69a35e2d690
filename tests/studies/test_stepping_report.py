"""The stepping engines' table and figure from round-trip datasets (synthetic, no engine)."""

import numpy as np
import xarray as xr

from contactalpha.studies.engines.stepping import scene_for
from contactalpha.studies.engines.stepping_report import stepping_figure, stepping_table


def fake(engine, err):
    t, loads = [0.2, 0.5, 0.8], [0.05, 0.3, 0.6]
    delivered = np.array(t)[:, None] + err * np.ones((3, 3))
    ds = xr.Dataset(
        {name: (("target", "load"), delivered) for name in ("e_n_refined", "e_n_law", "e_n_usual")},
        coords={"target": t, "load": loads},
    )
    ds["seconds"] = (("target", "load"), np.full((3, 3), 0.5))
    ds.attrs.update(engine=engine, law="kelvin_voigt", timestep=1 / 240)
    return ds


def test_table_gives_each_engines_worst_error_and_says_what_was_skipped():
    skipped = xr.Dataset(attrs={"engine": "drake", "skipped": "pydrake not installed"})
    text = stepping_table([fake("pybullet", 2e-4), skipped])
    row = next(line for line in text.splitlines() if line.startswith("| pybullet"))
    assert "| 2.0e-04 | 2.0e-04 | 2.0e-04" in row
    assert "| drake | — | — | — | skipped: pydrake not installed" in text


def test_figure_has_a_panel_per_engine_run():
    fig = stepping_figure([fake("pybullet", 0.0), fake("mujoco", 0.01)])
    assert len(fig.axes) == 2


def test_scene_for_spans_the_steps_and_loads():
    sc = scene_for("mujoco", 0.3)
    omega = (sc.stiffness / sc.mass) ** 0.5
    assert abs(np.pi / omega / 0.002 - 30.0) < 1e-9
    assert abs(sc.accel / (omega * sc.approach_speed) - 0.3) < 1e-12


def test_usual_mappings_are_models_of_each_engines_law():
    from contactalpha.adapters.registry import adapter
    from contactalpha.models.registry import ALL_MODELS
    from contactalpha.studies.engines.stepping import STEPS, USUAL

    assert set(USUAL) == set(STEPS)
    for engine, model in USUAL.items():
        assert ALL_MODELS[model].law == adapter(engine).law.name
