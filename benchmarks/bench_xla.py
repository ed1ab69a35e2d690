"""The JAX front door against the numba batch on this CPU, in one run (issue 36).

For N random scenes of the default law (Hunt-Crossley, n = 3/2; Newton's e_N), times, best of
``--repeat``:

- the table lookup alone: ``engine.table.alpha_tabulated`` (numba, its threads) against
  ``xla.table_damping`` under ``jax.jit`` (XLA's CPU threads), and their ratio;
- the whole front door: ``parameters.batch.batched_parameters`` against ``xla.contact_parameters``
  (load factor, lookup, engine damping), and their ratio;
- where the numba front door's time goes: the load factor (Eq. 10 solved per scene), the lookup,
  and the impact it integrates per scene to report what the damping delivers;
- the numba lookup on one thread.

The first (compiling) call of each is timed apart.  GPU numbers come only where JAX sees a GPU
(``jax.devices()``); the device is printed.  Prints the largest relative difference of the two
lookups.  Timings depend on the machine's load (printed).

Usage:  python benchmarks/bench_xla.py [--n 1000000] [--repeat 3]
"""

import argparse
import os
import time

import numpy as np


def best(fn, repeat):
    out = None
    times = []
    for _ in range(repeat):
        t = time.perf_counter()
        out = fn()
        times.append(time.perf_counter() - t)
    return min(times), out


def main():
    import jax

    jax.config.update("jax_enable_x64", True)
    from contactalpha.engine.table import alpha_tabulated
    from contactalpha.laws import get_law
    from contactalpha.parameters.batch import batched_parameters, hertz_load_factor
    from contactalpha.xla import contact_parameters, device_table, table_damping

    p = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    p.add_argument("--n", type=int, default=1_000_000)
    p.add_argument("--repeat", type=int, default=3)
    args = p.parse_args()
    rng = np.random.default_rng(0)
    n = args.n
    s = {
        "mass": rng.uniform(0.1, 2.0, n),
        "stiffness": 10.0 ** rng.uniform(6.0, 9.0, n),
        "approach_speed": rng.uniform(0.2, 3.0, n),
        "accel": rng.uniform(0.0, 50.0, n),
        "target": rng.uniform(0.05, 0.95, n),
    }
    e, xi = s["target"], rng.uniform(0.0, 0.99, n)
    print(
        f"machine load (1 min): {os.getloadavg()[0]:.2f} on {os.cpu_count()} cores; "
        f"JAX devices: {jax.devices()}"
    )

    tab = device_table(get_law(), "kinematic")
    lookup = jax.jit(lambda e, x: table_damping(tab, e, x))
    ej, xj = jax.device_put(e), jax.device_put(xi)
    t = time.perf_counter()
    jax.block_until_ready(lookup(ej[:8], xj[:8]))
    jax.block_until_ready(lookup(ej, xj))
    compile_lookup = time.perf_counter() - t
    alpha_tabulated(e[:8], xi[:8], restitution="kinematic")
    t_nb, ref = best(lambda: alpha_tabulated(e, xi, restitution="kinematic"), args.repeat)
    t_jx, got = best(lambda: jax.block_until_ready(lookup(ej, xj)), args.repeat)
    worst = float(np.max(np.abs(np.asarray(got) / ref - 1.0)))
    print(f"lookup, first JAX calls (compile): {compile_lookup:.2f} s")
    print(
        f"lookup numba: {n / t_nb:.3g} scenes/s; JAX: {n / t_jx:.3g} scenes/s; "
        f"JAX/numba time ratio {t_jx / t_nb:.2f}"
    )
    print(f"lookup max relative difference: {worst:.1e}")

    front = jax.jit(lambda **kw: contact_parameters(**kw))
    t = time.perf_counter()
    jax.block_until_ready(front(**s))
    compile_front = time.perf_counter() - t
    batched_parameters(**{k: v[:8] for k, v in s.items()})
    t_nbf, _ = best(lambda: batched_parameters(**s), args.repeat)
    t_jxf, _ = best(lambda: jax.block_until_ready(front(**s)), args.repeat)
    print(f"front door, first JAX call (compile): {compile_front:.2f} s")
    print(
        f"front door numba: {n / t_nbf:.3g} scenes/s; JAX: {n / t_jxf:.3g} scenes/s; "
        f"time ratio JAX/numba {t_jxf / t_nbf:.2f}"
    )

    args5 = [s[k] for k in ("mass", "stiffness", "approach_speed", "accel")]
    t_xi, xi_s = best(lambda: hertz_load_factor(*args5), args.repeat)
    ok = xi_s <= 0.99
    t_lk, alpha = best(lambda: alpha_tabulated(e[ok], xi_s[ok], restitution="kinematic"), args.repeat)
    sub = min(alpha.size, 20_000)  # a sample: the impact costs about a thousand lookups
    t_imp, _ = best(lambda: get_law().impact(alpha[:sub], xi_s[ok][:sub]), 1)
    t_imp *= n / sub
    print(
        f"numba front door, where the time goes (s per 1e6 scenes): total {t_nbf / n * 1e6:.3f}; "
        f"load factor {t_xi / n * 1e6:.3f}; lookup {t_lk / n * 1e6:.3f}; one integrated impact per "
        f"scene (the front door runs three: at the damping, at half and twice the speed) "
        f"{t_imp / n * 1e6:.3f}"
    )
    import numba

    threads = numba.get_num_threads()
    numba.set_num_threads(1)
    t_nb1, _ = best(lambda: alpha_tabulated(e, xi, restitution="kinematic"), args.repeat)
    numba.set_num_threads(threads)
    print(
        f"lookup numba, one thread: {n / t_nb1:.3g} scenes/s ({threads} threads above); "
        f"JAX/numba time ratio {t_jx / t_nb1:.2f}"
    )


if __name__ == "__main__":
    main()
