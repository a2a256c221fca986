"""Figures of the evaluation: per case, the distance walked (and on a floating base the yaw) over
time for each method, one line per dt, the smallest dt (the reference) dashed."""
import os

import numpy as np


def case_figure(case, rows, data, fig_dir):
    """rows: the case's default rows (dicts with method, dt, key, stable); data: key -> trajectory.
    Returns the path written, or None if there is nothing to draw."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    methods = sorted({r["method"] for r in rows}, key=lambda m: (m != "ne-pgm", m))
    if not methods or not any(r["key"] in data for r in rows):
        return None
    floating = case["base"] == "floating"
    nrow = 2 if floating else 1
    fig, axes = plt.subplots(nrow, len(methods), figsize=(6 * len(methods), 3.4 * nrow), squeeze=False, sharex=True)
    dts = sorted({r["dt"] for r in rows})
    cmap = plt.get_cmap("viridis")
    for j, method in enumerate(methods):
        for r in sorted((r for r in rows if r["method"] == method and r["key"] in data), key=lambda r: r["dt"]):
            d = data[r["key"]]
            p = d["pos"] - d["pos"][0]
            dist = np.hypot(p[:, 0], p[:, 1]) if floating else p[:, 0]
            ref = r["dt"] == min(dts)
            style = dict(color="black", linestyle="--", linewidth=1.0) if ref else \
                dict(color=cmap(dts.index(r["dt"]) / max(1, len(dts) - 1)), linewidth=0.9)
            label = f"{r['dt'] * 1000:g} ms" + (" (reference)" if ref else "") + ("" if r["stable"] else " (unstable)")
            axes[0, j].plot(d["time"], dist, label=label, **style)
            if floating:
                axes[1, j].plot(d["time"], np.unwrap(d["rpy"][:, 2]) - d["rpy"][0, 2], **style)
        axes[0, j].set_title(f"{case['robot']}, {case['ground']}: {method}", fontsize=10)
        axes[0, j].set_ylabel("|Δ(x, y)|, m" if floating else "x, m")
        axes[0, j].legend(fontsize=7)
        if floating:
            axes[1, j].set_ylabel("yaw, rad")
        axes[-1, j].set_xlabel("time, s")
        for ax in axes[:, j]:
            ax.grid(True, alpha=0.3)
    fig.tight_layout()
    os.makedirs(fig_dir, exist_ok=True)
    path = os.path.join(fig_dir, f"steps_{case['id']}.png")
    fig.savefig(path, dpi=80)
    plt.close(fig)
    return path
