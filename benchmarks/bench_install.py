"""Benchmark of the core install against the workflow install (issue 25, item 3).

Run: ``python benchmarks/bench_install.py [--extras workflow] [--keep DIR]``.
For each of ``pip install .`` (the core: numpy, scipy, numba) and ``pip install ".[workflow]"``
it makes a fresh virtual environment, times the install (wall clock; pip's download cache is
used as a user's would be after a first install, ``--no-cache`` empties it for the run), and
prints the distributions installed and the size of the environment's site-packages.  Then, in
the core environment, it checks that no workflow dependency was installed and runs every public
entry point of the core (the library calls and the command line) from a scratch directory.
"""

import argparse
import os
import platform
import shutil
import subprocess
import sys
import tempfile
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
WORKFLOW_ONLY = ("snakemake", "xarray", "pandas", "matplotlib", "h5py", "h5netcdf", "fonttools", "jsonschema")
CORE_CHECK = """
import warnings, contactalpha as ca
print(ca.alpha(0.5, 0.2), ca.alpha(0.5, 0.2, restitution="kinematic"))
print(ca.contact_parameters(0.5, 2.0, 2.51e6, 0.5, accel=9.81).damping)
print(ca.contact_parameters(e_N=0.5, mass=2.0, stiffness=2.51e6, approach_speed=0.5, accel=9.81).damping)
print(ca.advise(0.5, 2.0, 2.51e6, 0.5, accel=9.81).recommended)
print(ca.critical_speed(0.5, 2.0, 2.51e6, 9.81))
print(ca.predict_bounces(ca.Scene(), "exact").approach_speeds[:3])
print(ca.hertz_stiffness(200e9, 0.3, 0.01, modulus_2=200e9, poisson_2=0.3))
print(ca.solve_alpha(0.5, 0.2).alpha, ca.convert_restitution(0.5, 0.2))
import sys
assert not {"xarray", "pandas", "matplotlib", "snakemake", "yaml"} & set(sys.modules), sorted(sys.modules)
"""
CLI_CHECKS = (
    ["--version"],
    ["alpha", "0.5", "0.2"],
    ["alpha", "--e-n", "0.5", "--xi", "0.2"],
    ["export-c", "c_out"],
    ["params", "--eps", "0.5", "--mass", "2", "--stiffness", "2.51e6", "--speed", "0.5", "--accel", "9.81"],
    ["scene", "--eps", "0.5", "--mass", "2", "--stiffness", "2.51e6", "--speed", "0.5", "--accel", "9.81"],
    ["hertz", "--modulus", "200e9", "--poisson", "0.3", "--radius", "0.01"],
)


def site_packages_bytes(env):
    """Bytes under the environment's site-packages."""
    sp = next(Path(env).glob("lib/python*/site-packages"))
    return sum(f.stat().st_size for f in sp.rglob("*") if f.is_file() and not f.is_symlink())


def install(env, spec, no_cache):
    """Make a venv at ``env``, pip install ``spec`` into it; returns (seconds, distributions)."""
    subprocess.run([sys.executable, "-m", "venv", env], check=True)
    pip = [f"{env}/bin/python", "-m", "pip", "install", "-q", "--disable-pip-version-check"]
    clock = time.perf_counter()
    subprocess.run([*pip, *(["--no-cache-dir"] if no_cache else []), spec], check=True)
    seconds = time.perf_counter() - clock
    out = subprocess.run(
        [f"{env}/bin/python", "-m", "pip", "list", "--format=freeze", "--disable-pip-version-check"],
        check=True,
        capture_output=True,
        text=True,
    ).stdout
    return seconds, sorted(line.split("==")[0].lower() for line in out.split())


def main(argv=None):
    p = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    p.add_argument("--extras", default="workflow", help="the full install's extras (default workflow)")
    p.add_argument("--no-cache", action="store_true", help="pip without its download cache")
    p.add_argument("--keep", default=None, help="make the environments here and keep them")
    args = p.parse_args(argv)
    base = args.keep or tempfile.mkdtemp(prefix="bench_install_")
    machine = platform.processor() or platform.machine()
    print(f"machine: {machine}, {os.cpu_count()} cores, {platform.platform()}")
    print(f"load average: {os.getloadavg()[0]:.2f}; pip cache: {'off' if args.no_cache else 'on'}")
    rows = {}
    try:
        for label, spec in (("core", str(ROOT)), (f"[{args.extras}]", f"{ROOT}[{args.extras}]")):
            env = os.path.join(base, "core" if label == "core" else "full")
            seconds, dists = install(env, spec, args.no_cache)
            rows[label] = (seconds, len(dists), site_packages_bytes(env), dists)
            print(
                f"{label:12s} install {seconds:6.1f} s, {len(dists):3d} distributions, "
                f"site-packages {rows[label][2] / 2**20:7.1f} MiB"
            )
        (cs, cn, cb, cdists), (fs, fn, fb, _) = rows.values()
        print(f"core / full: time {cs / fs:.2f}, size {cb / fb:.2f}, distributions {cn}/{fn}")
        stray = [d for d in cdists if d in WORKFLOW_ONLY]
        print(f"core distributions: {' '.join(cdists)}")
        print(f"workflow dependencies in the core install: {stray or 'none'}")
        env = os.path.join(base, "core")
        with tempfile.TemporaryDirectory() as scratch:
            run = {"cwd": scratch, "check": True, "capture_output": True, "text": True}
            subprocess.run([f"{env}/bin/python", "-c", CORE_CHECK], **run)
            for cli in CLI_CHECKS:
                subprocess.run([f"{env}/bin/contactalpha", *cli], **run)
        print(f"core entry points: {len(CLI_CHECKS)} CLI commands and the library calls ran")
    finally:
        if args.keep is None:
            shutil.rmtree(base, ignore_errors=True)


if __name__ == "__main__":
    main()
