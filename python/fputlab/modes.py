"""Normal modes of the fixed-end chain (see also Lattice.to_modes / mode_energies)."""
from __future__ import annotations

import numpy as np

from ._lowlevel import modes_omega

__all__ = ["omega", "mode_matrix"]


def omega(N: int) -> np.ndarray:
    """omega_k = 2 sin(k pi / (2(N+1))), k = 1..N (paper Eq. wk)."""
    return modes_omega(int(N))


def mode_matrix(N: int) -> np.ndarray:
    """The explicit orthogonal matrix A_jk = sqrt(2/(N+1)) sin(jk pi/(N+1)) (for small N; the
    library itself transforms by FFT)."""
    j = np.arange(1, N + 1)
    return np.sqrt(2.0 / (N + 1)) * np.sin(np.outer(j, j) * np.pi / (N + 1))
