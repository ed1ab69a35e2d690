"""Writing the tuned parameters beside the model: each engine's writer (``write``'s files).

MuJoCo's is the MJCF with the pair's ``<pair>`` (a URDF compiled to MJCF first), Drake's the SDF
or URDF with the pair's proximity properties, PyBullet's a script that loads the URDF and sets the
pair's links.  Each writer takes ``(contact, output, parameters, notes)`` (its ``Tuner``) and goes
by the format the contact was read from (``MechanismContact.file_format``).
"""

import tempfile
from pathlib import Path

from . import write
from .mujoco_model import load_model
from .pybullet_model import collision_links


def write_mujoco(contact, output, params, notes=()):
    """The MJCF with the pair's ``<pair>`` set to ``params`` (a URDF compiled to MJCF first)."""
    attrs = {name: value for name, value in params.items()}
    attrs["condim"] = str(int(params["condim"][0]))
    compiled = None
    if contact.file_format == "urdf":
        compiled = _compiled_mjcf(contact.model, output)
    return write.write_mjcf(contact.model, output, contact.pair, attrs, compiled_xml=compiled,
                            stamp=_stamp(contact))  # fmt: skip


def _compiled_mjcf(model, output):
    import mujoco

    m = load_model(model)
    tmp = Path(output).with_suffix(".compiled.tmp.xml")
    try:
        mujoco.mj_saveLastXML(str(tmp), m)
        return tmp.read_text()
    finally:
        tmp.unlink(missing_ok=True)


def write_drake(contact, output, params, notes=()):
    """The SDF or URDF with the pair's stiffness and dissipation."""
    keep = {k: params[k] for k in ("point_contact_stiffness", "hunt_crossley_dissipation")}
    return write.write_drake(contact.model, output, contact.pair, keep, stamp=_stamp(contact))


def _stamp(contact):
    return f"tune of {Path(contact.model).name}, pair {contact.pair[0]} / {contact.pair[1]}"


def write_pybullet(contact, output, params, notes):
    """The script that loads the URDF and sets the pair's links (``write.write_pybullet``)."""
    urdf = contact.file_format == "urdf"
    links = collision_links(contact.model, contact.pair) if urdf else (None, None)
    return write.write_pybullet(contact.model, output, contact.pair, params, notes, links)


def in_memory_mjcf(contact, params):
    """The MJCF text ``write_mujoco`` writes for ``params`` (the engine loop and the check drop it)."""
    with tempfile.TemporaryDirectory() as tmp:
        out = Path(tmp) / "tuned.xml"
        write_mujoco(contact, out, params)
        return out.read_text()
