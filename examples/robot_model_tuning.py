"""From a robot model to tuned contacts: a two-link leg's foot on the floor, in MuJoCo.

The model (examples/data/two_link_leg.xml) is a hip on a vertical slider, a thigh and a shank,
and a foot sphere touching the floor at its default pose.  We want the foot to bounce with
Newton's e_N = 0.5 when the leg lands at 0.8 m/s, with a contact stiffness of 1e7 N/m.

``tune`` reads the contact from the file (point, normal, effective mass, free acceleration and
MuJoCo's own contact row), solves MuJoCo's soft-contact law there, corrects it for the row's
diagA (which is not J M^-1 J^T in a mechanism), writes a tuned copy with a <pair> and drops it in
MuJoCo.  The free-body mapping, run on the same drop, misses the target by more; what is left of
the corrected one's miss is the leg folding during the contact, which refining on MuJoCo's own
drop takes up.

Run: python examples/robot_model_tuning.py   (needs ``pip install mujoco``)
"""

import re
import tempfile
from pathlib import Path

from contactalpha.mechanism import tune
from contactalpha.mechanism.mujoco_model import mujoco_drop

MODEL = Path(__file__).resolve().parent / "data" / "two_link_leg.xml"
PAIR = ("floor", "foot")
TARGET, STIFFNESS = 0.5, 1e7
QVEL = (-0.8, 0.0, 0.0)  # the hip slides down at 0.8 m/s, the joints still
TIMESTEP = 2e-6  # s: small, so that MuJoCo's step stays close to the continuous law

with tempfile.TemporaryDirectory() as tmp:
    out = Path(tmp) / "two_link_leg_tuned.xml"
    result = tune(
        MODEL, PAIR, TARGET, qvel=QVEL, stiffness=STIFFNESS, output=out, check=True, timestep=TIMESTEP
    )
    c = result.contact
    print("\n".join(c.summary()))
    print(f"solref           {result.parameters['solref'][0]:.9g} {result.parameters['solref'][1]:.9g}")
    print(f"effective d      {result.details.effective_impedance:.9f}")
    print(f"delivered e_N    {result.delivered:.6f}")
    free = result.details.free_body["solref"]
    text = re.sub(r'solref="[^"]*"', f'solref="{free[0]!r} {free[1]!r}"', out.read_text())
    miss = mujoco_drop(text, PAIR, c.qpos, c.qvel, timestep=TIMESTEP).e_n
    print(f"free-body e_N    {miss:.6f}")
    print(f"mass change      {result.mass_change:.6f}")
    # The effective mass moves by 0.65 % while the foot is down: refining the damping on MuJoCo's
    # own drop from the same touchdown state takes up what the touchdown values leave out.
    refined = tune(MODEL, PAIR, TARGET, qvel=QVEL, stiffness=STIFFNESS, output=out, check=True,
                   timestep=TIMESTEP, refine=True)  # fmt: skip
    print(f"refined solref   {refined.parameters['solref'][0]:.9g} {refined.parameters['solref'][1]:.9g}")
    print(f"refined e_N      {refined.delivered:.6f}")
