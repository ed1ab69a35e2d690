"""Tuned parameters written back beside the user's model: never over it.

- MJCF: the model with a ``<contact><pair>`` for the two geometries (``solref``, ``solimp``, and
  the geometries' own ``condim``, ``friction``, ``margin`` and ``gap`` as MuJoCo combines them),
  replacing an earlier ``<pair>`` of the same two.  A URDF read by MuJoCo is written as the MJCF
  MuJoCo compiles from it (``mj_saveLastXML``) with the pair added; MuJoCo writes that file with
  6 significant digits, so its poses and inertias (and m_eff) differ from the URDF's by ~1e-6.
- SDF or URDF for Drake: ``<drake:proximity_properties>`` in each of the two ``<collision>``
  elements, a URDF's values in ``value`` attributes, an SDF's as text (Drake has no per-pair
  parameters; ``internal::CombinePointContactParameters`` combines the two geometries', so each
  gets ``2k`` and the dissipation ``d``).
- PyBullet: a short Python script of ``changeDynamics`` calls (each body ``2k`` and ``c/2``), with
  ``apply_to(body)`` finding the two URDF links by name.

A relative asset folder or include of the model is made absolute when the output lies in another
folder, so the written file loads from where it is.
"""

import os
import xml.etree.ElementTree as ET
from collections.abc import Sequence
from pathlib import Path

from contactalpha.io import write_text_atomic
from contactalpha.provenance import history_line

DRAKE_NS = "http://drake.mit.edu"
ET.register_namespace("drake", DRAKE_NS)


def _parse(path=None, text=None):
    """The root element, with the file's comments kept; ValueError naming the file if it is not XML."""
    parser = ET.XMLParser(target=ET.TreeBuilder(insert_comments=True))
    try:
        if text is not None:
            return ET.fromstring(text, parser=parser)
        return ET.parse(path, parser=parser).getroot()
    except ET.ParseError as err:
        raise ValueError(f"model = {str(path)!r} is not well-formed XML: {err}") from None


def _stamp(root, what):
    """A first comment in ``root``: what was tuned, when, by which version."""
    root.insert(0, ET.Comment(f" {history_line(what)} "))


def check_output(model: str | Path, output: str | Path) -> Path:
    """The output path; ValueError if it is the model itself (never overwritten), a folder, or nowhere."""
    out = Path(output)
    if out.exists() and Path(model).exists() and out.resolve() == Path(model).resolve():
        raise ValueError(f"output = {str(output)!r} is the model file itself; give another path (-o)")
    if out.is_dir():
        raise ValueError(f"output = {str(output)!r} is a folder; give the path of the file to write (-o)")
    if not out.parent.is_dir():
        raise ValueError(f"output = {str(output)!r}: its folder {str(out.parent)!r} does not exist")
    return out


def _write(out, text):
    """``io.write_text_atomic``; an OSError names the user's path (not the temporary file's)."""
    try:
        write_text_atomic(out, text)
    except OSError as err:
        raise ValueError(f"output = {str(out)!r} cannot be written: {err.strerror or err}") from None
    return out


def _absolute_assets(root, source_dir, out_dir):
    if Path(source_dir).resolve() == Path(out_dir).resolve():
        return
    compiler = root.find("compiler")
    if compiler is None:
        compiler = ET.Element("compiler")
        root.insert(0, compiler)
    for key in ("meshdir", "texturedir", "assetdir"):
        value = compiler.get(key)
        if value is not None and not os.path.isabs(value):
            compiler.set(key, str((Path(source_dir) / value).resolve()))
    if compiler.get("meshdir") is None and compiler.get("assetdir") is None:
        compiler.set("assetdir", str(Path(source_dir).resolve()))
    for inc in root.iter("include"):
        f = inc.get("file")
        if f and not os.path.isabs(f):
            inc.set("file", str((Path(source_dir) / f).resolve()))


def _fmt(values):
    return " ".join(repr(float(v)) for v in values)


def write_mjcf(
    model_path: str | Path,
    output: str | Path,
    pair: tuple[str, str],
    attributes: dict[str, tuple | str],
    *,
    compiled_xml: str | None = None,
    stamp: str = "tuned",
) -> Path:
    """Write the MJCF with a ``<pair>`` of ``pair`` carrying ``attributes`` (name -> tuple or str).

    ``compiled_xml``: the MJCF text to start from instead of the file (a URDF's compiled model).
    """
    out = check_output(model_path, output)
    root = _parse(model_path, compiled_xml)
    if root.tag != "mujoco":
        raise ValueError(f"model = {str(model_path)!r} is not MJCF (its root is <{root.tag}>)")
    _absolute_assets(root, Path(model_path).parent, out.parent)
    contact = root.find("contact")
    if contact is None:
        contact = ET.SubElement(root, "contact")
    for old in list(contact.findall("pair")):
        if {old.get("geom1"), old.get("geom2")} == set(pair):
            contact.remove(old)
    elem = ET.SubElement(contact, "pair", {"geom1": pair[0], "geom2": pair[1]})
    for name, value in attributes.items():
        elem.set(name, value if isinstance(value, str) else _fmt(value))
    _stamp(root, stamp)
    ET.indent(root)
    _write(out, ET.tostring(root, encoding="unicode") + "\n")
    return out


def _collision(root, name):
    found = [c for c in root.iter("collision") if c.get("name") in (name, name.split("::")[-1])]
    if len(found) != 1:
        raise ValueError(f"geometry {name!r}: {len(found)} <collision> elements carry that name (need one)")
    return found[0]


def write_drake(
    model_path: str | Path,
    output: str | Path,
    pair: tuple[str, str],
    per_geometry: dict[str, float | str],
    *,
    stamp: str = "tuned",
) -> Path:
    """Write the SDF/URDF with ``<drake:proximity_properties>`` (``per_geometry``: tag -> value) on both."""
    out = check_output(model_path, output)
    root = _parse(model_path)
    for name in pair:
        col = _collision(root, name)
        tag = f"{{{DRAKE_NS}}}proximity_properties"
        props = col.find(tag)
        if props is None:
            props = ET.SubElement(col, tag)
        for key, value in per_geometry.items():  # the geometry's other properties (friction) stay
            elem = props.find(f"{{{DRAKE_NS}}}{key}")
            if elem is None:
                elem = ET.SubElement(props, f"{{{DRAKE_NS}}}{key}")
            if root.tag == "robot":  # URDF: Drake reads the value attribute
                elem.set("value", repr(float(value)))
            else:  # SDF: the element's text
                elem.text = repr(float(value))
    _absolute_uris(root, Path(model_path).parent, out.parent)
    _stamp(root, stamp)
    ET.indent(root)
    _write(out, '<?xml version="1.0"?>\n' + ET.tostring(root, encoding="unicode") + "\n")
    return out


def _absolute_uris(root, source_dir, out_dir):
    if Path(source_dir).resolve() == Path(out_dir).resolve():
        return
    for elem in root.iter():
        for key in ("filename",):
            value = elem.get(key)
            if value and "://" not in value and not os.path.isabs(value):
                elem.set(key, str((Path(source_dir) / value).resolve()))
        if elem.tag == "uri" and elem.text and "://" not in elem.text and not os.path.isabs(elem.text):
            elem.text = str((Path(source_dir) / elem.text.strip()).resolve())


PYBULLET_SCRIPT = '''"""contactalpha tune: PyBullet contact parameters for {pair0} / {pair1} of {model}.

{notes}

Load the model as the values assume: ``loadURDF(path, useFixedBase=..., flags=URDF_USE_SELF_COLLISION
| URDF_USE_INERTIA_FROM_FILE)`` (without the second flag PyBullet recomputes the inertias from the
collision shapes, and the effective mass differs).  The values are for a frictionless contact
without PyBullet's link damping (linearDamping, angularDamping 0.04 by default) and with the
joints' default velocity motors switched off (setJointMotorControlArray with forces 0).
"""

import pybullet as pb

# The URDF links that carry the two geometries (None: the model is not a URDF).
LINKS = ({link0!r}, {link1!r})
CONTACT_STIFFNESS = {k!r}
CONTACT_DAMPING = {c!r}


def apply(body_a, link_a, body_b, link_b, client=0):
    """Set the tuned stiffness and damping on both sides of the contact (after loading the model)."""
    for body, link in ((body_a, link_a), (body_b, link_b)):
        pb.changeDynamics(body, link, contactStiffness=CONTACT_STIFFNESS, contactDamping=CONTACT_DAMPING,
                          physicsClientId=client)


def link_index(body, name, client=0):
    """PyBullet's index of the link called ``name`` in ``body`` (-1 for the base)."""
    if pb.getBodyInfo(body, physicsClientId=client)[0].decode() == name:
        return -1
    for j in range(pb.getNumJoints(body, physicsClientId=client)):
        if pb.getJointInfo(body, j, physicsClientId=client)[12].decode() == name:
            return j
    raise ValueError(f"no link {{name!r}} in body {{body}}")


def apply_to(body, client=0, other=None):
    """``apply`` for the URDF loaded as ``body`` (both links in it, or the second in ``other``)."""
    other = body if other is None else other
    apply(body, link_index(body, LINKS[0], client), other, link_index(other, LINKS[1], client), client)
'''


def write_pybullet(
    model_path: str | Path,
    output: str | Path,
    pair: tuple[str, str],
    params: dict,
    notes: Sequence[str],
    links: Sequence[str | None] = (None, None),
) -> Path:
    """Write a Python script applying ``params`` (per-body ``contactStiffness``, ``contactDamping``).

    ``links``: the URDF link names of the two geometries (the script's ``apply_to`` finds them).
    """
    out = check_output(model_path, output)
    text = PYBULLET_SCRIPT.format(
        pair0=pair[0], pair1=pair[1], model=model_path, notes="\n".join(notes),
        k=float(params["contactStiffness"]), c=float(params["contactDamping"]),
        link0=links[0], link1=links[1],
    )  # fmt: skip
    _write(out, text)
    return out
