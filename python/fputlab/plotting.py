"""Plots of runs (matplotlib, Agg-safe: nothing here opens a window)."""
from __future__ import annotations

import numpy as np


def _axes(ax):
    if ax is not None:
        return ax
    import matplotlib.pyplot as plt
    return plt.subplots(figsize=(6, 4))[1]


def plot_mode_energies(run, modes=(1, 2, 3, 4), ax=None, relative: bool = False):
    """E_k(t) for the given modes (paper Figs. 1b, 2b/d, 3)."""
    ax = _axes(ax)
    scale = run.energy[0] if relative else 1.0
    for k in modes:
        ax.plot(run.t, run.mode_energies[:, k - 1] / scale, lw=0.9, label=f"$E_{k}$")
    ax.set_xlabel("$t$")
    ax.set_ylabel("$E_k/E$" if relative else "$E_k$")
    ax.legend(loc="upper right", frameon=False)
    return ax


def envelope(run, window: int) -> tuple[np.ndarray, np.ndarray]:
    """Running maximum of |x_j| over blocks of `window` samples: (block mid-times, (B, N))."""
    if run.states is None:
        raise ValueError("run has no states: integrate with store_states=True")
    N = run.lattice.N
    x = np.abs(run.states[:, :N])
    B = x.shape[0] // window
    if B == 0:
        raise ValueError(f"window {window} is longer than the run ({x.shape[0]} samples)")
    env = x[: B * window].reshape(B, window, N).max(axis=1)
    t = run.t[: B * window].reshape(B, window).mean(axis=1)
    return t, env


def plot_envelope(run, window: int, ax=None):
    """Top view of the oscillation envelope of x_j(t) (paper Figs. 1a, 2a/c)."""
    ax = _axes(ax)
    t, env = envelope(run, window)
    N = run.lattice.N
    im = ax.imshow(env.T, aspect="auto", origin="lower", cmap="viridis",
                   extent=(t[0], t[-1], 1, N), interpolation="nearest")
    ax.set_xlabel("$t$")
    ax.set_ylabel("$j$")
    ax.figure.colorbar(im, ax=ax, label=r"max $|x_j|$")
    return ax
