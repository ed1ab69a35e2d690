"""The public API is typed: every exported function's parameters and return, every dataclass field."""

import dataclasses
import inspect
from pathlib import Path

import contactalpha

PKG = Path(contactalpha.__file__).parent


def test_every_public_function_is_annotated():
    missing = []
    for name in contactalpha.__all__:
        obj = getattr(contactalpha, name)
        if not callable(obj):  # a registry (LAWS): data, typed where it is defined
            continue
        if dataclasses.is_dataclass(obj):
            missing += [
                f"{name}.{f.name}"
                for f in dataclasses.fields(obj)
                if f.type in (None, inspect.Parameter.empty)
            ]
            continue
        fn = inspect.unwrap(obj)
        sig = inspect.signature(fn)
        missing += [
            f"{name}({p})" for p, v in sig.parameters.items() if v.annotation is inspect.Parameter.empty
        ]
        if sig.return_annotation is inspect.Signature.empty:
            missing.append(f"{name} -> ?")
    assert missing == []


def test_the_package_says_it_is_typed():
    assert (PKG / "py.typed").is_file()
