"""ihbm: periodic steady states of nonlinear oscillators with fractional-order damping,
by the incremental harmonic balance method.

    import ihbm
    m = ihbm.Model(open("quarter_car.ihbm").read())     # or ihbm.Model.builtin("quarter-car")
    s = m.solve(omega=8.0, harmonics=5, set={"k3": 1e8})
    c = m.sweep(omega_from=1.0, omega_to=30.0, harmonics=5)
    c["columns"]["z1_max_abs"]                           # a NumPy array
    ihbm.plot(c, output="z1")                            # matplotlib

Every analysis returns a dict shaped like the command line's JSON (``ihbm solve
--json``, ``ihbm sweep --json``, ...); sweeps are :class:`Curve` dicts that add
``"columns"``, NumPy arrays named like the CSV's columns plus ``segment``. Errors raise
:class:`IhbmError` with the library's message, naming arguments by their keywords.
Computations run without the GIL; sweeps and fold analyses show progress (tqdm, when
installed) and stop on Ctrl-C, raising :class:`Interrupted` with what was traced.
"""

import json as _json

from . import _native
from ._native import DEFAULT_HARMONICS, IhbmError
from ._plot import plot

__all__ = [
    "Model",
    "Curve",
    "IhbmError",
    "Interrupted",
    "builtin_models",
    "plot",
    "DEFAULT_HARMONICS",
]


class Interrupted(KeyboardInterrupt):
    """Ctrl-C (or another ``KeyboardInterrupt``) stopped a sweep or a fold analysis.
    :attr:`result` is what was traced until then, as the call would have returned it:
    its last segment (or fold curve) ends ``"stopped"``, unless Ctrl-C came as the run
    was finishing and the result is whole."""

    def __init__(self, result):
        super().__init__("interrupted; the result traced so far is in .result")
        self.result = result


class Curve(dict):
    """A sweep's result: the ``sweep`` JSON as a dict, plus ``"columns"``, one NumPy
    array per column: the parameter (``omega``, or the swept parameter's name),
    ``stable`` (1.0, 0.0, or NaN without a verdict), ``{output}_max_abs``,
    ``{output}_mean``, ``{output}_amp1``, ``{output}_rms``, ``{output}_min``,
    ``{output}_max`` for every output, and ``segment`` (integers:
    the index in ``"segments"`` of the piece of the curve each point belongs to)."""

    def to_dataframe(self):
        """The columns as a pandas ``DataFrame`` (pandas must be installed)."""
        try:
            import pandas
        except ImportError as e:
            raise ImportError(
                "Curve.to_dataframe() needs pandas: pip install pandas"
            ) from e
        return pandas.DataFrame(self["columns"])


def builtin_models():
    """The names of the built-in models."""
    return list(_native.builtin_names())


def _pairs(set):
    if set is None:
        return []
    return [(str(k), float(v)) for k, v in dict(set).items()]


def _count(aft_samples):
    """``aft_samples`` as the engine takes it: ``None``, or a whole number >= 1."""
    if aft_samples is None:
        return None
    n = int(aft_samples)
    if n != aft_samples or n < 1:
        raise ValueError(f"invalid aft_samples: {aft_samples!r} (expected a whole number "
                         f"of samples per period, at least 2N + 1)")
    return n


class _Progress:
    """The ``progress`` keyword as a callable ``(points, value)`` for the engine, which
    calls it now and then while it runs: ``None`` is a tqdm bar when tqdm is
    installed (shown only for runs longer than a second) and nothing otherwise,
    ``False`` nothing, a callable is called as it is."""

    def __init__(self, progress, what, parameter):
        self.bar = None
        self.call = None
        if callable(progress):
            self.call = progress
        elif progress is None:
            try:
                from tqdm import tqdm
            except ImportError:
                return
            self.parameter = parameter
            self.bar = tqdm(desc=what, unit=" points", delay=1.0, leave=False)
            self.call = self._update
        elif progress is not False:
            raise TypeError(
                f"progress must be None, False or a callable (points, value), not {progress!r}"
            )

    def _update(self, points, value):
        self.bar.update(points - self.bar.n)
        self.bar.set_postfix_str(f"{self.parameter} = {value:.6g}", refresh=False)

    def close(self):
        if self.bar is not None:
            self.bar.close()


def _finish(result, stopped_by):
    """The result, or, when an exception stopped the run, that exception: an
    :class:`Interrupted` carrying the result for a ``KeyboardInterrupt``."""
    if stopped_by is None:
        return result
    if isinstance(stopped_by, KeyboardInterrupt):
        raise Interrupted(result) from stopped_by
    raise stopped_by


class Model:
    """A model: from the text of one ``oscillator!`` body (a model file's content),
    :meth:`builtin` or :meth:`file`. Parameter values given as ``set={...}`` apply to
    that call only."""

    def __init__(self, text, origin="<text>"):
        self._m = _native.NativeModel(text, origin)

    @classmethod
    def builtin(cls, name):
        """A built-in model (see :func:`builtin_models`)."""
        m = cls.__new__(cls)
        m._m = _native.NativeModel.builtin(name)
        return m

    @classmethod
    def file(cls, path):
        """The model in a model file (``*.ihbm``); errors name the file, line and column."""
        m = cls.__new__(cls)
        m._m = _native.NativeModel.file(str(path))
        return m

    @property
    def name(self):
        """The model's name."""
        return self._m.name

    @property
    def description(self):
        """The model's description (its doc comment)."""
        return self._m.description

    @property
    def dofs(self):
        """The degrees of freedom, in order."""
        return list(self._m.dofs)

    @property
    def outputs(self):
        """The outputs, in order (the names results use)."""
        return list(self._m.outputs)

    @property
    def equations(self):
        """The equations of motion, as text."""
        return list(self._m.equations)

    @property
    def params(self):
        """``{name: (default, doc)}`` in declaration order."""
        return {n: (v, d) for n, v, d in self._m.params}

    def __repr__(self):
        return f"ihbm.Model({self.name!r})"

    def solve(self, omega, harmonics=DEFAULT_HARMONICS, set=None, aft_samples=None,
              sensitivity=None):
        """The periodic solution at ``omega`` (rad/s): the ``solve`` JSON as a dict.
        ``aft_samples``: samples per period of the transform (default: the alias-free
        count; 16 (2N + 1) for a model with ``max``/``min``/``abs``/``sign``).
        ``sensitivity``: parameter names; each output then has ``"sensitivities"``,
        the rates of change of its statistics per unit of each parameter."""
        names = [sensitivity] if isinstance(sensitivity, str) else list(sensitivity or [])
        return _json.loads(self._m.solve(float(omega), int(harmonics), _pairs(set),
                                         _count(aft_samples), [str(n) for n in names]))

    def sweep(self, omega_from, omega_to, harmonics=DEFAULT_HARMONICS, set=None,
              progress=None, aft_samples=None, **settings):
        """The amplitude–frequency curve from ``omega_from`` to ``omega_to`` (rad/s), a
        :class:`Curve`. ``settings`` are the study file's ``sweep`` keys
        (``max_step``, ``stability=False``, ``amplitude_bound="rel:1e3"``, ...);
        ``progress`` as described in the README (``False``: no bar); ``aft_samples`` as
        for :meth:`solve`. Ctrl-C raises :class:`Interrupted` with the curve traced so
        far."""
        bar = _Progress(progress, f"sweep {self.name}", "omega")
        try:
            text, columns, stopped_by = self._m.sweep(
                float(omega_from), float(omega_to), int(harmonics), _pairs(set),
                _json.dumps(settings), bar.call, _count(aft_samples))
        finally:
            bar.close()
        curve = Curve(_json.loads(text))
        curve["columns"] = columns
        return _finish(curve, stopped_by)

    def sweep_param(self, param, value_from, value_to, omega, harmonics=DEFAULT_HARMONICS,
                    set=None, progress=None, aft_samples=None, **settings):
        """The response at fixed ``omega`` as parameter ``param`` goes from
        ``value_from`` to ``value_to``; as :meth:`sweep` (the first column is named
        after the parameter, as in the CSV)."""
        bar = _Progress(progress, f"sweep {param} of {self.name}", str(param))
        try:
            text, columns, stopped_by = self._m.sweep_param(
                str(param), float(value_from), float(value_to), float(omega), int(harmonics),
                _pairs(set), _json.dumps(settings), bar.call, _count(aft_samples))
        finally:
            bar.close()
        curve = Curve(_json.loads(text))
        curve["columns"] = columns
        return _finish(curve, stopped_by)

    def simulate(self, omega, periods=None, dt=None, scheme=None, set=None):
        """Time integration from rest at ``omega``: the ``simulate`` JSON as a dict.
        ``scheme`` is ``"bdf2"`` or ``"gl"`` (default: the command line's)."""
        return _json.loads(self._m.simulate(float(omega), _pairs(set), periods, dt, scheme))

    def backbone(self, to, mode=1, output=None, harmonics=DEFAULT_HARMONICS, set=None,
                 progress=None, aft_samples=None):
        """Nonlinear mode ``mode`` continued until max|output| = ``to``: the
        ``backbone`` JSON as a dict. Progress and Ctrl-C as for :meth:`sweep`
        (:class:`Interrupted` carries the points traced, ``"ended": "stopped"``)."""
        bar = _Progress(progress, f"backbone of {self.name}", "max|x|")
        try:
            text, stopped_by = self._m.backbone(float(to), int(mode), int(harmonics),
                                                _pairs(set), output, bar.call,
                                                _count(aft_samples))
        finally:
            bar.close()
        return _finish(_json.loads(text), stopped_by)

    def folds(self, param, value_from, value_to, omega_from, omega_to,
              harmonics=DEFAULT_HARMONICS, boundary=None, set=None, progress=None,
              **settings):
        """Every fold of the Ω-curve (``boundary="period-doubling"`` or ``"torus"``:
        those points instead) continued as ``param`` goes from ``value_from`` to
        ``value_to``, with the cusps: the ``folds`` JSON as a dict. Progress and
        Ctrl-C as for :meth:`sweep`."""
        bar = _Progress(progress, f"folds of {self.name}", str(param))
        try:
            text, stopped_by = self._m.folds(
                str(param), float(value_from), float(value_to), float(omega_from),
                float(omega_to), int(harmonics), _pairs(set), _json.dumps(settings), boundary,
                bar.call)
        finally:
            bar.close()
        return _finish(_json.loads(text), stopped_by)

    def cycle(self, omega, harmonics=DEFAULT_HARMONICS, set=None):
        """A limit cycle of a model without forcing near the frequency guess ``omega``:
        the ``cycle`` JSON as a dict."""
        return _json.loads(self._m.cycle(float(omega), int(harmonics), _pairs(set)))

    def cycles(self, param, value_from, value_to, omega, harmonics=DEFAULT_HARMONICS,
               set=None, progress=None):
        """The limit cycle near ``omega`` continued in ``param``, with the Hopf point
        where it is born: the ``cycle --param`` JSON as a dict. Progress and Ctrl-C as
        for :meth:`sweep`."""
        bar = _Progress(progress, f"limit cycles of {self.name}", str(param))
        try:
            text, stopped_by = self._m.cycles(str(param), float(value_from), float(value_to),
                                              float(omega), int(harmonics), _pairs(set),
                                              bar.call)
        finally:
            bar.close()
        return _finish(_json.loads(text), stopped_by)
