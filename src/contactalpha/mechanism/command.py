"""The ``contactalpha tune MODEL --pair G1 G2 --e-n E ...`` subcommand: its parser and its run."""

import sys
import warnings

# ``--discrete`` -> ``tune``'s ``discrete``.
DISCRETE_CHOICES = {"auto": None, "always": True, "never": False}

EXAMPLES = (
    "contactalpha tune robot.xml --pair floor foot --e-n 0.5 --speed 1.0 -o robot_tuned.xml",
    "contactalpha tune leg.sdf --pair floor foot --e-n 0.6 --qvel -0.8 0 0 --stiffness 6.6e8 --check",
    "contactalpha tune arm.xml --pair wall tip --e-n 0.3 --qvel 1.6 --force arm -20 0 0 --engine mujoco",
)


def add_parser(make, number):
    """Add the ``tune`` subcommand: ``make(name, help)`` gives its parser, ``number`` parses floats."""
    t = make("tune", "tune a contact of an MJCF/URDF/SDF model for Newton's e_N and write it back")
    t.add_argument("model", help="the model file (MJCF .xml, URDF .urdf, SDF .sdf); never overwritten")
    t.add_argument("--pair", nargs=2, required=True, metavar=("GEOM1", "GEOM2"), help="the two geometries")
    t.add_argument("--e-n", type=number, required=True, help="target Newton's restitution, in (0, 1)")
    t.add_argument("--speed", type=number, help="closing speed of the contact point at touchdown, m/s")
    t.add_argument(
        "--qvel", type=number, nargs="+", help="joint velocities at touchdown (instead of --speed)"
    )
    t.add_argument("--qpos", type=number, nargs="+", help="configuration at touchdown (default the model's)")
    t.add_argument("--engine", help="an engine with a tuner (mujoco, drake, pybullet: the registry checks "
                   "it when the command runs); default: the first installed engine that reads the file "
                   "(drake for .sdf, and .urdf whose meshes it reads; mujoco for .xml; printed)")  # fmt: skip
    t.add_argument("--stiffness", type=number, help="contact stiffness along the normal, N/m "
                   "(MuJoCo: default the model's own; Drake and PyBullet need it)")  # fmt: skip
    t.add_argument("--impedance", type=number, help="MuJoCo's constant solimp d (default 0.9)")
    t.add_argument("--force", nargs=4, action="append", metavar=("BODY", "FX", "FY", "FZ"),
                   help="a constant force on BODY's centre of mass, N, world axes (repeat)")  # fmt: skip
    t.add_argument("-o", "--output", help="file written (default MODEL_tuned.xml/.sdf/.py beside the model)")
    t.add_argument(
        "--check", action="store_true", help="drop the tuned model in the engine and report its e_N"
    )
    t.add_argument(
        "--timestep",
        type=number,
        help="the engine's step, s: its discrete answer and --check's drop "
        "(default: MuJoCo the model's, PyBullet 1/240, Drake the continuous plant)",
    )
    t.add_argument("--discrete", choices=tuple(DISCRETE_CHOICES), default="auto",
                   help="the step map's phase-mean answer: where the law's misses by more than 1e-3 "
                   "(auto), always, or never")  # fmt: skip
    t.add_argument("--no-engine-loop", action="store_true",
                   help="write the reduced model's answer without solving on the engine's own "
                   "drops of the whole model (the default solves there)")  # fmt: skip
    t.add_argument("--package-path", action="append", metavar="NAME=DIR",
                   help="the folder of package NAME for package:// URIs (repeat; else ROS_PACKAGE_PATH, "
                   "else beside the file)")  # fmt: skip
    t.add_argument("--refine", action="store_true",
                   help="MuJoCo: refine the damping on the engine's own drop from touchdown")  # fmt: skip
    t.add_argument(
        "--ground",
        action="store_true",
        help="a URDF without a floor: add one (a box link 'ground', its top at z = 0)",
    )
    t.add_argument(
        "--base",
        choices=("fixed", "floating"),
        help="a URDF's root link: fixed to the world (default, in every engine) or floating (drake)",
    )
    t.add_argument(
        "--verify",
        type=int,
        metavar="N",
        help="drop the written file in the engine at N touchdown phases and print the measured "
        "mean and range beside the predicted",
    )
    t.add_argument("--force-write", action="store_true",
                   help="write the law's answer even where no damping reaches the target at the step "
                   "(the exit status is still the unreachable one, 3)")  # fmt: skip
    return t


def _forces(items, parser):
    forces = {}
    for body, *xyz in items or ():
        try:
            forces[body] = tuple(float(x) for x in xyz)
        except ValueError:
            parser.error(f"--force {body} {' '.join(xyz)}: FX FY FZ must be numbers")
    return forces


def run(args, parser):
    """Run the subcommand; returns the exit status (ValueError propagates to the CLI's handler)."""
    from contactalpha.adapters.mujoco_soft import IMPEDANCE
    from contactalpha.parameters.reach import EXIT_UNREACHABLE

    from .tune import default_output, tune

    output = args.output or default_output(args.model, args.engine)
    from . import uris

    packages = uris.parse_package_paths(args.package_path)
    with warnings.catch_warnings(record=True) as caught, uris.using(packages):
        warnings.simplefilter("always")
        try:
            result = tune(
                args.model, tuple(args.pair), args.e_n, speed=args.speed, qvel=args.qvel, qpos=args.qpos,
                engine=args.engine, stiffness=args.stiffness, forces=_forces(args.force, parser),
                impedance=IMPEDANCE if args.impedance is None else args.impedance, output=output,
                check=args.check, timestep=args.timestep, refine=args.refine,
                discrete=DISCRETE_CHOICES[args.discrete], engine_loop=not args.no_engine_loop,
                force_write=args.force_write, ground=args.ground, base=args.base, verify=args.verify,
            )  # fmt: skip
        except ImportError as exc:
            raise ValueError(str(exc)) from None
        finally:
            for w in caught:
                print(f"contactalpha: warning: {' '.join(str(w.message).split())}", file=sys.stderr)
    print("\n".join(result.contact.summary()))
    for name, value in result.parameters.items():
        shown = " ".join(f"{float(v):.12g}" for v in (value if isinstance(value, tuple) else (value,)))
        print(f"{result.engine + '.' + name:32s} {shown}")
    print("\n".join(f"# {line}" for line in result.notes))
    print(f"written {result.output}" if result.output is not None else "# nothing written")
    if not result.reached:
        written = (f"written anyway (--force-write) to {result.output}" if result.output is not None
                   else "nothing written (--force-write writes this answer anyway)")  # fmt: skip
        print(f"contactalpha: unreachable: {result.unreachable}; {written}", file=sys.stderr)
        return EXIT_UNREACHABLE
    return 0
