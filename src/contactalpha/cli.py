"""Command line: ``contactalpha alpha EPS XI``, ``impact ALPHA XI`` and ``scene EPS ...`` (the advisor)."""

import argparse
import re
import sys

from contactalpha.engine.driver import ATOL, RTOL, impact
from contactalpha.engine.solver import EPS_TOL, solve_alpha


def _number(text):
    try:
        return float(text)
    except ValueError:
        raise argparse.ArgumentTypeError(f"{text!r} is not a number") from None


# Every float literal that starts with a minus: argparse's own pattern (-1, -.5) misses -1e-3,
# -inf and -nan and reads them as unknown options.
NEGATIVE_NUMBER = re.compile(r"^-(\d+\.?\d*|\.\d+)([eE][+-]?\d+)?$|^-(inf|infinity|nan)$", re.IGNORECASE)


class Parser(argparse.ArgumentParser):
    """An ``ArgumentParser`` that reads negative numbers in any float form as values.

    Argument errors are reported on one line (``contactalpha: error: ...``), exit status 2.
    """

    def __init__(self, *args, **kwargs):
        super().__init__(*args, **kwargs)
        self._negative_number_matcher = NEGATIVE_NUMBER

    def error(self, message):
        """Print ``message`` on one line to stderr and exit with status 2 (argparse prints usage too)."""
        misplaced = [opt for opt in GLOBAL_OPTIONS if "unrecognized arguments" in message and opt in message]
        if misplaced:
            where = "global, give before the command (contactalpha --rtol 1e-10 alpha ...)"
            message += f"; {' and '.join(misplaced)}: {where}"
        self.exit(2, f"{self.prog}: error: {message} (see {self.prog} -h)\n")


# Options of the command itself, not of a subcommand: they go before it.
GLOBAL_OPTIONS = ("--rtol", "--atol")


# The workflow's config schema, relative to a checkout (check-config --schema overrides it).
SCHEMA = "workflow/schemas/config.schema.yaml"


def build_parser():
    """Return the argument parser of the ``contactalpha`` command."""
    p = Parser(
        prog="contactalpha",
        description="Hunt-Crossley damping factor alpha under a constant external load.",
    )
    p.add_argument(
        "--rtol", type=_number, default=RTOL, help=f"integrator rtol, before the command (default {RTOL})"
    )
    p.add_argument(
        "--atol", type=_number, default=ATOL, help=f"integrator atol, before the command (default {ATOL})"
    )
    sub = p.add_subparsers(dest="command", required=True)
    a = sub.add_parser("alpha", help="alpha that gives restitution EPS at influence factor XI")
    a.add_argument("eps", type=_number, help="Stronge restitution coefficient, 0 <= EPS <= 1")
    a.add_argument("xi", type=_number, help="influence factor of the load, 0 <= XI < 1")
    a.add_argument("--tol", type=_number, default=EPS_TOL, help=f"tolerance on eps (default {EPS_TOL})")
    i = sub.add_parser("impact", help="integrate one impact with damping ALPHA at influence factor XI")
    i.add_argument("alpha", type=_number, help="hysteresis damping factor, ALPHA >= 0")
    i.add_argument("xi", type=_number, help="influence factor of the load, 0 <= XI < 1")
    s = sub.add_parser("scene", help="which contact model a scene needs (scene advisor)")
    s.add_argument(
        "eps", type=_number, help="requested restitution (Stronge's eps; e_N with --kinematic), 0 < EPS <= 1"
    )
    s.add_argument("--mass", type=_number, required=True, help="effective mass, kg")
    s.add_argument("--stiffness", type=_number, required=True, help="Hertz stiffness k, N/m^1.5")
    s.add_argument("--speed", type=_number, required=True, help="approach speed, m/s")
    load = s.add_mutually_exclusive_group(required=True)
    load.add_argument("--accel", type=_number, help="constant acceleration into the contact, m/s^2")
    load.add_argument("--force", type=_number, help="constant force into the contact, N")
    s.add_argument("--tol", type=_number, default=0.01, help="tolerance on the delivered eps (default 0.01)")
    s.add_argument(
        "--kinematic", action="store_true", help="EPS is Newton's kinematic e_N (default: Stronge's eps)"
    )
    s.add_argument("--json", action="store_true", help="print the advice as JSON")
    c = sub.add_parser("check-config", help="check workflow config files as `snakemake -n` would")
    c.add_argument("files", nargs="+", help="YAML config files (e.g. one given to --configfile)")
    c.add_argument("--schema", default=SCHEMA, help=f"the workflow's JSON schema (default {SCHEMA})")
    f = sub.add_parser("params", help="contact parameters of a scene in SI units, per engine (front door)")
    target = f.add_mutually_exclusive_group(required=True)
    target.add_argument("--eps", type=_number, help="Stronge's energetic restitution, 0 <= EPS <= 1")
    target.add_argument("--e-n", dest="e_n", type=_number, help="Newton's kinematic e_N, 0 < E_N <= 1")
    f.add_argument("--mass", type=_number, required=True, help="effective mass, kg")
    f.add_argument("--stiffness", type=_number, required=True, help="Hertz stiffness k, N/m^1.5")
    f.add_argument("--speed", type=_number, required=True, help="approach speed, m/s")
    f_load = f.add_mutually_exclusive_group(required=True)
    f_load.add_argument("--accel", type=_number, help="constant acceleration into the contact, m/s^2")
    f_load.add_argument("--force", type=_number, help="constant force into the contact, N")
    f.add_argument("--radius", type=_number, help="sphere radius, m (adds OpenSim's stiffness)")
    f.add_argument("--json", action="store_true", help="print the parameters as JSON")
    x = sub.add_parser("export-c", help="write the exact-alpha tables and evaluator as C99 source")
    x.add_argument("directory", help="folder to write contactalpha.h and contactalpha.c into")
    return p


def _print_advice(adv):
    from contactalpha.scene.advisor import format_advice

    print(format_advice(adv))


def main(argv=None):
    """Run the command line; returns the exit status (2 for bad input, 1 for a failed solve)."""
    args = build_parser().parse_args(argv)
    try:
        if args.command == "check-config":
            from contactalpha.config import load_config

            for path in args.files:
                load_config(path, args.schema)
                print(f"{path}: ok")
            return 0
        if args.command == "scene":
            from contactalpha.io import json_text
            from contactalpha.scene.advisor import advise

            kw = {"accel": args.accel} if args.accel is not None else {"force": args.force}
            kw["restitution"] = "kinematic" if args.kinematic else "energetic"
            adv = advise(args.eps, args.mass, args.stiffness, args.speed, tol=args.tol, **kw)
            print(json_text(adv.to_dict(), indent=1)) if args.json else _print_advice(adv)
            return 0
        if args.command == "export-c":
            from contactalpha.export.c_source import export_c

            for path in export_c(args.directory):
                print(path)
            return 0
        if args.command == "params":
            from dataclasses import asdict

            from contactalpha.io import json_text
            from contactalpha.scene.parameters import contact_parameters, format_parameters

            cp = contact_parameters(
                args.eps,
                args.mass,
                args.stiffness,
                args.speed,
                e_N=args.e_n,
                accel=args.accel,
                force=args.force,
                radius=args.radius,
            )
            print(json_text(asdict(cp), indent=1) if args.json else format_parameters(cp))
            return 0
        if args.command == "alpha":
            s = solve_alpha(args.eps, args.xi, tol=args.tol, rtol=args.rtol, atol=args.atol)
            print(f"alpha        {s.alpha:.15g}")
            print(f"eps reached  {s.eps_reached:.15g}")
            print(f"e_N reached  {s.e_n_reached:.15g}")
            print(f"end state    {s.state}")
            print(f"impacts      {s.impacts}")
            print(f"steps        {s.steps}")
            print(f"status       {s.status}")
            return 0 if s.ok else 1
        r = impact(args.alpha, args.xi, rtol=args.rtol, atol=args.atol)
        print(f"eps          {r.eps:.15g}")
        print(f"e_N          {r.e_n:.15g}")
        print(f"end state    {r.state}")
        print(f"x_max        {r.x_max:.15g}")
        print(f"x_end        {r.x_end:.15g}")
        print(f"v_end        {r.v_end:.15g}")
        print(f"t_max        {r.t_max:.15g}")
        print(f"t_end        {r.t_end:.15g}")
        print(f"steps        {r.steps}")
        print(f"status       {r.status}")
        return 0 if r.ok else 1
    except (ValueError, RuntimeError, OSError) as exc:
        # Bad input, a failed solve, a file that cannot be written: one line, never a traceback.
        message = " ".join(str(exc).split()) or type(exc).__name__
        print(f"contactalpha: error: {message}", file=sys.stderr)
        return 2


if __name__ == "__main__":  # pragma: no cover
    sys.exit(main())
