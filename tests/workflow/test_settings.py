"""Each stage's settings object has the schema's defaults: one owner, diffed here."""

import inspect
from dataclasses import asdict, fields
from pathlib import Path

import pytest
import yaml

from contactalpha.adapters import exudyn_contact, opensim_hc
from contactalpha.config import settings_from
from contactalpha.engine.table import KINEMATIC_FILE
from contactalpha.engine.table_build import (
    KinematicTableSettings,
    TableCheckSettings,
    TableSettings,
    build_kinematic_table,
    build_table,
    built_with,
    check_table,
)
from contactalpha.paper.ball.study import BallSettings
from contactalpha.paper.bench.report import BenchSettings, FailureSettings
from contactalpha.paper.closedform.compute import ClosedFormRefitSettings, ClosedFormSettings
from contactalpha.paper.fig9.compute import Fig9Settings
from contactalpha.paper.fit.report import FitSettings
from contactalpha.paper.surface.compute import SolverSettings, SurfaceSettings, compute_surface
from contactalpha.scene.ball import ContactNumerics, Scene, simulate
from contactalpha.studies.adequacy.report import AdequacySettings
from contactalpha.studies.engines.compute import EnginesSettings, ExudynSettings, OpenSimSettings
from contactalpha.studies.restitution.curves import RestitutionCurveSettings, restitution_curves

SCHEMA = Path(__file__).resolve().parents[2] / "workflow" / "schemas" / "config.schema.yaml"

# Schema section -> (settings class, keys only the workflow has, fields only the library has).
OWNERS = {
    ("surface",): (SurfaceSettings, set(), set()),
    ("surface", "solver"): (SolverSettings, set(), set()),
    ("models", "table"): (TableSettings, set(), set()),
    ("models", "check"): (TableCheckSettings, set(), set()),
    ("models", "fig9"): (Fig9Settings, set(), set()),
    ("fit",): (
        FitSettings,
        {"package_coefficients"},
        {"max_nfev", "reading_max_nfev", "coarse_stride", "jacobian"},
    ),
    ("ball", "numerics"): (ContactNumerics, set(), set()),
    ("restitution", "curves"): (RestitutionCurveSettings, set(), set()),
    ("restitution", "table"): (KinematicTableSettings, set(), set()),
    ("restitution", "check"): (TableCheckSettings, set(), set()),
    ("bench",): (BenchSettings, set(), set()),
    ("engines",): (EnginesSettings, set(), set()),
    ("adequacy",): (AdequacySettings, set(), set()),
    ("ball",): (BallSettings, set(), set()),
    ("closedform",): (ClosedFormSettings, {"package_constants"}, set()),
    ("closedform", "refit"): (ClosedFormRefitSettings, set(), set()),
}
# Sections (or keys) no settings object owns, and why: every other key of the schema must be owned.
NOT_OWNED = {
    ("models", "package_table"): "a package path the `ship` rule writes, not a setting of a computation",
    ("restitution", "package_table"): "a package path the `ship_kinematic_table` rule writes",
    ("closedform", "package_constants"): "a package path the `closedform_ship` rule writes",
}


def _section(path):
    node = yaml.safe_load(SCHEMA.read_text())
    for key in path:
        node = node["properties"][key]
    return node


def _default(node):
    """The value an absent key takes: its default, with the defaults of an object's members filled in."""
    value = node.get("default")
    if node.get("type") == "object" and value == {}:
        return {k: _default(v) for k, v in node["properties"].items()}
    return value


def _plain(value):
    if isinstance(value, tuple | list):
        return [_plain(v) for v in value]
    if isinstance(value, dict):
        return {k: _plain(v) for k, v in value.items()}
    return value


@pytest.mark.parametrize("path", list(OWNERS), ids=".".join)
def test_settings_defaults_are_the_schema_defaults(path):
    cls, workflow_only, library_only = OWNERS[path]
    schema = {k: v for k, v in _default(_section(path)).items() if k not in workflow_only}
    ours = {k: v for k, v in _plain(asdict(cls())).items() if k not in library_only}
    assert ours == schema


def _owned(path):
    """Whether the schema key ``path`` is owned: by a settings object, the workflow, or listed as not."""
    return any(path[: len(key)] == key for key in (*OWNERS, *NOT_OWNED))


def test_every_schema_key_has_an_owner():
    sections = _section(())["properties"]
    keys = [(name, key) for name, node in sections.items() for key in node["properties"]]
    assert [k for k in keys if not _owned(k)] == []
    stale = [
        k
        for k in NOT_OWNED
        if k[0] not in sections or (len(k) > 1 and k[1] not in sections[k[0]]["properties"])
    ]
    assert stale == []


def test_settings_from_builds_nested_settings_and_refuses_unknown_keys():
    s = settings_from(
        BenchSettings, {"rtols": [1e-4, 1e-8], "failure": {"eps": [0.5]}, "code": 1}, ignore=["code"]
    )
    assert s.rtols == (1e-4, 1e-8)
    assert s.failure == FailureSettings(eps=(0.5,))
    assert s.scaling == BenchSettings().scaling
    with pytest.raises(ValueError, match=r"unknown setting\(s\) \['rtol'\]; valid: rtols"):
        settings_from(BenchSettings, {"rtol": 1e-4})
    with pytest.raises(ValueError, match=r"FailureSettings: unknown setting\(s\) \['step'\]"):
        settings_from(BenchSettings, {"failure": {"step": 1e-3}})


def test_scene_defaults_are_the_schema_defaults():
    scene = _default(_section(("ball", "scene")))
    cases = _default(_section(("ball", "cases")))
    s = Scene()
    assert {k: getattr(s, k) for k in scene} == scene
    assert {k: getattr(s, k) for k in ("eps", "force", "t_end")} == {
        k: cases[k] for k in ("eps", "force", "t_end")
    }


def _kwdefaults(fn):
    return {n: p.default for n, p in inspect.signature(fn).parameters.items() if p.default is not p.empty}


def test_library_defaults_are_the_settings_defaults():
    # build_table(refine_n=2) once disagreed with the shipped table's 3.
    d = _kwdefaults(build_table)
    assert {f.name: d[f.name] for f in fields(TableSettings)} == asdict(TableSettings())
    assert _kwdefaults(check_table)["n"] == TableCheckSettings().points
    d = _kwdefaults(compute_surface)
    assert {f.name: d[f.name] for f in fields(SolverSettings)} == asdict(SolverSettings())
    d = _kwdefaults(simulate)
    assert {f.name: d[f.name] for f in fields(ContactNumerics)} == asdict(ContactNumerics())
    d = _kwdefaults(build_kinematic_table)
    assert {f.name: d[f.name] for f in fields(KinematicTableSettings)} == asdict(KinematicTableSettings())
    for fn in (opensim_hc.drop_impact, opensim_hc.bounce):
        d = _kwdefaults(fn)
        assert {f.name: d[f.name] for f in fields(OpenSimSettings)} == asdict(OpenSimSettings())
    d = _kwdefaults(exudyn_contact.drop_impact)
    assert {f.name: d[f.name] for f in fields(ExudynSettings)} == asdict(ExudynSettings())
    d = _kwdefaults(restitution_curves)
    assert {f.name: d[f.name] for f in fields(RestitutionCurveSettings)} == asdict(RestitutionCurveSettings())


def test_shipped_kinematic_table_has_the_default_settings():
    # The default run checks the shipped table instead of building one only while this holds.
    assert built_with(KINEMATIC_FILE, asdict(KinematicTableSettings()))
    assert not built_with(KINEMATIC_FILE, dict(asdict(KinematicTableSettings()), n_q=50))
    assert not built_with(KINEMATIC_FILE.with_name("missing.npz"), {})


def test_unknown_settings_are_refused():
    with pytest.raises(TypeError):
        TableSettings(refine=3)


def test_fig9_eps_range_holds_both_ends_on_round_values():
    eps = Fig9Settings(eps={"start": 0.1, "stop": 0.9, "step": 0.2}).eps_values()
    assert eps.tolist() == [0.1, 0.3, 0.5, 0.7, 0.9]
    assert Fig9Settings().eps_values().tolist() == [round(0.01 * k, 2) for k in range(1, 100)]


def test_default_surface_grid_is_the_papers_with_the_log_columns():
    eps, xi = SurfaceSettings().grid()
    assert (eps.size, xi.size) == (99, 124)
    assert (eps[0], eps[-1], xi[0], xi[1], xi[-1]) == (0.01, 0.99, 0.0, 1e-5, 0.99)
