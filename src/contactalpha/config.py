"""Checks on the workflow configuration that its JSON schema cannot express.

The Snakefile calls ``check_config`` right after the schema validation, so a
bad config fails at ``snakemake -n``, before any job runs, with a message
naming the key: NaN or infinite numbers (JSON-schema bounds let NaN through),
whole numbers written as floats where the schema wants an integer (``2.0``),
unsorted grids, ranges that do not fit their step, a section or Eq. 26 ``xi``
off the surface grid, and model names that are not registered.
"""

import math
import typing
from collections.abc import Mapping
from dataclasses import fields, is_dataclass
from pathlib import Path

import numpy as np
import yaml

from contactalpha.models import MODELS
from contactalpha.paper.surface.compute import check_surface_config, grid_from_config

# libyaml's loader when PyYAML has it: the same data as yaml.safe_load, ~10x faster (the config
# schema, read at every Snakefile parse: 0.03 s against 0.3 s); errors are worded by safe_load.
FAST_LOADER = getattr(yaml, "CSafeLoader", yaml.SafeLoader)

# Section name -> check of that section alone; stages add theirs here.
SECTION_CHECKS = {"surface": check_surface_config}


def settings_from(cls, section, ignore=()):
    """The settings object ``cls`` (a dataclass) of one config section: what a workflow script calls.

    A key absent from ``section`` takes the class's default (which is the schema's); a sub-section
    whose field is itself a settings dataclass is built the same way; lists become tuples.

    Parameters
    ----------
    cls : type
        A dataclass whose fields are the section's keys.
    section : Mapping
        The config section, or Snakemake's ``params`` (anything with ``items()``).
    ignore : sequence of str
        Keys of ``section`` that are not settings (e.g. a rule's ``code_version``).

    Raises
    ------
    ValueError
        Naming the keys that ``cls`` does not have, and the valid ones.
    """
    section = dict(section.items())
    names = [f.name for f in fields(cls)]
    unknown = sorted(set(section) - set(names) - set(ignore))
    if unknown:
        raise ValueError(f"{cls.__name__}: unknown setting(s) {unknown}; valid: {', '.join(names)}")
    hints = typing.get_type_hints(cls)
    kwargs = {}
    for name in names:
        if name not in section:
            continue
        value = section[name]
        if is_dataclass(hints[name]) and isinstance(value, Mapping):
            value = settings_from(hints[name], value)
        elif isinstance(value, list):
            value = tuple(value)
        kwargs[name] = value
    return cls(**kwargs)


def read_yaml(path):
    """The YAML file ``path`` as Python data; a malformed file raises naming its line and column.

    Raises
    ------
    ValueError
        ``<path>:<line>:<column>: malformed YAML: <problem>`` (line and column from 1).
    """
    text = Path(path).read_text(encoding="utf-8")
    try:
        return yaml.load(text, Loader=FAST_LOADER)
    except yaml.YAMLError:
        pass  # parse again below for PyYAML's own wording of the problem
    try:
        return yaml.safe_load(text)
    except yaml.MarkedYAMLError as err:
        mark = err.problem_mark or err.context_mark
        where = f"{path}:{mark.line + 1}:{mark.column + 1}" if mark else str(path)
        raise ValueError(f"{where}: malformed YAML: {err.problem or err.context}") from None
    except yaml.YAMLError as err:
        raise ValueError(f"{path}: malformed YAML: {err}") from None


def _walk(value, key):
    """(key, value) of every leaf of nested dicts and lists, keys dotted (``a.b[2]``)."""
    if isinstance(value, dict):
        for name, item in value.items():
            yield from _walk(item, f"{key}.{name}" if key else str(name))
    elif isinstance(value, list | tuple):
        for i, item in enumerate(value):
            yield from _walk(item, f"{key}[{i}]")
    else:
        yield key, value


def check_finite(config):
    """Raise ``ValueError`` naming the first key that holds NaN or an infinite number."""
    for key, value in _walk(config, ""):
        if isinstance(value, float) and not math.isfinite(value):
            raise ValueError(f"{key} = {value!r} is not a finite number; valid: a finite number")


def _resolve(node, schema):
    ref = node.get("$ref", "")
    if ref.startswith("#/"):
        target = schema
        for part in ref[2:].split("/"):
            target = target[part]
        node = {**target, **{k: v for k, v in node.items() if k != "$ref"}}
    return node


def _types(node):
    kind = node.get("type", [])
    return {kind} if isinstance(kind, str) else set(kind)


def check_integers(config, schema):
    """Raise ``ValueError`` naming the first key whose schema type is integer but that holds a float.

    JSON schema counts ``2.0`` as an integer; Python's ``range`` and array sizes do not.
    ``schema`` is the parsed JSON schema (local ``$ref`` resolved) of ``config``.
    """
    _check_integers(config, schema, schema, "")


def _check_integers(value, node, root, key):
    node = _resolve(node, root)
    types = _types(node)
    if "integer" in types and "number" not in types and isinstance(value, float):
        raise ValueError(f"{key} = {value!r} is not a whole number; valid: an integer such as {int(value)}")
    if isinstance(value, dict):
        for name, item in value.items():
            if name in node.get("properties", {}):
                _check_integers(item, node["properties"][name], root, f"{key}.{name}" if key else name)
    elif isinstance(value, list) and isinstance(node.get("items"), dict):
        for i, item in enumerate(value):
            _check_integers(item, node["items"], root, f"{key}[{i}]")


def _valid_models():
    return ", ".join(sorted(MODELS))


def _check_every_model(where, names):
    """Raise naming the first entry of ``names`` (a name or a list) that is not a registered model."""
    for i, model in enumerate([names] if isinstance(names, str) else names or []):
        if model not in MODELS:
            at = where + (f"[{i}]" if not isinstance(names, str) else "")
            raise ValueError(f"{at} = {model!r} is not a registered model; valid: {_valid_models()}")


def _check_preference(where, names):
    """Raise unless the preference list ``names`` (a name or a list) holds a registered model."""
    names = [names] if isinstance(names, str) else list(names or [])
    if names and not any(model in MODELS for model in names):
        raise ValueError(
            f"{where} = {names!r}: none is a registered model; valid: at least one of {_valid_models()}"
        )


# Keys whose every entry must be a registered model, and preference lists whose first registered
# entry is used (at least one must be registered).  The ball's ``cases.variants`` and
# ``first_collision.formulas`` skip unregistered names by design and say so in their results.
MODEL_KEYS = (
    ("models.fig9.models", _check_every_model),
    ("models.fig9.reference", _check_every_model),
    ("models.fig9.new_model", _check_every_model),
    ("ball.first_collision.classical", _check_every_model),
    ("closedform.models", _check_every_model),
    ("engines.case_a_model", _check_every_model),
    ("ball.new_model", _check_preference),
    ("ball.first_collision.reference", _check_preference),
)


def _lookup(config, dotted):
    node = config
    for part in dotted.split("."):
        if not isinstance(node, Mapping) or part not in node:
            return None
        node = node[part]
    return node


def _check_models(config):
    for where, check in MODEL_KEYS:
        names = _lookup(config, where)
        if names is not None:
            check(where, names)
    fig9 = config.get("models", {}).get("fig9", {})
    if "new_model" in fig9 and "models" in fig9 and fig9["new_model"] not in fig9["models"]:
        raise ValueError(
            f"models.fig9.new_model = {fig9['new_model']!r} is not in models.fig9.models; "
            f"valid: one of {', '.join(fig9['models'])}"
        )


def _check_fit(config):
    eq26 = config.get("fit", {}).get("eq26")
    if eq26 is None or "surface" not in config:
        return
    _, xi = grid_from_config(config["surface"])
    # The fit selects the section by equality (paper.fit.fit_eq26): the value must be a grid value.
    if not np.any(xi == float(eq26["xi"])):
        raise ValueError(
            f"fit.eq26.xi = {eq26['xi']!r} is not on the surface xi grid; "
            "valid: one of the xi values, e.g. add it to surface.xi.values"
        )


def check_config(config, schema=None):
    """Raise ``ValueError`` naming the first bad key of the workflow ``config`` (a dict).

    Parameters
    ----------
    config : dict
        The configuration, after the schema validation (defaults filled in).
    schema : dict or path-like, optional
        Its JSON schema, for the integer check (``check_integers``).
    """
    check_finite(config)
    if schema is not None:
        check_integers(config, schema if isinstance(schema, dict) else read_yaml(schema))
    for name, check in SECTION_CHECKS.items():
        if name in config:
            check(config[name], key=name)
    _check_fit(config)
    _check_models(config)


def load_config(path, schema):
    """The workflow config file ``path`` as ``snakemake -n`` sees it, or the first error on one line.

    Read (a malformed file names its line and column), validated against the JSON
    ``schema`` file with its defaults filled in, then ``check_config``.  For a
    ``--configfile``, which Snakemake parses before the workflow and reports without a
    position; ``contactalpha check-config`` calls this.

    Raises
    ------
    ValueError
        Naming the file, and the key or the line at fault.
    """
    import jsonschema
    from snakemake.utils import validate

    for name in (path, schema):
        if not Path(name).is_file():
            raise ValueError(f"{name} is not a file; valid: a YAML file")
    config = read_yaml(path)
    if config is None:
        raise ValueError(f"{path} is empty (no sections); Snakemake refuses an empty config file")
    if not isinstance(config, dict):
        raise ValueError(f"{path} holds a {type(config).__name__}; valid: a mapping of sections")
    rules = read_yaml(schema)
    error = jsonschema.exceptions.best_match(jsonschema.Draft202012Validator(rules).iter_errors(config))
    if error is not None:
        key = ".".join(str(k) for k in error.absolute_path) or "(top level)"
        raise ValueError(f"{path}: {key}: {error.message}")
    validate(config, str(schema))  # fills in the defaults, as the Snakefile does
    try:
        check_config(config, rules)
    except ValueError as err:
        raise ValueError(f"{path}: {err}") from None
    return config
