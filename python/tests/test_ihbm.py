"""The Python package against independent values: closed forms, exact linearity, the
elliptic backbone, time integration, and the command line's own model file."""

import cmath
import math
import pathlib
import threading
import time

import numpy as np
import pytest

import ihbm

ROOT = pathlib.Path(__file__).resolve().parents[2]
MODEL_FILE = ROOT / "examples" / "quarter_car.ihbm"

FRACTIONAL = """
/// m x'' + c x' + h D^p x + k x + k3 x^3 = F cos(Ωt)
pub struct Fractional {
    params { m = 1.0, c = 0.05, h = 0.2, p = 0.5, k = 1.0, k3 = 0.0, F = 0.1 }
    dofs { x }
    equations { m * D(x, 2) + c * D(x, 1) + h * D(x, p) + k * x + k3 * x.powi(3) = F * cos(omega * t); }
}
"""


def fractional_amplitude(w, m=1.0, c=0.05, h=0.2, p=0.5, k=1.0, F=0.1):
    """|X| = F / |k - mΩ² + icΩ + h (iΩ)^p|, the steady-state fractional derivative."""
    z = k - m * w * w + 1j * c * w + h * (1j * w) ** p
    return F / abs(z)


def test_linear_fractional_oscillator_is_its_closed_form():
    m = ihbm.Model(FRACTIONAL, "fractional.ihbm")
    assert m.name == "fractional"
    for w in [0.3, 0.9, 1.0, 1.7, 4.0]:
        s = m.solve(omega=w, harmonics=3)
        assert s["converged"]
        exact = fractional_amplitude(w)
        assert abs(s["outputs"]["x"]["amp1"] - exact) < 1e-12 * exact


def quarter_car_frf(w, m1=240.0, m2=30.0, k1=16000.0, kt=160000.0, c=1000.0, h=1000.0, p=0.5,
                    F=0.01):
    """(Z1, Z2) of the linear quarter car from its 2x2 frequency response (Cramer)."""
    s = complex(0.0, w)
    ks = k1 + c * s + h * s ** p
    a11, a12 = -m1 * w * w + ks, -ks
    a21, a22 = -ks, -m2 * w * w + ks + kt
    det = a11 * a22 - a12 * a21
    rhs2 = kt * F
    return (-a12 * rhs2) / det, (a11 * rhs2) / det


def test_sweep_columns_of_the_linear_quarter_car_are_its_frequency_response():
    car = ihbm.Model.file(MODEL_FILE)
    c = car.sweep(omega_from=1.0, omega_to=100.0, harmonics=5, set={"k3": 0.0}, tol=1e-12)
    cols = c["columns"]
    n = len(c["points"])
    assert n > 20
    assert list(cols)[:5] == ["omega", "stable", "z1_max_abs", "z1_mean", "z1_amp1"]
    assert all(len(v) == n for v in cols.values())
    assert np.all(cols["stable"] == 1.0)  # a damped linear system is stable everywhere
    exact = np.array([abs(quarter_car_frf(w)[0]) for w in cols["omega"]])
    assert np.max(np.abs(cols["z1_amp1"] - exact) / exact) < 1e-9


def test_parameter_sweep_of_a_linear_model_is_proportional():
    car = ihbm.Model.builtin("quarter-car")
    c = car.sweep_param("F", 0.001, 0.05, omega=8.0, harmonics=3, set={"k3": 0.0})
    # the first column is the parameter, named as in the CSV
    assert list(c["columns"])[:2] == ["F", "stable"]
    ratio = c["columns"]["z1_amp1"] / c["columns"]["F"]
    assert c["columns"]["F"][-1] == pytest.approx(0.05, rel=1e-12)
    assert np.max(np.abs(ratio / ratio[0] - 1.0)) < 1e-9
    assert ratio[0] == pytest.approx(abs(quarter_car_frf(8.0, F=1.0)[0]), rel=1e-9)


def test_the_model_file_is_the_built_in_quarter_car():
    a = ihbm.Model.file(MODEL_FILE).solve(omega=8.0, set={"k3": 5e6})
    b = ihbm.Model.builtin("quarter-car").solve(omega=8.0, set={"k3": 5e6})
    assert a == b
    assert ihbm.Model.file(MODEL_FILE).params["kt"] == (160000.0, "tyre stiffness, N/m")


def agm(a, b):
    while abs(a - b) > 1e-15 * a:
        a, b = (a + b) / 2, math.sqrt(a * b)
    return a


def test_duffing_backbone_is_the_elliptic_closed_form():
    # x'' + x + k3 x^3 = 0 with max|x| = a: Ω = π √(1 + k3 a²) / (2 K(m)),
    # m = k3 a² / (2 (1 + k3 a²)), K(m) = π / (2 agm(1, √(1 - m))).
    d = ihbm.Model.builtin("duffing")
    b = d.backbone(to=1.5, harmonics=15, set={"c": 0.0, "k3": 1.0, "F": 0.0})
    assert len(b["points"]) > 5
    for pt in b["points"]:
        a = pt["outputs"]["x"]["max_abs"]
        mm = a * a / (2 * (1 + a * a))
        k = math.pi / (2 * agm(1.0, math.sqrt(1 - mm)))
        exact = math.pi * math.sqrt(1 + a * a) / (2 * k)
        assert abs(pt["omega"] - exact) < 1e-9 * exact
        assert abs(pt["damping"]) < 1e-12


def test_time_integration_agrees_with_harmonic_balance():
    car = ihbm.Model.builtin("quarter-car")
    w = 8.0
    hb = car.solve(omega=w, harmonics=9, set={"k3": 5e6})
    # BDF2 at dt = T/400 over 20 s: second order, the gap is 1e-5 (the Rust suite's
    # claim is 1e-4 for these settings).
    td = car.simulate(omega=w, periods=26, dt=2 * math.pi / w / 400, scheme="bdf2",
                      set={"k3": 5e6})
    for out in ["z1", "y"]:
        a, b = hb["outputs"][out]["max_abs"], td["outputs"][out]["max_abs"]
        assert abs(a - b) < 1e-4 * a


def test_errors_are_exceptions_with_the_librarys_messages(tmp_path):
    with pytest.raises(ihbm.IhbmError, match=r"^s\.ihbm:2:14: `x\.sin\(\)` is not allowed"):
        ihbm.Model("struct S { params { } dofs { x }\n equations { x.sin() = 0.0; } }", "s.ihbm")
    car = ihbm.Model.builtin("quarter-car")
    with pytest.raises(ihbm.IhbmError, match="unknown parameter 'k9'"):
        car.solve(omega=8.0, set={"k9": 1.0})
    with pytest.raises(ihbm.IhbmError, match="unknown field `bogus`"):
        car.sweep(1.0, 30.0, bogus=1)
    with pytest.raises(ihbm.IhbmError, match="unknown model 'nope'"):
        ihbm.Model.builtin("nope")
    bad = tmp_path / "bytes.ihbm"
    bad.write_bytes(b"struct S {\xfe }")
    with pytest.raises(ihbm.IhbmError, match=r"bytes\.ihbm:1:11: not UTF-8"):
        ihbm.Model.file(bad)
    with pytest.raises(ihbm.IhbmError, match="missing.ihbm"):
        ihbm.Model.file(tmp_path / "missing.ihbm")
    with pytest.raises(ihbm.IhbmError, match="invalid scheme"):
        car.simulate(omega=8.0, scheme="rk99")
    # a value outside the domain the model declares, wherever it enters
    with pytest.raises(ihbm.IhbmError, match=r"parameter m1: -240 \(expected a value in \(0, inf\)"):
        car.solve(omega=8.0, set={"m1": -240.0})
    with pytest.raises(ihbm.IhbmError, match=r"end of the range of c: -1 .*\[0, inf\)"):
        car.sweep_param("c", -1.0, 100.0, omega=8.0)
    assert issubclass(ihbm.IhbmError, ValueError)


def test_long_computations_release_the_gil():
    half = ihbm.Model.builtin("half-car")
    done = threading.Event()
    result = {}

    def work():
        result["curve"] = half.sweep(1.0, 100.0, harmonics=15, set={"k3f": 5e6, "k3r": 5e6, "F": 0.025})
        done.set()

    t = threading.Thread(target=work)
    start = time.perf_counter()
    t.start()
    ticks = 0
    while not done.is_set():
        ticks += 1
        time.sleep(0.001)
    t.join()
    elapsed = time.perf_counter() - start
    assert len(result["curve"]["points"]) > 50
    # With the GIL held the main thread would not run until the sweep returned.
    assert elapsed < 0.02 or ticks > 5, (elapsed, ticks)


def test_builtin_models_are_listed():
    names = ihbm.builtin_models()
    assert "quarter-car" in names and "half-car" in names
    assert ihbm.Model.builtin("half-car").outputs == ["z", "theta", "yf", "yr"]


def test_the_papers_fig7_example_runs(tmp_path):
    pytest.importorskip("matplotlib")
    import importlib.util

    path = ROOT / "python" / "examples" / "paper_fig07.py"
    spec = importlib.util.spec_from_file_location("paper_fig07", path)
    example = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(example)
    out = tmp_path / "fig07.png"
    peaks = example.main(str(out))
    assert out.stat().st_size > 10_000
    assert len(peaks) == 6


def test_van_der_pol_cycles_follow_the_small_mu_expansion_and_the_hopf_point():
    vdp = ihbm.Model.builtin("van-der-pol")
    for mu in [0.05, 0.1, 0.2]:
        c = vdp.cycle(omega=1.0, harmonics=15, set={"mu": mu})
        # ω = 1 − μ²/16 + O(μ⁴), amplitude 2 + O(μ²)
        assert abs(c["omega"] - (1 - mu * mu / 16)) < 0.05 * mu ** 4 + 1e-12
        assert abs(c["outputs"]["x"]["max_abs"] - 2.0) < 0.1 * mu * mu
    f = vdp.cycles("mu", 1.0, -0.5, omega=1.0, harmonics=15)
    assert abs(f["hopf"]["value"]) < 1e-10 and abs(f["hopf"]["omega"] - 1.0) < 1e-10


def test_quarter_car_cusps_obey_the_cubic_scaling_law():
    # x -> s x maps (k3, F) to (k3 s², F / s): the least cusp's F times √k3 is one number.
    car = ihbm.Model.builtin("quarter-car")
    least = []
    for k3 in [2e6, 8e6]:
        f = car.folds("F", 0.005, 0.2, omega_from=5.0, omega_to=60.0, set={"k3": k3})
        cusps = [c["value"] for c in f["cusps"] if c["kind"] == "cusp"]
        least.append(min(cusps) * math.sqrt(k3))
    assert abs(least[1] / least[0] - 1) < 1e-7


def test_expression_outputs_and_a_bump_stop_from_python():
    # The quarter car's body acceleration is Ω²|Z1| (the linear closed form: the bump
    # stop never engages here), and a model with a kink reports the samples its
    # transform took, which aft_samples changes.
    text = """
    pub struct Car {
        params { m1 = 240.0, m2 = 30.0, k1 = 16000.0, kt = 160000.0, c = 1000.0, F = 0.01 }
        dofs { z1, z2 }
        let bump = 1e6 * max(0.0, z2 - z1 - 0.05);
        equations {
            m1 * D(z1, 2) + k1 * (z1 - z2) + c * D(z1 - z2, 1) - bump = 0.0;
            m2 * D(z2, 2) + kt * (z2 - F * cos(omega * t)) - k1 * (z1 - z2) - c * D(z1 - z2, 1)
                + bump = 0.0;
        }
        outputs { z1, acc = D(z1, 2), bump }
    }"""
    car = ihbm.Model(text)
    w = 9.0
    k = 16000.0 + 1000.0j * w
    a11, a12, a22 = k - 240.0 * w * w, -k, k + 160000.0 - 30.0 * w * w
    z1 = -a12 * 160000.0 * 0.01 / (a11 * a22 - a12 * a12)
    r = car.solve(w, harmonics=3)
    assert abs(r["outputs"]["acc"]["amp1"] - w * w * abs(z1)) < 1e-9 * w * w * abs(z1)
    assert r["outputs"]["bump"]["max_abs"] == 0.0
    assert r["aft_samples"] == 120  # 16 (2N + 1) = 112 at N = 3, up to a fast FFT size
    assert car.solve(w, harmonics=3, aft_samples=64)["aft_samples"] == 64
    with pytest.raises(ValueError, match="invalid aft_samples: 5"):
        car.solve(w, harmonics=3, aft_samples=5)
    with pytest.raises(ValueError, match="invalid aft_samples: 2.5"):
        car.sweep(1.0, 2.0, aft_samples=2.5)
    ride = ihbm.Model.builtin("quarter-car-ride")
    assert {"acc", "travel", "tyre", "air"} <= set(ride.outputs)


def test_solve_sensitivities_are_the_closed_forms_derivative():
    # The linear quarter car's body amplitude is linear in the road amplitude F:
    # d amp1 / dF = amp1 / F exactly; an unknown parameter names itself.
    car = ihbm.Model.builtin("quarter-car")
    r = car.solve(8.0, set={"k3": 0.0}, sensitivity=["F", "p"])
    z1 = r["outputs"]["z1"]
    assert list(z1["sensitivities"]) == ["F", "p"]
    assert abs(z1["sensitivities"]["F"]["amp1"] - z1["amp1"] / 0.01) < 1e-9 * z1["amp1"] / 0.01
    assert car.solve(8.0, sensitivity="c")["outputs"]["y"]["sensitivities"]["c"]["rms"] < 0
    with pytest.raises(ValueError, match="unknown parameter"):
        car.solve(8.0, sensitivity=["q"])
