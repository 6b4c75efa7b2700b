"""ihbm: periodic steady states of nonlinear oscillators with fractional-order damping,
by the incremental harmonic balance method.

    import ihbm
    m = ihbm.Model(open("quarter_car.ihbm").read())     # or ihbm.Model.builtin("quarter-car")
    s = m.solve(omega=8.0, harmonics=5, set={"k3": 1e8})
    c = m.sweep(omega_from=1.0, omega_to=30.0, harmonics=5)
    c["columns"]["z1_max_abs"]                           # a NumPy array

Every analysis returns a dict shaped like the command line's JSON (``ihbm solve
--json``, ``ihbm sweep --json``, ...); sweeps add ``"columns"``, NumPy arrays named
like the CSV's columns. Errors raise :class:`IhbmError` with the library's message.
Computations run without the GIL.
"""

import json

import numpy as np

from ._native import DEFAULT_HARMONICS, IhbmError, NativeModel, builtin_names

__all__ = ["Model", "IhbmError", "builtin_models", "DEFAULT_HARMONICS"]


def builtin_models():
    """The names of the built-in models."""
    return list(builtin_names())


def _pairs(set):
    if set is None:
        return []
    return [(str(k), float(v)) for k, v in dict(set).items()]


def _columns(csv):
    """NumPy columns from the curve's CSV, named as its header names them (``omega``,
    or the parameter for a parameter sweep, then ``stable`` as 1.0, 0.0 or NaN where no
    verdict exists, then ``{output}_{statistic}``)."""
    lines = csv.splitlines()
    names = lines[0].split(",")
    rows = [line.split(",") for line in lines[1:]]
    stable = {"true": 1.0, "false": 0.0, "": np.nan}
    cols = {}
    for j, name in enumerate(names):
        if name == "stable":
            cols[name] = np.array([stable[r[j]] for r in rows], dtype=float)
        else:
            cols[name] = np.array([float(r[j]) for r in rows], dtype=float)
    return cols


class Model:
    """A model: from the text of one ``oscillator!`` body (a model file's content),
    :meth:`builtin` or :meth:`file`. Parameter values given as ``set={...}`` apply to
    that call only."""

    def __init__(self, text, origin="<text>"):
        self._m = NativeModel(text, origin)

    @classmethod
    def builtin(cls, name):
        """A built-in model (see :func:`builtin_models`)."""
        m = cls.__new__(cls)
        m._m = NativeModel.builtin(name)
        return m

    @classmethod
    def file(cls, path):
        """The model in a model file (``*.ihbm``); errors name the file, line and column."""
        m = cls.__new__(cls)
        m._m = NativeModel.file(str(path))
        return m

    @property
    def name(self):
        return self._m.name

    @property
    def description(self):
        return self._m.description

    @property
    def dofs(self):
        return list(self._m.dofs)

    @property
    def outputs(self):
        return list(self._m.outputs)

    @property
    def equations(self):
        return list(self._m.equations)

    @property
    def params(self):
        """``{name: (default, doc)}`` in declaration order."""
        return {n: (v, d) for n, v, d in self._m.params}

    def __repr__(self):
        return f"ihbm.Model({self.name!r})"

    def solve(self, omega, harmonics=DEFAULT_HARMONICS, set=None):
        """The periodic solution at ``omega`` (rad/s): the ``solve`` JSON as a dict."""
        return json.loads(self._m.solve(float(omega), int(harmonics), _pairs(set)))

    def sweep(self, omega_from, omega_to, harmonics=DEFAULT_HARMONICS, set=None, **settings):
        """The amplitude–frequency curve from ``omega_from`` to ``omega_to`` (rad/s):
        the ``sweep`` JSON plus ``"columns"``. ``settings`` are the study file's
        ``sweep`` keys (``max_step``, ``stability=False``, ``amplitude_bound="rel:1e3"``, ...)."""
        text, csv = self._m.sweep(float(omega_from), float(omega_to), int(harmonics),
                                  _pairs(set), json.dumps(settings))
        curve = json.loads(text)
        curve["columns"] = _columns(csv)
        return curve

    def sweep_param(self, param, value_from, value_to, omega, harmonics=DEFAULT_HARMONICS,
                    set=None, **settings):
        """The response at fixed ``omega`` as parameter ``param`` goes from
        ``value_from`` to ``value_to``; as :meth:`sweep` (the first column is named
        after the parameter, as in the CSV)."""
        text, csv = self._m.sweep_param(str(param), float(value_from), float(value_to),
                                        float(omega), int(harmonics), _pairs(set),
                                        json.dumps(settings))
        curve = json.loads(text)
        curve["columns"] = _columns(csv)
        return curve

    def simulate(self, omega, periods=None, dt=None, scheme=None, set=None):
        """Time integration from rest at ``omega``: the ``simulate`` JSON as a dict.
        ``scheme`` is ``"bdf2"`` or ``"gl"`` (default: the command line's)."""
        return json.loads(self._m.simulate(float(omega), _pairs(set), periods, dt, scheme))

    def backbone(self, to, mode=1, output=None, harmonics=DEFAULT_HARMONICS, set=None):
        """Nonlinear mode ``mode`` continued until max|output| = ``to``: the
        ``backbone`` JSON as a dict."""
        return json.loads(self._m.backbone(float(to), int(mode), int(harmonics), _pairs(set),
                                           output))

    def folds(self, param, value_from, value_to, omega_from, omega_to,
              harmonics=DEFAULT_HARMONICS, boundary=None, set=None, **settings):
        """Every fold of the Ω-curve (``boundary="period-doubling"`` or ``"torus"``:
        those points instead) continued as ``param`` goes from ``value_from`` to
        ``value_to``, with the cusps: the ``folds`` JSON as a dict."""
        return json.loads(self._m.folds(str(param), float(value_from), float(value_to),
                                        float(omega_from), float(omega_to), int(harmonics),
                                        _pairs(set), json.dumps(settings), boundary))

    def cycle(self, omega, harmonics=DEFAULT_HARMONICS, set=None):
        """A limit cycle of a model without forcing near the frequency guess ``omega``:
        the ``cycle`` JSON as a dict."""
        return json.loads(self._m.cycle(float(omega), int(harmonics), _pairs(set)))

    def cycles(self, param, value_from, value_to, omega, harmonics=DEFAULT_HARMONICS,
               set=None):
        """The limit cycle near ``omega`` continued in ``param``, with the Hopf point
        where it is born: the ``cycle --param`` JSON as a dict."""
        return json.loads(self._m.cycles(str(param), float(value_from), float(value_to),
                                         float(omega), int(harmonics), _pairs(set)))
