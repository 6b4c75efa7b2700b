"""The Python front end: type stubs against the module, NumPy columns against the JSON
points, the plot helper, progress and Ctrl-C, and errors naming Python keywords.
Numbers are checked against closed forms (an undamped or a fractional linear
oscillator), never against values copied from ihbm's own output."""

import _thread
import ast
import inspect
import math
import pathlib
import subprocess
import sys
import threading
import time

import numpy as np
import pytest

import ihbm
import ihbm._native

PACKAGE = pathlib.Path(ihbm.__file__).resolve().parent

# The Duffing oscillator x'' + c x' + k x + k3 x^3 = F cos(Ωt) (the built-in model).
DUFFING_SOFT = {"m": 1.0, "c": 0.05, "k": 1.0, "k3": 1.0, "F": 0.2}


# --- stubs -----------------------------------------------------------------------

def stub_tree(name):
    return ast.parse((PACKAGE / name).read_text())


def stub_functions(body):
    """{name: ast.FunctionDef} of a stub's (module or class) body."""
    return {n.name: n for n in body if isinstance(n, ast.FunctionDef)}


def stub_params(fn):
    """Parameter (name, kind) pairs of a stub function, as inspect names the kinds."""
    a = fn.args
    out = [(x.arg, "POSITIONAL_ONLY") for x in a.posonlyargs]
    out += [(x.arg, "POSITIONAL_OR_KEYWORD") for x in a.args]
    if a.vararg:
        out.append((a.vararg.arg, "VAR_POSITIONAL"))
    out += [(x.arg, "KEYWORD_ONLY") for x in a.kwonlyargs]
    if a.kwarg:
        out.append((a.kwarg.arg, "VAR_KEYWORD"))
    return out


def runtime_params(obj, drop_first):
    ps = list(inspect.signature(obj).parameters.values())
    if drop_first:
        ps = ps[1:]
    return [(p.name, p.kind.name) for p in ps]


def stub_names(tree):
    names = set()
    for n in tree.body:
        if isinstance(n, (ast.FunctionDef, ast.ClassDef)):
            names.add(n.name)
        elif isinstance(n, ast.ImportFrom):
            names.update(a.asname or a.name for a in n.names)
        elif isinstance(n, ast.AnnAssign):
            names.add(n.target.id)
        elif isinstance(n, ast.Assign):
            names.update(t.id for t in n.targets if isinstance(t, ast.Name))
    return names


def check_class(cls, node):
    """Every public attribute of `cls` has a stub in `node`, with the runtime's
    parameters (names, order, kinds); and every stub exists at runtime."""
    stubs = stub_functions(node.body)
    public = [n for n in vars(cls) if not n.startswith("_") or n == "__init__"]
    for name in public:
        assert name in stubs, f"{cls.__name__}.{name} has no stub"
        attr = inspect.getattr_static(cls, name)
        if isinstance(attr, property):
            continue
        if isinstance(attr, (classmethod, staticmethod)):
            fn, drop = getattr(cls, name), False
            stub = stub_params(stubs[name])
            if isinstance(attr, classmethod):
                stub = stub[1:]
        else:
            fn, drop = getattr(cls, name), True
            stub = stub_params(stubs[name])[1:]
        assert stub == runtime_params(fn, drop), f"{cls.__name__}.{name}"
    for name in stubs:
        assert name in public or name.startswith("__"), f"stub of {cls.__name__}.{name} has no runtime attribute"


def test_every_public_name_has_a_stub_with_its_keywords():
    tree = stub_tree("__init__.pyi")
    assert set(ihbm.__all__) <= stub_names(tree)
    assert {n for n in vars(ihbm) if not n.startswith("_")} == set(ihbm.__all__)
    functions = stub_functions(tree.body)
    for name in ["builtin_models", "plot"]:
        assert stub_params(functions[name]) == runtime_params(getattr(ihbm, name), False), name
    classes = {n.name: n for n in tree.body if isinstance(n, ast.ClassDef)}
    for name in ["Model", "Curve", "Interrupted"]:
        check_class(getattr(ihbm, name), classes[name])
    # the stub's __all__ is the module's
    (stub_all,) = [n for n in tree.body if isinstance(n, ast.Assign) and n.targets[0].id == "__all__"]
    assert ast.literal_eval(stub_all.value) == ihbm.__all__


def test_the_native_module_has_stubs_too_and_the_package_is_typed():
    assert (PACKAGE / "py.typed").is_file()
    tree = stub_tree("_native.pyi")
    public = {n for n in vars(ihbm._native) if not n.startswith("_")}
    assert public <= stub_names(tree)
    functions = stub_functions(tree.body)
    assert stub_params(functions["builtin_names"]) == runtime_params(ihbm._native.builtin_names, False)
    (node,) = [n for n in tree.body if isinstance(n, ast.ClassDef) and n.name == "NativeModel"]
    stubs = stub_functions(node.body)
    for name in vars(ihbm._native.NativeModel):
        if name.startswith("_"):
            continue
        assert name in stubs, f"NativeModel.{name} has no stub"
        attr = getattr(ihbm._native.NativeModel, name)
        if callable(attr) and not isinstance(inspect.getattr_static(ihbm._native.NativeModel, name), staticmethod):
            assert stub_params(stubs[name])[1:] == runtime_params(attr, True), name


def test_mypy_stubtest_finds_the_stubs_consistent_with_the_module(tmp_path):
    # mypy's own check: every runtime name, argument and default against the stubs.
    pytest.importorskip("mypy.stubtest")
    run = subprocess.run([sys.executable, "-m", "mypy.stubtest", "ihbm"], cwd=tmp_path,
                         capture_output=True, text=True)
    assert run.returncode == 0, run.stdout + run.stderr


# --- columns ---------------------------------------------------------------------

def duffing_curve(**kw):
    d = ihbm.Model.builtin("duffing")
    return d.sweep(omega_from=0.5, omega_to=2.5, harmonics=3, set=DUFFING_SOFT, progress=False, **kw)


def test_columns_are_the_json_points_and_segment_indexes_the_segments():
    c = duffing_curve()
    cols = c["columns"]
    pts = c["points"]
    assert isinstance(c, ihbm.Curve) and isinstance(c, dict)
    stats = ["max_abs", "mean", "amp1", "rms", "min", "max"]
    assert list(cols) == ["omega", "stable"] + [f"x_{s}" for s in stats] + ["segment"]
    assert cols["omega"].dtype == np.float64 and cols["segment"].dtype == np.int64
    assert np.array_equal(cols["omega"], [p["omega"] for p in pts])
    verdict = {True: 1.0, False: 0.0, None: np.nan}
    assert np.array_equal(cols["stable"], [verdict[p["stable"]] for p in pts], equal_nan=True)
    for stat in stats:
        assert np.array_equal(cols[f"x_{stat}"], [p["outputs"]["x"][stat] for p in pts])
    # Each point lies in the range of the segment its index names.
    segs = c["segments"]
    for w, s in zip(cols["omega"], cols["segment"]):
        lo, hi = sorted([segs[s]["from_omega"], segs[s]["to_omega"]])
        assert lo - 1e-12 <= w <= hi + 1e-12
    # the arrays are NumPy's own and writable
    cols["omega"][0] = 0.0


def test_a_runaway_curves_segments_split_at_the_undamped_resonance():
    # x'' + x = F cos(Ωt): |x| = F / |1 - Ω²| grows without bound at Ω = 1, so the sweep
    # ends at the amplitude bound and starts again from the other end.
    d = ihbm.Model.builtin("duffing")
    c = d.sweep(0.5, 1.5, harmonics=1, set={"c": 0.0, "k3": 0.0, "F": 0.1}, progress=False)
    cols = c["columns"]
    assert len(c["segments"]) == 2 and c["segments"][0]["ended"] == "amplitude bound"
    below, above = cols["segment"] == 0, cols["segment"] == 1
    assert below.any() and above.any() and np.all(below | above)
    assert np.all(cols["omega"][below] < 1.0) and np.all(cols["omega"][above] > 1.0)
    exact = 0.1 / np.abs(1.0 - cols["omega"] ** 2)
    assert np.max(np.abs(cols["x_amp1"] - exact) / exact) < 1e-9


def test_to_dataframe_with_and_without_pandas(monkeypatch):
    c = duffing_curve(stability=False)
    monkeypatch.setitem(sys.modules, "pandas", None)  # as if pandas were not installed
    with pytest.raises(ImportError, match="pandas"):
        c.to_dataframe()
    monkeypatch.undo()
    pd = pytest.importorskip("pandas")
    df = c.to_dataframe()
    assert isinstance(df, pd.DataFrame)
    assert list(df.columns) == list(c["columns"])
    assert np.array_equal(df["x_max_abs"].to_numpy(), c["columns"]["x_max_abs"])


# --- the plot helper -------------------------------------------------------------

@pytest.fixture
def plt():
    mpl = pytest.importorskip("matplotlib")
    mpl.use("Agg")
    import matplotlib.pyplot as plt

    yield plt
    plt.close("all")


def lines(ax, gid):
    return [ln for ln in ax.get_lines() if ln.get_gid() == gid]


def test_plot_draws_one_line_per_segment_and_verdict_with_folds_and_jumps(plt):
    c = duffing_curve()
    ax = ihbm.plot(c)
    pts = c["points"]
    seg = c["columns"]["segment"]
    expected = {(int(s), p["stable"]) for s, p in zip(seg, pts)}
    curve = lines(ax, "curve")
    assert len(curve) == len(expected)
    styles = sorted(ln.get_linestyle() for ln in curve)
    assert styles == sorted({True: "-", False: "--", None: ":"}[v] for _, v in expected)
    # a hardening Duffing oscillator: two folds, a jump up and a jump down
    (folds,) = lines(ax, "folds")
    assert len(folds.get_xdata()) == len(c["folds"]) == 2
    assert np.array_equal(folds.get_xdata(), [f["omega"] for f in c["folds"]])
    jumps = lines(ax, "jump")
    assert len(jumps) == len(c["jumps"]) == 2
    assert sorted(j.get_marker() for j in jumps) == ["^", "v"]
    # the resonance peak, where the sweep JSON places it, above every point
    (peaks,) = lines(ax, "peaks")
    assert len(c["peaks"]) >= 1
    assert np.array_equal(peaks.get_xdata(), [k["omega"] for k in c["peaks"]])
    assert np.array_equal(peaks.get_ydata(), [k["value"] for k in c["peaks"]])
    assert max(peaks.get_ydata()) >= max(c["columns"]["x_max_abs"])
    assert ax.get_ylabel() == "max |x|"


def test_plot_never_joins_the_pieces_of_a_runaway_curve(plt):
    d = ihbm.Model.builtin("duffing")
    c = d.sweep(0.5, 1.5, harmonics=1, set={"c": 0.0, "k3": 0.0, "F": 0.1}, progress=False)
    fig, ax = plt.subplots()
    assert ihbm.plot(c, ax=ax, output="x", label="undamped") is ax
    for ln in lines(ax, "curve"):
        x = np.asarray(ln.get_xdata())
        y = np.asarray(ln.get_ydata())
        drawn = x[np.isfinite(y)]
        assert np.all(drawn < 1.0) or np.all(drawn > 1.0)
    assert {ln.get_color() for ln in lines(ax, "curve")} == {lines(ax, "curve")[0].get_color()}
    with pytest.raises(ValueError, match="unknown output 'z'"):
        ihbm.plot(c, ax=ax, output="z")


def test_plot_draws_fold_curves_with_cusps_and_a_backbone(plt):
    d = ihbm.Model.builtin("duffing")
    f = d.folds("F", 0.01, 0.3, omega_from=0.5, omega_to=2.5, harmonics=3,
                set={"c": 0.05, "k3": 1.0}, progress=False)
    ax = ihbm.plot(f)
    assert len(lines(ax, "curve")) == len(f["curves"]) >= 1
    cusps = lines(ax, "cusps")
    assert len(cusps) == (1 if f["cusps"] else 0)
    if f["cusps"]:
        assert len(cusps[0].get_xdata()) == len(f["cusps"])
    assert ax.get_ylabel() == "F"
    b = d.backbone(to=1.0, harmonics=5, set={"c": 0.0, "k3": 1.0, "F": 0.0})
    ax = ihbm.plot(b)
    drawn = sum(np.isfinite(ln.get_ydata()).sum() for ln in lines(ax, "curve"))
    assert drawn >= len(b["points"])
    with pytest.raises(ValueError, match="none of them"):
        ihbm.plot({"model": "x"})


# --- progress and Ctrl-C ---------------------------------------------------------

def fractional_amplitude(w, m=1.0, c=0.05, h=0.2, p=0.5, k=1.0, F=0.1):
    """|X| = F / |k - mΩ² + icΩ + h (iΩ)^p| of the linear fractional oscillator."""
    return F / abs(k - m * w * w + 1j * c * w + h * (1j * w) ** p)


FRACTIONAL = """
/// m x'' + c x' + h D^p x + k x = F cos(Ωt)
pub struct Fractional {
    params { m = 1.0, c = 0.05, h = 0.2, p = 0.5, k = 1.0, F = 0.1 }
    dofs { x }
    equations { m * D(x, 2) + c * D(x, 1) + h * D(x, p) + k * x = F * cos(omega * t); }
}
"""


def test_progress_is_called_with_the_points_so_far():
    calls = []
    m = ihbm.Model(FRACTIONAL)
    c = m.sweep(0.2, 3.0, harmonics=3, max_step=0.002,
                progress=lambda n, w: calls.append((n, w)))
    assert calls, "the first event is always reported"
    counts = [n for n, _ in calls]
    assert counts == sorted(counts) and counts[-1] <= len(c["points"])
    with pytest.raises(TypeError, match="progress"):
        m.sweep(0.2, 3.0, progress="yes")


def test_an_exception_in_the_progress_callback_stops_the_sweep():
    def fail(n, w):
        raise RuntimeError("stop here")

    with pytest.raises(RuntimeError, match="stop here"):
        ihbm.Model(FRACTIONAL).sweep(0.2, 3.0, harmonics=3, progress=fail)


def test_ctrl_c_from_another_thread_stops_the_sweep_keeping_its_points():
    m = ihbm.Model(FRACTIONAL)
    started = threading.Event()

    def progress(n, w):
        started.set()

    def press_ctrl_c():
        # Once the sweep runs (its first progress call), as a SIGINT would.
        started.wait(timeout=60)
        _thread.interrupt_main()

    presser = threading.Thread(target=press_ctrl_c)
    presser.start()
    # A sweep of many small steps, which takes far longer than the interrupt.
    with pytest.raises(ihbm.Interrupted) as info:
        m.sweep(0.2, 3.0, harmonics=3, max_step=1e-5, min_step=1e-7, initial_step=1e-6,
                max_steps=10**7, progress=progress)
    presser.join()
    assert isinstance(info.value, KeyboardInterrupt)
    c = info.value.result
    assert isinstance(c, ihbm.Curve)
    assert c["segments"][-1]["ended"] == "stopped"
    cols = c["columns"]
    assert 0 < len(c["points"]) == len(cols["omega"])
    assert cols["omega"][-1] < 3.0
    exact = np.array([fractional_amplitude(w) for w in cols["omega"]])
    assert np.max(np.abs(cols["x_amp1"] - exact) / exact) < 1e-9


# --- errors name Python keywords -------------------------------------------------

def test_errors_name_the_python_keywords_not_command_line_flags():
    car = ihbm.Model.builtin("quarter-car")
    cases = [
        (lambda: car.sweep(omega_from=-1.0, omega_to=30.0), r"^invalid omega_from: -1 \("),
        (lambda: car.sweep(omega_from=1.0, omega_to=math.inf), r"^invalid omega_to: inf \("),
        (lambda: car.sweep_param("F", 0.01, 0.02, omega=0.0), r"^invalid omega: 0 \("),
        (lambda: car.folds("F", 0.01, 0.1, omega_from=5.0, omega_to=-60.0),
         r"^invalid omega_to: -60 \("),
        (lambda: car.sweep(1.0, 30.0, max_step=-0.1), r"^invalid max_step: -0.1 \("),
        (lambda: car.sweep(1.0, 30.0, min_step=0.5, max_step=0.1),
         r"^invalid min_step: 0.5 \(expected at most max_step \(0.1\)\)$"),
        (lambda: car.sweep_param("F", 0.01, 0.02, omega=8.0, max_steps=0),
         r"^invalid max_steps: 0 \(expected at least 1\)$"),
    ]
    for call, message in cases:
        with pytest.raises(ihbm.IhbmError, match=message) as info:
            call()
        assert "--" not in str(info.value)


# --- the README ------------------------------------------------------------------

def test_the_readmes_first_curves_run(tmp_path, monkeypatch, plt):
    import re

    root = pathlib.Path(__file__).resolve().parents[2]
    blocks = re.findall(r"```python\n(.*?)```", (root / "python" / "README.md").read_text(), re.S)
    # the Ctrl-C example is a deliberately long sweep
    runnable = [b for b in blocks if "Interrupted" not in b]
    assert len(runnable) == 2
    (tmp_path / "examples").symlink_to(root / "examples")
    monkeypatch.chdir(tmp_path)
    ns = {}
    for b in runnable:
        exec(b, ns)
    assert (tmp_path / "quarter_car.png").stat().st_size > 10_000
    assert isinstance(ns["curve"], ihbm.Curve)


def test_ctrl_c_stops_a_backbone_keeping_its_points_on_the_closed_form():
    # x'' + x + x^3 = 0 with max|x| = a: Ω = π √(1 + a²) / (2 K(m)),
    # m = a² / (2 (1 + a²)), K(m) = π / (2 agm(1, √(1 - m))).
    def agm(a, b):
        while abs(a - b) > 1e-15 * a:
            a, b = (a + b) / 2, math.sqrt(a * b)
        return a

    started = threading.Event()

    def progress(n, a):
        # slow enough for the interrupt to land before the backbone is done
        started.set()
        time.sleep(0.5)

    def press_ctrl_c():
        started.wait(timeout=60)
        _thread.interrupt_main()

    presser = threading.Thread(target=press_ctrl_c)
    presser.start()
    d = ihbm.Model.builtin("duffing")
    with pytest.raises(ihbm.Interrupted) as info:
        d.backbone(to=50.0, harmonics=31, set={"c": 0.0, "k3": 1.0, "F": 0.0},
                   progress=progress)
    presser.join()
    b = info.value.result
    assert b["ended"] == "stopped"
    assert 0 < len(b["points"])
    for pt in b["points"]:
        a = pt["outputs"]["x"]["max_abs"]
        assert a < 50.0
        mm = a * a / (2 * (1 + a * a))
        k = math.pi / (2 * agm(1.0, math.sqrt(1 - mm)))
        exact = math.pi * math.sqrt(1 + a * a) / (2 * k)
        assert abs(pt["omega"] - exact) < 1e-9 * exact


def test_ctrl_c_interrupts_a_long_time_integration_within_a_second():
    # 20 000 forcing periods take seconds; the call answers the interrupt at once
    # (the integration is left to finish on its own thread, its result dropped).
    m = ihbm.Model.builtin("fractional-duffing")

    def press_ctrl_c():
        time.sleep(0.3)
        _thread.interrupt_main()

    presser = threading.Thread(target=press_ctrl_c)
    start = time.monotonic()
    presser.start()
    with pytest.raises(KeyboardInterrupt):
        m.simulate(1.0, periods=20000)
    waited = time.monotonic() - start
    presser.join()
    assert waited < 2.0, f"answered after {waited:.2f} s"
