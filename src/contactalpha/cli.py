"""Command line: ``contactalpha params``, ``scene``, ``alpha``, ``hertz``, ``impact``, ``warmup``, ...

Every subcommand takes the restitution the same way (``--eps`` or ``--e-n``, or ``--kinematic``),
and its options before or after the subcommand's name; ``-h`` shows examples.

Building the parser imports no kernel (no numba, no SciPy): what ``--help`` shows comes from the
leaf ``contactalpha.defaults`` and the subcommands' parser modules, and each handler imports what
it runs.
"""

import argparse
import importlib.util
import math
import os
import re
import sys
from pathlib import Path

from contactalpha.calibration import command as calibrate_command
from contactalpha.defaults import (
    ATOL,
    EPS_TOL,
    EXIT_UNREACHABLE,
    RTOL,
    STIFFNESS_UNITS,
)
from contactalpha.version import __version__


def _parser_module(name):
    """The parser module ``contactalpha.<name>``, loaded without its package's ``__init__``.

    ``contactalpha.mechanism`` imports every engine's model reader when it loads; its ``command``
    module (the ``tune`` subcommand's parser) needs none of them until it runs.
    """
    if name in sys.modules:
        return sys.modules[name]
    path = Path(__file__).parent.joinpath(*name.split(".")[1:]).with_suffix(".py")
    spec = importlib.util.spec_from_file_location(name, path)
    assert spec is not None and spec.loader is not None  # a .py file in the package always has both
    module = importlib.util.module_from_spec(spec)
    sys.modules[name] = module
    spec.loader.exec_module(module)
    return module


tune_command = _parser_module("contactalpha.mechanism.command")


def _number(text):
    try:
        return float(text)
    except ValueError:
        raise argparse.ArgumentTypeError(f"{text!r} is not a number") from None


def _step(text):
    """A step in s, or the word "default" (the engine's own default step)."""
    return text if text == "default" else _number(text)


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

FORCE_HELP = (
    "constant force pressing the bodies together, N; gravity is NOT added: add the weight m g "
    "yourself, or give --accel g + F/m"
)


def stiffness_help():
    """How ``params`` reads --stiffness (from ``defaults``): physical, the unit of each law's k."""
    parts = []
    for unit in dict.fromkeys(STIFFNESS_UNITS.values()):
        laws = ", ".join(law for law, u in STIFFNESS_UNITS.items() if u == unit)
        parts.append(f"{unit} for {laws}")
    return (
        "the contact law's physical stiffness k: " + "; ".join(parts) + "; never per unit mass (MuJoCo's "
        "block divides by --mass); default law hunt_crossley"
    )


# Exit statuses of `params` (its -h prints them).
PARAMS_EXIT = (
    "exit status: 0 parameters printed; 2 bad input (one line on stderr); "
    f"{EXIT_UNREACHABLE} no damping reaches the target (stderr names the nearest reachable target "
    "and what would reach this one)"
)
# Each subcommand's examples (shown by -h).
EXAMPLES = {
    "alpha": (
        "contactalpha alpha --eps 0.5 --xi 0.2",
        "contactalpha alpha --e-n 0.5 --xi 0.2",
        "contactalpha alpha 0.5 0.2 --rtol 1e-10",
    ),
    "impact": ("contactalpha impact 1.5 0.2",),
    "scene": (
        "contactalpha scene --eps 0.3 --mass 2 --stiffness 2.51e6 --speed 0.5 --force 619.62",
        "contactalpha scene --e-n 0.6 --mass 0.5 --stiffness 1.4e8 --speed 0.5 --accel 9.81 --speeds 0.1 1",
    ),
    "params": (
        "contactalpha params --e-n 0.6 --mass 2 --stiffness 2.51e6 --speed 0.5 --accel 9.81",
        "contactalpha params --eps 0.5 --mass 2 --stiffness 2.51e6 --speed 0.5 --force 600 --radius 0.05",
        "contactalpha params --e-n 0.5 --mass 0.1 --stiffness 1e4 --speed 1 --accel 9.81 --engine mujoco",
    ),
    "hertz": (
        "contactalpha hertz --modulus 210e9 --poisson 0.3 --radius 0.01  # steel ball, steel plate",
        "contactalpha hertz --modulus 210e9 --poisson 0.3 --radius 0.01 --modulus-2 inf  # rigid plate",
    ),
    "export-c": ("contactalpha export-c build/  # build/contactalpha.h, build/contactalpha.c",),
    "check-config": ("contactalpha check-config config.yaml workflow/configs/fine.yaml",),
    "warmup": ("contactalpha warmup  # once after installing: first calls then load compiled code",),
    "calibrate": (
        "contactalpha calibrate data/drops/hc_eps_times.csv --mass 0.05 --radius 0.02",
        "contactalpha calibrate heights.csv --mass 0.05 --hypothesis all --json report.json --figures drop",
    ),
    "tune": tune_command.EXAMPLES,
}


def _integrator_options(parser, defaults):
    """``--rtol``/``--atol``: on the main parser with defaults, on a subcommand without (SUPPRESS)."""
    parser.add_argument("--rtol", type=_number, default=RTOL if defaults else argparse.SUPPRESS,
                        help=f"integrator rtol (default {RTOL})")  # fmt: skip
    parser.add_argument("--atol", type=_number, default=ATOL if defaults else argparse.SUPPRESS,
                        help=f"integrator atol (default {ATOL})")  # fmt: skip


def _restitution_options(parser, positional):
    """The restitution, the same way in every subcommand: ``--eps`` or ``--e-n`` (or ``--kinematic``)."""
    if positional:
        parser.add_argument("eps_positional", nargs="?", type=_number, metavar="EPS",
                            help="the restitution as a positional value (same as --eps)")  # fmt: skip
    target = parser.add_mutually_exclusive_group()
    target.add_argument("--eps", type=_number, help="Stronge's energetic restitution eps, 0 <= EPS <= 1")
    target.add_argument("--e-n", dest="e_n", type=_number, help="Newton's kinematic e_N, 0 < E_N <= 1")
    parser.add_argument("--kinematic", action="store_true", help="EPS is Newton's kinematic e_N (as --e-n)")


def _scene_options(parser, stiffness_help=None):
    parser.add_argument("--mass", type=_number, required=True, help="effective mass, kg")
    stiffness_help = stiffness_help or "Hertz stiffness k, N/m^1.5 (`contactalpha hertz` computes it)"
    parser.add_argument("--stiffness", type=_number, required=True, help=stiffness_help)
    parser.add_argument("--speed", type=_number, required=True, help="approach speed, m/s")
    load = parser.add_mutually_exclusive_group(required=True)
    load.add_argument(
        "--accel", type=_number, help="constant acceleration into the contact, m/s^2 (g included)"
    )
    load.add_argument("--force", type=_number, help=FORCE_HELP)


def _sub(sub, name, help_text):
    epilog = "examples:\n" + "\n".join(f"  {line}" for line in EXAMPLES.get(name, ()))
    p = sub.add_parser(name, help=help_text, description=help_text, epilog=epilog,
                       formatter_class=argparse.RawDescriptionHelpFormatter)  # fmt: skip
    p.error = Parser.error.__get__(p)  # one-line errors in every subcommand too
    p.set_defaults(subparser=p)  # the handlers word their errors as this subcommand's
    return p


def build_parser():
    """Return the argument parser of the ``contactalpha`` command."""
    p = Parser(
        prog="contactalpha",
        description="Hunt-Crossley damping factor alpha under a constant external load.",
        epilog="Options go before or after the subcommand; `contactalpha SUBCOMMAND -h` shows examples.",
    )
    p.add_argument("--version", action="version", version=f"%(prog)s {__version__}")
    _integrator_options(p, defaults=True)
    sub = p.add_subparsers(dest="command", required=True)
    a = _sub(sub, "alpha", "exact alpha that gives restitution EPS (or e_N) at influence factor XI")
    _restitution_options(a, positional=True)
    a.add_argument("xi_positional", nargs="?", type=_number, metavar="XI", help="same as --xi")
    a.add_argument("--xi", type=_number, help="influence factor of the load, 0 <= XI < 1")
    a.add_argument("--tol", type=_number, default=EPS_TOL, help=f"tolerance on eps (default {EPS_TOL})")
    _integrator_options(a, defaults=False)
    i = _sub(sub, "impact", "integrate one impact with damping ALPHA at influence factor XI")
    i.add_argument("alpha", type=_number, help="hysteresis damping factor, ALPHA >= 0")
    i.add_argument("xi", type=_number, help="influence factor of the load, 0 <= XI < 1")
    _integrator_options(i, defaults=False)
    s = _sub(sub, "scene", "which contact model a scene needs, judged over its speeds (scene advisor)")
    _restitution_options(s, positional=True)
    _scene_options(s)
    s.add_argument("--tol", type=_number, default=0.01, help="tolerance on the delivered eps (default 0.01)")
    s.add_argument("--speeds", type=_number, nargs=2, metavar=("LOW", "HIGH"),
                   help="judge over these approach speeds, m/s (default: the bounce sequence)")  # fmt: skip
    s.add_argument("--json", action="store_true", help="print the advice as JSON")
    c = _sub(sub, "check-config", "check workflow config files as `snakemake -n` would (needs [workflow])")
    c.add_argument("files", nargs="+", help="YAML config files (e.g. one given to --configfile)")
    c.add_argument("--schema", default=SCHEMA, help=f"the workflow's JSON schema (default {SCHEMA})")
    f = _sub(sub, "params", "contact parameters of a scene in SI units, per engine (front door)")
    f.epilog += "\n\n" + PARAMS_EXIT
    _restitution_options(f, positional=False)
    _scene_options(f, stiffness_help())
    f.add_argument("--radius", type=_number, help="sphere radius, m (adds OpenSim's stiffness)")
    f.add_argument("--json", action="store_true", help="print the parameters as JSON")
    f.add_argument(
        "--engine",
        help="solve for this registered engine's law and print its block, in its own names and units "
        "(the engines pages list them; an unknown name is refused with "
        "the registry's list)",
    )
    f.add_argument(
        "--refine", action="store_true", help="with --engine: refine on the engine's own drops (needs it)"
    )
    f.add_argument("--quiet", action="store_true", help="no progress lines on stderr (--refine prints them)")
    f.add_argument(
        "--timestep",
        type=_step,
        nargs="?",
        const="default",
        help="with --engine: the engine's step, s (alone: its default step); the answer is then for the "
        "mean over a uniformly random touchdown phase at that step, with the range one drop sees",
    )
    f.add_argument(
        "--verify",
        type=lambda text: text if text == "default" else int(text),
        nargs="?",
        const="default",
        metavar="N",
        help="with --timestep: run the installed engine at N touchdown phases, measured against "
        "predicted, with the sampling error of the N-phase mean (alone: N doubles until that error is "
        "small; docs/stepping.md)",
    )
    f.add_argument(
        "--law",
        help="contact law (contactalpha.laws.LAWS; default hunt_crossley, n = 3/2); "
        "--stiffness is then that law's physical stiffness (N/m for n = 1, N/m^1.5 for n = 3/2)",
    )
    h = _sub(sub, "hertz", "Hertz stiffness k (N/m^1.5) of two bodies from moduli, Poisson ratios, radii")
    h.add_argument("--modulus", type=_number, required=True, help="Young's modulus of body 1, Pa")
    h.add_argument("--poisson", type=_number, required=True, help="Poisson ratio of body 1, in (-1, 0.5]")
    h.add_argument("--radius", type=_number, required=True, help="radius of body 1 at the contact, m")
    h.add_argument("--modulus-2", type=_number, help="body 2's modulus, Pa (default body 1's; inf: rigid)")
    h.add_argument("--poisson-2", type=_number, help="body 2's Poisson ratio (default body 1's)")
    h.add_argument(
        "--radius-2", type=_number, default=math.inf, help="body 2's radius, m (default inf: a flat)"
    )
    x = _sub(sub, "export-c", "write the exact-alpha tables and evaluator as C99 source")
    x.add_argument("directory", help="folder to write contactalpha.h and contactalpha.c into")
    _sub(sub, "warmup", "compile every numba kernel now (later first calls load the compiled code)")
    calibrate_command.add_parser(lambda name, text: _sub(sub, name, text), _number)
    tune_command.add_parser(lambda name, text: _sub(sub, name, text), _number)
    return p


def _restitution(args, parser):
    """``(value, "energetic" | "kinematic")`` from ``EPS``, ``--eps``, ``--e-n`` and ``--kinematic``."""
    given = [v for v in (getattr(args, "eps_positional", None), args.eps, args.e_n) if v is not None]
    if len(given) != 1:
        parser.error("give the restitution once: --eps EPS (Stronge's) or --e-n E_N (Newton's kinematic)")
    kinematic = args.e_n is not None or args.kinematic
    return given[0], "kinematic" if kinematic else "energetic"


def _print_advice(adv):
    from contactalpha.scene.advisor import format_advice

    print(format_advice(adv))


def main(argv=None):
    """Run the command line; the exit status: 2 bad input, 1 a failed solve, 3 an unreachable target."""
    parser = build_parser()
    args = parser.parse_args(argv)
    try:
        return COMMANDS[args.command](args, args.subparser)
    except BrokenPipeError:
        # The reader went away (`contactalpha params ... | head`): not an error of ours. Point
        # stdout at devnull so that Python's flush at exit does not raise again.
        os.dup2(os.open(os.devnull, os.O_WRONLY), sys.stdout.fileno())
        return 0
    except (ValueError, RuntimeError, OSError, ImportError) as exc:
        message = " ".join(str(exc).split()) or type(exc).__name__
        if _unreachable(exc):
            # No damping reaches the target: the nearest reachable one and the remedy, one line.
            print(f"contactalpha: unreachable: {message}", file=sys.stderr)
            return EXIT_UNREACHABLE
        # Bad input, a failed solve, a file that cannot be written, an optional engine not
        # installed (its message says how to install it): one line, never a traceback.
        print(f"contactalpha: error: {message}", file=sys.stderr)
        return 2


def _unreachable(exc):
    """True for ``parameters.reach.UnreachableTarget`` (only a loaded ``reach`` can have raised one)."""
    reach = sys.modules.get("contactalpha.parameters.reach")
    return reach is not None and isinstance(exc, reach.UnreachableTarget)


def _check_config(args, parser):
    try:
        from contactalpha.config import load_config
    except ModuleNotFoundError as exc:
        print(
            f"contactalpha: error: check-config needs the workflow's libraries ({exc.name} is missing): "
            'pip install "contactalpha[workflow]"',
            file=sys.stderr,
        )
        return 2
    for path in args.files:
        load_config(path, args.schema)
        print(f"{path}: ok")
    return 0


def _scene(args, parser):
    from contactalpha.io import json_text
    from contactalpha.scene.advisor import advise

    value, restitution = _restitution(args, parser)
    kw = {"accel": args.accel} if args.accel is not None else {"force": args.force}
    adv = advise(value, args.mass, args.stiffness, args.speed, tol=args.tol, restitution=restitution,
                 speeds=None if args.speeds is None else tuple(args.speeds), **kw)  # fmt: skip
    print(json_text(adv.to_dict(), indent=1)) if args.json else _print_advice(adv)
    return 0


def _export_c(args, parser):
    from contactalpha.export.c_source import export_c

    for path in export_c(args.directory):
        print(path)
    return 0


def _print_engine(args, value, restitution):
    """``params --engine NAME``: that engine's block (``parameters.engine_block``)."""
    from contactalpha.adapters.registry import adapter
    from contactalpha.io import json_text
    from contactalpha.parameters.engine_block import engine_answer, format_block
    from contactalpha.progress import Progress

    if args.refine:
        label = f"contactalpha: refining on {args.engine}'s drops"
    elif args.timestep is not None:
        label = f"contactalpha: solving at {args.engine}'s step" + (
            " and verifying in the engine" if args.verify else ""
        )
    else:
        label = f"contactalpha: {args.engine}'s parameters"
    with Progress(label) as progress:
        params, notes, stepped = engine_answer(
            args.engine, value, args.mass, args.stiffness, args.speed, args.accel, force=args.force,
            restitution=restitution, radius=args.radius, refine=args.refine,
            timestep=args.timestep, verify=args.verify, progress=None if args.quiet else progress,
        )  # fmt: skip
    if args.json:
        units = getattr(adapter(args.engine), "units", {})
        data = {"engine": args.engine, "parameters": params, "units": units, "notes": notes}
        if stepped is not None:  # the answer at the step as numbers (mean, minimum, maximum, steps, ...)
            data["stepped"] = stepped
        print(json_text(data, indent=1))
    else:
        print(format_block(args.engine, params, notes))
    return 0


def _params(args, parser):
    from contactalpha.adapters.registry import adapter
    from contactalpha.dem.load import load_effect
    from contactalpha.io import json_text
    from contactalpha.parameters.front_door import contact_parameters
    from contactalpha.parameters.result import as_plain_data, format_parameters

    value, restitution = _restitution(args, parser)
    if args.engine is not None and args.law is not None:
        raise ValueError("give --engine or --law, not both: an engine's block uses its own law")
    if args.engine is not None:
        return _print_engine(args, value, restitution)
    if args.timestep is not None or args.verify is not None:
        raise ValueError("--timestep and --verify need --engine: the step is an engine's")
    target = {"eps": value} if restitution == "energetic" else {"e_N": value}
    cp = contact_parameters(
        law=args.law,
        mass=args.mass,
        stiffness=args.stiffness,
        approach_speed=args.speed,
        accel=args.accel,
        force=args.force,
        radius=args.radius,
        **target,
    )
    data = as_plain_data(cp) | {
        "unit_notes": {
            name: " ".join(adapter(name).unit_notes) for name in cp.engines if adapter(name).unit_notes
        },
        "units": {name: getattr(adapter(name), "units", {}) for name in cp.engines},
    }
    effect = load_effect(cp.law, value, restitution, args.mass, args.stiffness, args.speed, cp.accel)
    data["load_effect"] = effect.to_dict()
    print(json_text(data, indent=1) if args.json else format_parameters(cp) + "\n" + effect.line())
    return 0


def _hertz(args, parser):
    from contactalpha.scene.hertz import hertz_stiffness

    k = hertz_stiffness(args.modulus, args.poisson, args.radius, modulus_2=args.modulus_2,
                        poisson_2=args.poisson_2, radius_2=args.radius_2)  # fmt: skip
    print(f"stiffness    {k:.15g} N/m^1.5")
    return 0


def _warmup(args, parser):
    from contactalpha.warmup import warm_up

    def progress(name, seconds):
        print(f"{name:10s} {seconds:6.1f} s", file=sys.stderr, flush=True)

    print("contactalpha: compiling every kernel (or loading it from numba's cache) ...", file=sys.stderr)
    total = sum(warm_up(progress=progress).values())
    print(f"ready        {total:.1f} s")
    return 0


def _alpha(args, parser):
    from contactalpha.engine.solver import solve_alpha

    value, restitution = _restitution(args, parser)
    xi = [v for v in (args.xi_positional, args.xi) if v is not None]
    if len(xi) != 1:
        parser.error("give the influence factor once: --xi XI (or the second positional value)")
    s = solve_alpha(value, xi[0], tol=args.tol, rtol=args.rtol, atol=args.atol, restitution=restitution)
    print(f"alpha        {s.alpha:.15g}")
    print(f"eps reached  {s.eps_reached:.15g}")
    print(f"e_N reached  {s.e_n_reached:.15g}")
    print(f"end state    {s.state}")
    print(f"impacts      {s.impacts}")
    print(f"steps        {s.steps}")
    print(f"status       {s.status}")
    return 0 if s.ok else 1


def _impact(args, parser):
    from contactalpha.engine.driver import impact

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


# Subcommand -> its handler ``f(args, parser) -> exit status``.
COMMANDS = {
    "alpha": _alpha,
    "impact": _impact,
    "scene": _scene,
    "check-config": _check_config,
    "params": _params,
    "hertz": _hertz,
    "export-c": _export_c,
    "warmup": _warmup,
    "calibrate": lambda args, parser: calibrate_command.run(args),
    "tune": tune_command.run,
}


if __name__ == "__main__":  # pragma: no cover
    sys.exit(main())
