"""The particle filter of labs::mrclam, written the way a NumPy user writes it (vectorised
over the particles, a Python loop over the steps), for the benchmark beside the
reference: scripts/bench-mrclam runs it on the recordings `estlab mrclam
--write-recording` writes and prints its time and RMS error.

    python3 tests/bench/mrclam_numpy.py RECORDING.json [PARTICLES] [SEED]

The same algorithm as the reference (the arc, the control noise's alphas, the gate
against the cloud's mean and covariance, weights by the readings' likelihood, low-variance
resampling below half the particles, the weighted mean and covariance at every step);
its own random numbers, so its RMS matches the reference's within sampling error only.
"""

import json
import sys
import time

import numpy as np

GATE = 13.815510557964274


def wrap(a):
    return (a + np.pi) % (2 * np.pi) - np.pi


def belief(p, w):
    mean = np.array([w @ p[:, 0], w @ p[:, 1], np.arctan2(w @ np.sin(p[:, 2]), w @ np.cos(p[:, 2]))])
    d = p - mean
    d[:, 2] = wrap(d[:, 2])
    return mean, (d * w[:, None]).T @ d


def main():
    recording = json.load(open(sys.argv[1]))
    n = int(sys.argv[2]) if len(sys.argv) > 2 else 2000
    rng = np.random.default_rng(int(sys.argv[3]) if len(sys.argv) > 3 else 1)
    run, noise = recording["run"], recording["noise"]
    a1, a2, a3, a4 = noise["alphas"]
    r = np.array(noise["measurement"]).reshape(2, 2).T
    r_inv = np.linalg.inv(r)
    dt = run["dt"]
    steps = run["steps"]
    start = np.array(steps[0]["truth"])
    p = start + 0.01 * rng.standard_normal((n, 3))
    p[:, 2] = wrap(p[:, 2])
    w = np.full(n, 1.0 / n)
    clock = time.perf_counter()
    mean, _ = belief(p, w)
    squared = [(mean[0] - start[0]) ** 2 + (mean[1] - start[1]) ** 2]  # the start counts too
    for step in steps[1:]:
        v, omega = step["control"]["v"], step["control"]["omega"]
        if v != 0.0 or omega != 0.0:
            draws = rng.standard_normal((n, 2))
            vs = v + (a1 * abs(v) + a2 * abs(omega)) * draws[:, 0]
            ws = omega + (a3 * abs(v) + a4 * abs(omega)) * draws[:, 1]
            delta = ws * dt
            small = np.abs(delta) < 1e-3
            safe = np.where(small, 1.0, delta)
            s = np.where(small, 1 - delta**2 / 6, np.sin(safe) / safe)
            c = np.where(small, delta / 2, (1 - np.cos(safe)) / safe)
            cos, sin = np.cos(p[:, 2]), np.sin(p[:, 2])
            p[:, 0] += vs * dt * (cos * s - sin * c)
            p[:, 1] += vs * dt * (sin * s + cos * c)
            p[:, 2] = wrap(p[:, 2] + delta)
        used = 0
        for reading in step["readings"]:
            m = np.array(reading["landmark"])
            z = np.array([reading["range"], reading["bearing"]])
            mean, cov = belief(p, w)
            dx, dy = m[0] - mean[0], m[1] - mean[1]
            q = dx * dx + dy * dy
            h = np.array([[-dx / np.sqrt(q), -dy / np.sqrt(q), 0.0], [dy / q, -dx / q, -1.0]])
            nu = z - np.array([np.sqrt(q), np.arctan2(dy, dx) - mean[2]])
            nu[1] = wrap(nu[1])
            if nu @ np.linalg.solve(h @ cov @ h.T + r, nu) > GATE:
                continue
            dxs, dys = m[0] - p[:, 0], m[1] - p[:, 1]
            nus = np.stack([z[0] - np.hypot(dxs, dys), wrap(z[1] - (np.arctan2(dys, dxs) - p[:, 2]))], axis=1)
            d = np.einsum("ij,jk,ik->i", nus, r_inv, nus)
            w = w * np.exp(-0.5 * (d - d.min()))
            w /= w.sum()
            used += 1
        if used and 1.0 / (w @ w) < n / 2:
            positions = (rng.uniform() + np.arange(n)) / n
            kept = np.minimum(np.searchsorted(np.cumsum(w), positions), n - 1)
            p = p[kept]
            w = np.full(n, 1.0 / n)
        mean, _ = belief(p, w)
        truth = step["truth"]
        squared.append((mean[0] - truth[0]) ** 2 + (mean[1] - truth[1]) ** 2)
    seconds = time.perf_counter() - clock
    rms = float(np.sqrt(np.mean(squared)))
    print(json.dumps({"particles": n, "steps": len(steps), "seconds": seconds, "rms": rms}))


if __name__ == "__main__":
    main()
