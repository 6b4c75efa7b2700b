"""``ihbm.plot``: a sweep, fold curves or a backbone drawn with matplotlib."""

import math

# How each stability verdict is drawn (the JSON's true, false, null).
_STYLE = {True: "-", False: "--", None: ":"}
_NAME = {True: "stable", False: "unstable", None: "no verdict"}


def plot(result, ax=None, output=None, *, label=None):
    """Draw ``result`` on ``ax`` (a new figure's axes when ``None``) and return ``ax``.

    - a sweep (:meth:`Model.sweep`, :meth:`Model.sweep_param`): max|``output``|
      against the swept parameter; stable points solid, unstable dashed, points
      without a verdict dotted; one line per segment and verdict, so the pieces of a
      curve (a runaway branch and the sweep back from the other end) are never joined;
      folds as circles, resonance peaks as crosses, each jump of a slow sweep as a
      dotted arrow (``^`` up, ``v`` down) from the amplitude it leaves to the one it
      lands on;
    - fold curves (:meth:`Model.folds`): each curve in the (Ω, parameter) plane, the
      cusps as diamonds (``output`` is not used);
    - a backbone (:meth:`Model.backbone`): max|``output``| against Ω, styled by
      stability as a sweep.

    ``output`` defaults to the first output (a backbone's: the one it was continued
    in). ``label`` labels the curve in a legend. Artists carry a ``gid``
    (``"curve"``, ``"folds"``, ``"peaks"``, ``"jump"``, ``"cusps"``) so they can be
    found again.
    Needs matplotlib.
    """
    try:
        import matplotlib.pyplot as plt
    except ImportError as e:
        raise ImportError("ihbm.plot needs matplotlib: pip install matplotlib") from e
    if not isinstance(result, dict):
        raise TypeError(f"ihbm.plot draws a sweep, folds or backbone result, not {type(result).__name__}")
    if ax is None:
        _, ax = plt.subplots()
    if "cusps" in result and "curves" in result:
        _folds(ax, result, label)
    elif "linear" in result and "mode" in result:
        out = output if output is not None else result.get("output")
        _backbone(ax, result, _output(result, out), label)
    elif "segments" in result and "points" in result:
        _sweep(ax, result, _output(result, output), label)
    else:
        raise ValueError("ihbm.plot draws a sweep, fold curves or a backbone; "
                         "this result is none of them")
    return ax


def _output(result, output):
    """The output to draw, checked against the result's."""
    names = list(result["points"][0]["outputs"]) if result["points"] else []
    if output is None:
        if not names:
            raise ValueError("ihbm.plot: the result has no points to draw")
        return names[0]
    if names and output not in names:
        raise ValueError(f"ihbm.plot: unknown output {output!r} (the result has {names})")
    return output


def _runs(ax, x, y, verdicts, segments, label, color):
    """Lines of constant verdict within each segment. A line takes the point after its
    last one too when that point is in the same segment, so that the styles meet; a
    line never crosses from one segment to the next. Returns the color used."""
    n = len(x)
    for seg in sorted(set(segments)):
        idx = [i for i in range(n) if segments[i] == seg]
        for v in (True, False, None):
            if not any(verdicts[i] is v for i in idx):
                continue
            ys = []
            for k, i in enumerate(idx):
                nxt = idx[k + 1] if k + 1 < len(idx) else None
                keep = verdicts[i] is v or (nxt is not None and verdicts[nxt] is v)
                ys.append(y[i] if keep else math.nan)
            (line,) = ax.plot([x[i] for i in idx], ys, linestyle=_STYLE[v], color=color,
                              gid="curve")
            color = line.get_color()
            if label is not None:
                line.set_label(f"{label} ({_NAME[v]})" if len(set(verdicts)) > 1 else label)
                label = None
    return color


def _sweep(ax, c, output, label):
    param = c.get("parameter", "omega")
    by_param = param != "omega"
    pts = c["points"]
    x = [p["param"] if by_param else p["omega"] for p in pts]
    y = [p["outputs"][output]["max_abs"] for p in pts]
    verdicts = [p["stable"] for p in pts]
    segments = _segments(c, x)
    color = _runs(ax, x, y, verdicts, segments, label, None)
    folds = [(f["param"] if by_param else f["omega"], f["outputs"][output]["max_abs"])
             for f in c["folds"] if output in f["outputs"]]
    if folds:
        ax.plot([f[0] for f in folds], [f[1] for f in folds], linestyle="none", marker="o",
                color=color, markerfacecolor="none", gid="folds")
    peaks = [(k["param"] if by_param else k["omega"], k["value"])
             for k in c.get("peaks", []) if k["output"] == output]
    if peaks:
        ax.plot([k[0] for k in peaks], [k[1] for k in peaks], linestyle="none", marker="x",
                color=color, gid="peaks")
    for j in c["jumps"]:
        if j["output"] != output:
            continue
        at = j["param"] if by_param else j["omega"]
        ax.plot([at, at], [j["from"], j["to"]], linestyle=":", color=color,
                marker="^" if j["direction"] == "up" else "v", markevery=[1], gid="jump")
    ax.set_xlabel("Ω (rad/s)" if not by_param else param)
    ax.set_ylabel(f"max |{output}|")


def _segments(c, x):
    """Each point's segment: the ``segment`` column when the result has one, else
    (a result read back from JSON) one segment."""
    cols = c.get("columns")
    if cols is not None and "segment" in cols:
        return [int(s) for s in cols["segment"]]
    return [0] * len(x)


def _folds(ax, f, label):
    color = None
    for curve in f["curves"]:
        pts = curve["points"]
        (line,) = ax.plot([p["omega"] for p in pts], [p["value"] for p in pts], color=color,
                          gid="curve")
        color = line.get_color()
        if label is not None:
            line.set_label(label)
            label = None
    if f["cusps"]:
        ax.plot([c["omega"] for c in f["cusps"]], [c["value"] for c in f["cusps"]],
                linestyle="none", marker="D", color=color, gid="cusps")
    ax.set_xlabel("Ω (rad/s)")
    ax.set_ylabel(f["parameter"])


def _backbone(ax, b, output, label):
    pts = b["points"]
    x = [p["omega"] for p in pts]
    y = [p["outputs"][output]["max_abs"] for p in pts]
    _runs(ax, x, y, [p["stable"] for p in pts], [0] * len(pts), label, None)
    ax.set_xlabel("Ω (rad/s)")
    ax.set_ylabel(f"max |{output}|")
