"""Benchmark (run by hand): Monitor.observe_many over numpy arrays, ns per sample, against the
Rust library's figure (`cargo bench --bench monitor`, `observe_all`). Also observe one call
per sample, for scale. Run: python python/benches/observe_many.py (after `pip install .`)."""

import pathlib
import time

import numpy as np

import safereach as sr

ROOT = pathlib.Path(__file__).resolve().parents[2]


def trace(n, dt=0.1, w=0.15):
    """A run within the seed's premises at W = 0.2: the robot waits at 0, the obstacle
    approaches from far away at speeds up to w, reported with each sample."""
    rng = np.random.default_rng(2016)
    t = np.arange(n) * dt
    v = rng.uniform(0.0, w, n)
    x = 1e6 - np.concatenate(([0.0], np.cumsum(v[1:] * dt)))
    v[0] = 0.0
    zeros = np.zeros(n)
    return t, zeros, zeros.copy(), x, v


def best_of(runs, f):
    best = float("inf")
    for _ in range(runs):
        start = time.perf_counter()
        f()
        best = min(best, time.perf_counter() - start)
    return best


def main():
    p = sr.Problem.from_file(str(ROOT / "problems" / "seed.toml"))
    p.set("environment.obstacle_speed", 0.2)
    cert = sr.certify(p)
    n = 1_000_000
    t, rx, rv, ox, ov = trace(n)

    def many():
        m = sr.Monitor(cert)
        verdict, events = m.observe_many(t, rx, rv, ox, ov)
        assert verdict == "held" and not events, events[:1]

    s = best_of(5, many)
    print(f"observe_many: {s / n * 1e9:.1f} ns/sample ({n / s / 1e6:.1f} M samples/s), best of 5, {n} samples")
    k = 100_000
    cols = [c[:k].tolist() for c in (t, rx, rv, ox, ov)]

    def one_by_one():
        m = sr.Monitor(cert)
        observe = m.observe
        for a, b, c, d, e in zip(*cols):
            observe(a, b, c, d, e)

    s = best_of(3, one_by_one)
    print(f"observe, one call per sample: {s / k * 1e9:.0f} ns/sample, best of 3, {k} samples")


if __name__ == "__main__":
    main()
