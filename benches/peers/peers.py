"""The Python side of ihbm's peer comparison (run by benches/peers/run.sh in a venv).

One tool per process: `python peers.py TOOL --harmonics N --from A --to B --points P
--samples S --repeats R` prints one JSON line (or an "error" line) for TOOL in
{harmonicbalance, pyharm-os}. The curve is the Duffing sweep
x'' + c x' + k x + k3 x^3 = F cos(Omega t), m = 1, c = 0.1, k = 1, k3 = 1, F = 0.5
(ihbm's `duffing` defaults).

Matching ihbm: both peers trace the curve by arc-length continuation with a step
measured in the plain Euclidean norm of (Fourier coefficients, Omega). ihbm's step is
adaptive; the peers get a constant step chosen so that they return about the same
number of points P as ihbm did (calibrated on an untimed pilot run: step = arc length
of the pilot curve / (P - 1)). Only the continuation is timed (not imports, not model
set-up, not the pilot that also triggers numba's JIT); the best of R repeats is kept.
"""

import argparse
import contextlib
import io
import json
import logging
import math
import sys
import time
from importlib.metadata import version

import numpy as np

M, C, K, K3, F = 1.0, 0.1, 1.0, 1.0, 0.5


def max_abs(cos, sin, harmonics, dc=0.0, samples=2048):
    """Largest |x(t)| over one period of dc + sum a_k cos k t + b_k sin k t."""
    theta = np.linspace(0.0, 2.0 * np.pi, samples, endpoint=False)
    k = np.arange(1, harmonics + 1)[:, None]
    x = dc + cos @ np.cos(k * theta) + sin @ np.sin(k * theta)
    return float(np.max(np.abs(x)))


def arc_length(params):
    """Polygon length of the curve in the tools' own metric (coefficients and Omega)."""
    return float(np.sum(np.linalg.norm(np.diff(params, axis=0), axis=1)))


def summary(points, harmonics):
    """points: list of (omega, dc, cos[N], sin[N]) -> peaks and the fold estimates."""
    omegas = np.array([p[0] for p in points])
    peak = max(max_abs(p[2], p[3], harmonics, p[1]) for p in points)
    amp1 = max(math.hypot(p[2][0], p[3][0]) for p in points)
    # Folds: where Omega turns back along the curve (to the point spacing).
    d = np.diff(omegas)
    folds = [float(omegas[i + 1]) for i in range(len(d) - 1) if d[i] * d[i + 1] < 0]
    return {"peak_max_abs": peak, "peak_amp1": amp1, "folds": folds,
            "omega_min": float(omegas.min()), "omega_max": float(omegas.max())}


# ---------------------------------------------------------------- harmonicbalance

def harmonicbalance_run(a, step):
    """Milan Rother's `harmonicbalance` (AFT on a Fourier class, scipy.optimize.root,
    secant predictor + hypersphere arc-length corrector): PredictorCorrectorSolver with
    the package's own defaults (method "hybr", use_jac=False), as in its README."""
    from harmonicbalance.fourier import Fourier
    from harmonicbalance.predictorcorrector import PredictorCorrectorSolver

    n = a.harmonics
    force = Fourier(omega=a.omega_from, n=n)
    force[1] = F  # F cos(Omega t)

    def residual(x):
        return M * x.dt().dt() + C * x.dt() + K * x + K3 * x ** 3 - force

    x0 = Fourier(omega=a.omega_from, n=n)
    x0[1] = F / (K - M * a.omega_from ** 2)  # linear response as the first guess
    pcs = PredictorCorrectorSolver(residual, x0, alpha_start=a.omega_from,
                                   alpha_end=a.omega_to, alpha_step=step, method="hybr")
    # Every solve prints its runtime (a @timer decorator): keep it off the terminal.
    with contextlib.redirect_stdout(io.StringIO()):
        start = time.perf_counter()
        sols = pcs.solve()
        seconds = time.perf_counter() - start
    params = np.array([s.params() for s in sols])
    points = [(s.omega, s.coeff_dc, np.asarray(s.coeffs_cos), np.asarray(s.coeffs_sin))
              for s in sols]
    return seconds, params, points, {}


# ---------------------------------------------------------------------- pyharm-os

def pyharm_run(a, step):
    """Safran's pyHarm (pyharm-os): Maestro input dictionary with a one-DOF substructure,
    mass (GOElement dto=2), LinearDamper, LinearSpring, CubicSpring and CosinusForcing
    connectors; FRF analysis with its defaults (tangent predictor, arc-length corrector,
    scipy root 'hybr' with pyHarm's analytic Jacobians) except a constant step size."""
    from pyHarm.Maestro import Maestro

    one = {"connect": {"sub": [0]}, "dirs": [0]}
    data = {
        "export": {"status": False},
        "analysis": {"FRF": {"study": "frf", "puls_inf": a.omega_from, "puls_sup": a.omega_to,
                             "ds0": step, "ds_max": step, "ds_min": step * 1e-4,
                             "stepsizer": "constant", "verbose": False}},
        "system": {"type": "Base", "nh": a.harmonics, "nti": a.samples},
        "substructures": {"sub": {"type": "onlydofs", "ndofs": 1, "nnodes": 1}},
        "connectors": {
            "mass": {"type": "GOElement", "dto": 2, "xo": 1, "k": M, **one},
            "damper": {"type": "LinearDamper", "k": C, **one},
            "spring": {"type": "LinearSpring", "k": K, **one},
            "cubic": {"type": "CubicSpring", "k": K3, **one},
            "force": {"type": "CosinusForcing", "amp": F, **one},
        },
    }
    maestro = Maestro(data)
    frf = maestro.nls["FRF"]
    start = time.perf_counter()
    frf.Solve(None)
    seconds = time.perf_counter() - start
    # Layout of x: [h0, c1, s1, c2, s2, ..., cN, sN, Omega] for the single DOF.
    xs = np.array([s.x for s in frf.SolList if s.flag_accepted])
    n = a.harmonics
    points = [(x[-1], x[0], x[1:2 * n:2], x[2:2 * n + 1:2]) for x in xs]
    return seconds, xs, points, {"rejected": sum(not s.flag_accepted for s in frf.SolList)}


TOOLS = {"harmonicbalance": harmonicbalance_run, "pyharm-os": pyharm_run}
DISTRIBUTIONS = {"harmonicbalance": "harmonicbalance", "pyharm-os": "pyHarm-os"}


def main():
    p = argparse.ArgumentParser()
    p.add_argument("tool", choices=sorted(TOOLS))
    p.add_argument("--harmonics", type=int, default=5)
    p.add_argument("--from", dest="omega_from", type=float, default=0.5)
    p.add_argument("--to", dest="omega_to", type=float, default=3.0)
    p.add_argument("--points", type=int, default=76, help="ihbm's point count to match")
    p.add_argument("--samples", type=int, default=24, help="time samples per period (AFT)")
    p.add_argument("--repeats", type=int, default=3)
    a = p.parse_args()
    run = TOOLS[a.tool]
    logging.disable(logging.CRITICAL)  # pyHarm logs every step; ihbm prints nothing either

    # Untimed pilot (also compiles pyHarm's numba kernels), then calibrate the step.
    step = 0.05
    for _ in range(3):
        _, params, points, _ = run(a, step)
        length = arc_length(params)
        new = length / max(a.points - 1, 1)
        if abs(len(points) - a.points) <= max(2, a.points // 50):
            break
        step = new
    best, points, extra = math.inf, points, {}
    for _ in range(a.repeats):
        seconds, params, points, extra = run(a, step)
        best = min(best, seconds)
    out = {"tool": a.tool, "version": version(DISTRIBUTIONS[a.tool]), "harmonics": a.harmonics,
           "samples": a.samples if a.tool == "pyharm-os" else 4 * a.harmonics + 1,
           "points": len(points), "step": step, "best_seconds_per_curve": best,
           "repeats": a.repeats, **summary(points, a.harmonics), **extra}
    print(json.dumps(out))


if __name__ == "__main__":
    try:
        main()
    except Exception as e:  # reported by run.sh, which skips this peer
        print(json.dumps({"tool": sys.argv[1] if len(sys.argv) > 1 else "?",
                          "error": f"{type(e).__name__}: {e}"}))
        sys.exit(1)
