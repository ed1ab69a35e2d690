"""The ``contactalpha calibrate FILE --mass ... --radius ...`` subcommand: its parser and its run."""

import importlib.util
import sys


def add_parser(make, number):
    """Add the ``calibrate`` subcommand: ``make(name, help)`` gives its parser, ``number`` parses floats."""
    c = make("calibrate", "fit contact laws to a drop test (times, heights, trajectory)")
    c.add_argument(
        "file",
        help="CSV: column t (impact times), dt, h (heights), or t and z (trajectory); a unit in the "
        "header is honoured: t (ms), h (cm), z [mm]",
    )
    c.add_argument("--mass", type=number, required=True, help="ball mass, kg")
    c.add_argument("--radius", type=number, help="ball radius, m (OpenSim's stiffness; with --moduli)")
    c.add_argument("--gravity", type=number, default=9.81, help="m/s^2 (default 9.81)")
    c.add_argument("--force", type=number, default=0.0, help="constant extra push down, N (default 0)")
    c.add_argument("--stiffness", type=number, help="stiffness guess, N/m^1.5")
    c.add_argument("--moduli", type=number, nargs=2, metavar=("E_BALL", "E_GROUND"), help="Young moduli, Pa")
    c.add_argument("--poisson", type=number, nargs=2, default=(0.3, 0.3), metavar=("NU_BALL", "NU_GROUND"))
    c.add_argument(
        "--hypothesis",
        "--law",  # its old name: "law" now names a contact law only
        dest="hypothesis",
        action="append",
        help="a restitution hypothesis to fit, e.g. hc_eps, or all (repeat; --law is its old name)",
    )
    c.add_argument(
        "--impedance",
        type=number,
        help="MuJoCo's constant impedance d in [0, 1) of the recording (mujoco_soft_damping; default 0.9)",
    )
    c.add_argument(
        "--interval-tolerance",
        type=number,
        default=None,
        help="s an interval may exceed the one before (default: from the recording's timing scatter, "
        "at least 1e-3)",
    )
    c.add_argument("--json", metavar="PATH", help="write the JSON report there")
    c.add_argument("--figures", metavar="PREFIX", help="write PREFIX_restitution.png, PREFIX_residuals.png")
    c.add_argument("--quiet", action="store_true", help="no progress lines on stderr")
    return c


def run(args):
    """Run the subcommand; returns the exit status (ValueError propagates to the CLI's handler)."""
    from .api import calibrate, format_calibration

    if args.figures and importlib.util.find_spec("matplotlib") is None:
        raise ValueError('--figures needs Matplotlib: pip install "contactalpha[workflow]" (or matplotlib)')
    try:
        cal = calibrate(
            args.file,
            mass=args.mass,
            radius=args.radius,
            hypotheses=args.hypothesis,
            gravity=args.gravity,
            force=args.force,
            stiffness=args.stiffness,
            moduli=args.moduli,
            poisson=tuple(args.poisson),
            interval_tolerance=args.interval_tolerance,
            impedance=args.impedance,
            progress=None if args.quiet else _progress,
        )
    except OSError as exc:
        raise ValueError(f"{args.file}: {exc.strerror or exc}") from None
    print(format_calibration(cal))
    if args.json:
        cal.to_json(args.json)
    if args.figures:
        for path in cal.figures(args.figures):
            print(path)
    return 0


def _progress(line):
    print(f"contactalpha calibrate: {line}", file=sys.stderr, flush=True)
