"""The PNG a failing waveform assertion attaches: the signal, its band or reference, and the
first violating sample, against emulated time."""
import textwrap

import numpy as np

from . import attachments


def _pyplot():
    """matplotlib only when a plot is drawn (a failure): importing it costs every run that
    passes (seconds in the TCG guest)."""
    import matplotlib
    matplotlib.use("Agg")  # files only: no display on a CI machine
    import matplotlib.pyplot as plt
    return plt


def failure_plot(assertion, signal, message, band=None, reference=None, marks=(), violation=None):
    """Writes the plot of a failed assertion into the current attachment folder and returns its
    path (None when no folder is set). band: (low, high) scalars or arrays over signal.time_s;
    reference: array over signal.time_s; marks: [(time_s, label)] vertical lines; violation:
    (time_s, value) of the first violating sample."""
    path = attachments.new_path(f"{assertion}_{signal.name}")
    if path is None:
        return None
    plt = _pyplot()
    fig, ax = plt.subplots(figsize=(9, 4.8), dpi=100)
    try:
        t = signal.time_s
        if band is not None:
            low = np.broadcast_to(np.asarray(band[0], dtype=float), t.shape)
            high = np.broadcast_to(np.asarray(band[1], dtype=float), t.shape)
            ax.fill_between(t, low, high, color="tab:green", alpha=0.18, step="post", label="band")
            ax.plot(t, low, color="tab:green", lw=0.8, drawstyle="steps-post")
            ax.plot(t, high, color="tab:green", lw=0.8, drawstyle="steps-post")
        if reference is not None:
            ax.plot(t, reference, color="tab:gray", lw=1.0, ls="--", label="reference")
        ax.plot(t, signal.values, color="tab:blue", lw=1.2, drawstyle="steps-post", label=signal.name)
        for time_s, label in marks:
            ax.axvline(time_s, color="tab:orange", lw=0.9, ls=":")
            ax.annotate(label, (time_s, 1.0), xycoords=("data", "axes fraction"), fontsize=8,
                        rotation=90, va="top", ha="right", color="tab:orange")
        if violation is not None and np.isfinite(violation[1]):
            ax.plot([violation[0]], [violation[1]], "o", color="tab:red", ms=7, label="first violation")
        elif violation is not None:
            ax.axvline(violation[0], color="tab:red", lw=1.2, label="first violation (NaN)")
        ax.set_xlabel("emulated time [s]")
        ax.set_ylabel(signal.label())
        ax.set_title("\n".join(textwrap.wrap(message, 120)[:4]), fontsize=7, loc="left")
        ax.grid(True, alpha=0.3)
        ax.legend(fontsize=8, loc="best")
        fig.tight_layout()
        fig.savefig(path)
    finally:
        plt.close(fig)
    attachments.attach(path)
    return path
