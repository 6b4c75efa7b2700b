"""Table and JSON of the peer comparison (standard library only; run by run.sh).

`python3 report.py OUT.json LINES...`: each LINES file holds JSON lines from
peer_duffing (ihbm) or peers.py (a Python peer), or one {"tool", "error"} line.
Prints the timing table and the curve check, writes OUT.json for the book.
"""

import json
import math
import sys

M, C, K, K3, F = 1.0, 0.1, 1.0, 1.0, 0.5
TOLERANCE = 0.03  # peak amplitudes must agree with ihbm within 3 %


def one_harmonic_peak():
    """Peak of a on [(k - m W^2) a + 3/4 k3 a^3]^2 + (c W a)^2 = F^2, in closed form.

    With A = a^2 and G(A, W) = [(k - m W^2) + 3/4 k3 A]^2 A + c^2 W^2 A - F^2, the top
    of the curve has dG/dW = 0 at fixed A, i.e. k - m W^2 + 3/4 k3 A = c^2 / (2m).
    Substituting W^2 = (k + 3/4 k3 A - c^2/(2m)) / m into G = 0 leaves a quadratic in A.
    """
    q = C * C / (2 * M)
    qa = C * C * 0.75 * K3 / M
    qb = q * q + C * C * (K - q) / M
    A = (-qb + math.sqrt(qb * qb + 4 * qa * F * F)) / (2 * qa)
    omega = math.sqrt((K + 0.75 * K3 * A - q) / M)
    return math.sqrt(A), omega


def read(paths):
    rows = []
    for path in paths:
        with open(path) as f:
            for line in f:
                line = line.strip()
                if line.startswith("{"):
                    rows.append(json.loads(line))
    return rows


def fmt_time(s):
    return f"{s * 1e3:10.3f} ms" if s >= 1e-3 else f"{s * 1e6:10.1f} us"


def table(columns, rows):
    """Print rows under (title, width) columns; a negative width aligns left."""
    def line(cells):
        return " ".join(f"{str(c):<{-w}}" if w < 0 else f"{str(c):>{w}}"
                        for c, (_, w) in zip(cells, columns))
    head = line([t for t, _ in columns])
    print(head)
    print("-" * len(head))
    for cells in rows:
        print(line(cells))


def main():
    out_path, paths = sys.argv[1], sys.argv[2:]
    rows = read(paths)
    ok = [r for r in rows if "error" not in r]
    failed = [r for r in rows if "error" in r]
    ihbm = next((r for r in ok if r["tool"] == "ihbm"), None)
    if ihbm is None:
        sys.exit("report: no result from ihbm")
    ref_a, ref_omega = one_harmonic_peak()

    for r in ok:
        # Like with like: the best of the repeats for every tool (ihbm also has its median).
        r["best_seconds_per_point"] = r["best_seconds_per_curve"] / max(r["points"], 1)
        r["ratio_to_ihbm"] = r["best_seconds_per_curve"] / ihbm["best_seconds_per_curve"]
        dev = abs(r["peak_max_abs"] / ihbm["peak_max_abs"] - 1)
        r["peak_deviation_from_ihbm"] = dev
        r["same_curve"] = dev <= TOLERANCE
        r["upper_fold"] = max(r["folds"]) if r["folds"] else None

    print()
    print("Duffing x'' + 0.1 x' + x + x^3 = 0.5 cos(W t), "
          f"W {ihbm['from']} -> {ihbm['to']}, N = {ihbm['harmonics']}")
    print()
    def timing(r):
        ratio = f"{r['ratio_to_ihbm']:13.1f}x" if r["same_curve"] else "  n/a (curve)"
        median = fmt_time(r["seconds_per_curve"]) if "seconds_per_curve" in r else "-"
        return [r["tool"], r["version"], r["harmonics"], r["points"],
                fmt_time(r["best_seconds_per_curve"]), median,
                fmt_time(r["best_seconds_per_point"]), ratio]

    table([("tool", -16), ("version", -8), ("N", 3), ("points", 6), ("time/curve", 13),
           ("(median)", 13), ("time/point", 13), ("ratio to ihbm", 14)], map(timing, ok))
    for r in failed:
        print(f"{r['tool']:<16} skipped: {r['error']}")

    print()
    print("Same curve? peak of max|x(t)| and of the first-harmonic amplitude over the points,")
    print("upper fold (where the curve turns back; ihbm locates it exactly, the peers to")
    print(f"their point spacing). One-harmonic closed form: peak a1 = {ref_a:.4f} at W = {ref_omega:.4f}.")
    print()
    def check(r):
        return [r["tool"], f"{r['peak_max_abs']:.4f}", f"{r['peak_amp1']:.4f}",
                f"{100 * (r['peak_amp1'] / ref_a - 1):+.2f}%",
                f"{r['upper_fold']:.4f}" if r["upper_fold"] else "-",
                f"{100 * (r['peak_max_abs'] / ihbm['peak_max_abs'] - 1):+.2f}%"]

    table([("tool", -16), ("peak max|x|", 12), ("peak a1", 9), ("a1 vs N=1 ref", 14),
           ("upper fold W", 13), ("vs ihbm", 8)], map(check, ok))
    bad = [r["tool"] for r in ok if not r["same_curve"]]
    if bad:
        print(f"\nWARNING: {', '.join(bad)} computed a different curve (peak off by more than "
              f"{TOLERANCE:.0%}); their speed ratio is not meaningful.")

    notes = [
        "time/curve and the ratio: best of the repeats for every tool (ihbm's median "
        "in the (median) column: on a shared machine the best is the least disturbed).",
        "Tolerances: ihbm Newton to 1e-10 on the scaled step; both peers scipy.optimize.root "
        "'hybr' (xtol 1.5e-8 relative), harmonicbalance with its default finite-difference "
        "Jacobian, pyHarm with its analytic one.",
        "Peers use a constant arc-length step calibrated to ihbm's point count; "
        "ihbm's step is adaptive (its default settings).",
        "ihbm also locates folds exactly and computes jump points; 'ihbm+stability' adds "
        "Hill stability of every point, which the peers do not compute.",
    ]
    print()
    for n in notes:
        print("note:", n)
    result = {"model": "duffing", "params": {"m": M, "c": C, "k": K, "k3": K3, "F": F},
              "one_harmonic_peak": {"a1": ref_a, "omega": ref_omega},
              "results": ok, "skipped": failed, "notes": notes}
    with open(out_path, "w") as f:
        json.dump(result, f, indent=2)
    print(f"\nresults written to {out_path}")


if __name__ == "__main__":
    main()
