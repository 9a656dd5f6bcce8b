"""The tolerance sheet of `linkage tolerance --plot`: per output, a histogram of the Monte Carlo values with
the nominal value, the 5-95 % band and the first-order estimate, and a bar chart of which tolerance drives
it (Sobol ST and S1 when computed, else each tolerance's first-order share of the variance)."""

from __future__ import annotations

import math

import numpy as np

from sim.output.io import atomic_path


def histogram(result, name: str, mech, display, ax=None):
    """The Monte Carlo values of output ``name`` (``display`` units) with the nominal value, p05/p95 and the
    linearised model's values over the same draws (first-order propagation); returns the Axes."""
    import matplotlib.pyplot as plt
    from sim.service.tolerance import output_quantity
    ax = ax or plt.gca()
    q = output_quantity(mech, name)
    s = result.summaries[name]
    v = np.asarray(display.convert(q, result.values[name]))
    v = v[np.isfinite(v)]
    unit = display.unit(q)
    lin = result.linearised[name] * display.factor(q) if name in result.linearised else np.empty(0)
    both = np.concatenate([v, lin[np.isfinite(lin)]])
    edges, clipped = 10, ""
    if both.size:
        lo, hi = np.percentile(both, [0.5, 99.5])        # a few near-singular designs would squash the rest
        if not hi > lo:
            lo, hi = both.min(), both.max()
        clipped = " (the outer 1 % not shown)" if (both.min() < lo or both.max() > hi) else ""
        edges = np.histogram_bin_edges(both, bins=min(60, max(10, int(math.sqrt(max(v.size, 1))))),
                                       range=(lo, hi) if hi > lo else None)
    if v.size:
        ax.hist(v, bins=edges, density=True, color="tab:blue", alpha=0.6, label=f"Monte Carlo ({v.size} designs)")
    f = display.factor(q)
    if lin.size:
        ax.hist(lin, bins=edges, density=True, histtype="step", color="tab:orange", lw=1.5,
                label=f"linearised (first order), std {s.first_order_std * f:.3g}")
    ax.axvline(s.nominal * f, color="k", lw=1.0, label=f"nominal {s.nominal * f:.4g}")
    for p in (s.p05, s.p95):
        if math.isfinite(p):
            ax.axvline(p * f, color="k", lw=0.8, ls=":")
    ax.set_xlabel(f"{name} [{unit}]" if unit else name)
    ax.set_ylabel("density")
    ax.set_title(f"{name}: mean {s.mean * f:.4g}, std {s.std * f:.3g} (5-95 %: dotted){clipped}", fontsize=9)
    ax.legend(fontsize=7, loc="best")
    return ax


def drivers(result, name: str, ax=None):
    """Which tolerance drives output ``name``: Sobol ST and S1 (with their confidence) when computed, else
    the first-order shares of the variance; returns the Axes."""
    import matplotlib.pyplot as plt
    ax = ax or plt.gca()
    s = result.summaries[name]
    names = [t.name for t in result.tolerances]
    y = np.arange(len(names))
    if not any(v > 0 for v in s.shares.values()) and not s.sobol:
        ax.text(0.5, 0.5, f"{name} does not vary\nunder these tolerances", ha="center", va="center",
                transform=ax.transAxes, fontsize=9)
    elif s.sobol:
        st = [s.sobol[n]["ST"] for n in names]
        s1 = [s.sobol[n]["S1"] for n in names]
        ax.barh(y + 0.2, st, height=0.4, color="tab:red", xerr=[s.sobol[n]["ST_conf"] for n in names],
                label="Sobol ST (total)")
        ax.barh(y - 0.2, s1, height=0.4, color="tab:pink", xerr=[s.sobol[n]["S1_conf"] for n in names],
                label="Sobol S1 (first order)")
        ax.plot([s.shares[n] for n in names], y, "k|", ms=12, label="first-order share")
        ax.set_xlabel("share of the variance")
    else:
        ax.barh(y, [s.shares[n] for n in names], height=0.6, color="tab:green", label="first-order share")
        ax.set_xlabel("first-order share of the variance")
    ax.set_yticks(y, names)
    ax.set_xlim(0, 1.05)
    ax.invert_yaxis()
    ax.set_title(f"what drives {name}", fontsize=9)
    if ax.get_legend_handles_labels()[0]:
        ax.legend(fontsize=7, loc="best")
    return ax


def sheet(result, mech, out: str, display) -> None:
    """Write the tolerance sheet of ``result`` to ``out`` (.png, .svg or .pdf), lengths and angles in
    ``display`` units."""
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    n = len(result.outputs)
    fig, axes = plt.subplots(n, 2, figsize=(11, 2.9 * n + 0.6), squeeze=False,
                             gridspec_kw={"width_ratios": [2.2, 1]})
    for k, name in enumerate(result.outputs):
        histogram(result, name, mech, display, axes[k, 0])
        drivers(result, name, axes[k, 1])
    tols = ", ".join(f"{t.name} {t.text}" for t in result.tolerances)
    failed = f"; {result.failed} failed to assemble" if result.failed else ""
    fig.suptitle(f"{result.mechanism}: tolerances {tols}; {result.samples} samples (seed {result.seed}){failed}",
                 fontsize=10)
    fig.tight_layout()
    try:
        with atomic_path(out) as tmp:
            fig.savefig(tmp, dpi=90)
    finally:
        plt.close(fig)
