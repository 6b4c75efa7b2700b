"""The reference paper's Fig. 7 from a model file: the quarter car's body displacement
and suspension deflection against Ω for fractional orders p = 0, 0.2, ..., 1.

    pip install "./python[examples]"
    python python/examples/paper_fig07.py            # writes fig07.png

Same curves as `ihbm run` draws in out/fig07_order.svg; the notebook
quarter_car.ipynb draws them too and goes on to a design question.
"""

import pathlib
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402

import ihbm  # noqa: E402

HERE = pathlib.Path(__file__).resolve().parent
MODEL = HERE.parents[1] / "examples" / "quarter_car.ihbm"


def main(out="fig07.png"):
    car = ihbm.Model.file(MODEL)
    fig, (top, bottom) = plt.subplots(2, 1, figsize=(7, 7), sharex=True)
    peaks = []
    for p in [0.0, 0.2, 0.4, 0.6, 0.8, 1.0]:
        curve = car.sweep(omega_from=1.0, omega_to=100.0, harmonics=5, set={"p": p})
        # stable branches solid, unstable dashed, folds and jumps marked
        ihbm.plot(curve, ax=top, output="z1", label=f"p = {p}")
        ihbm.plot(curve, ax=bottom, output="y")
        peaks.append(curve["columns"]["z1_max_abs"].max())
    top.set_ylabel("body displacement max|z1| (m)")
    bottom.set_ylabel("suspension deflection max|y| (m)")
    bottom.set_xlabel("forcing frequency Ω (rad/s)")
    top.legend()
    fig.suptitle("Fig. 7: fractional order p (quarter car, Table 1)")
    fig.savefig(out, dpi=120)
    # The paper's claim: the lower the order, the higher the resonance peak.
    assert all(a > b for a, b in zip(peaks, peaks[1:])), peaks
    return peaks


if __name__ == "__main__":
    main(*sys.argv[1:])
