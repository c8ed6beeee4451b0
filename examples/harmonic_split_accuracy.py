r"""
ABA(8,6,4) on two splits: accuracy as the nonlinearity shrinks
==============================================================

**Equations:** the homogeneous FPUT-α chain, fixed ends,

.. math::

   H = \sum_j \frac{p_j^2}{2} + \sum_b \left[\frac{R_b^2}{2} + \alpha\frac{R_b^3}{3}\right],
   \qquad R_b = x_b - x_{b-1}.

``"aba864"`` splits :math:`H = T(p) + V(x)`: the kick carries the whole force, which is not
small, so the error is :math:`O(h^4)` at every amplitude. ``"aba864-harmonic"`` splits
:math:`H = H_\mathrm{harmonic} + \varepsilon H_\mathrm{anharmonic}`: the harmonic chain is
integrated exactly (normal modes turned by :math:`\omega_k h`), the kick carries only
:math:`\alpha R^2`, and the error is
:math:`O(\varepsilon h^8 + \varepsilon^2 h^6 + \varepsilon^3 h^4)` with
:math:`\varepsilon \sim \alpha \times` amplitude.

**Parameters:** :math:`N = 8`, :math:`\alpha = 0.25`, :math:`x_j(0) = A \sin(\pi j/(N+1))`,
:math:`p = 0`, :math:`A = 3, 0.3, 0.1`; :math:`t = 100`; reference srkn14a6 at
:math:`dt = 0.01`.

**Shows:** the final-state error of both schemes for :math:`dt = 2, 1, 1/2, 1/4` and the observed
orders. aba864: order 4 at every :math:`A`. aba864-harmonic: orders ~6 over the large steps once
:math:`A` is small (where :math:`h^2 \gg \varepsilon`; it returns to 4 as :math:`h^2` approaches
:math:`\varepsilon`), and errors 15× (:math:`A = 3`) to :math:`10^4`–:math:`10^5`×
(:math:`A = 0.1`) smaller, the gap growing as :math:`A` shrinks (measured at :math:`dt = 1`:
:math:`7.9\times 10^{-3}` vs :math:`5.4\times 10^{-4}` at :math:`A = 3`;
:math:`1.3\times 10^{-6}` vs :math:`3.6\times 10^{-11}` at :math:`A = 0.1`). The exact harmonic
part also removes the step limit set by the highest frequency.

**Run:** ``python examples/harmonic_split_accuracy.py [--plot FILE]``
"""
import argparse

import numpy as np

import fputlab

N, ALPHA, T = 8, 0.25, 100.0
AMPLITUDES = (3.0, 0.3, 0.1)
STEPS = (2.0, 1.0, 0.5, 0.25)
METHODS = ("aba864", "aba864-harmonic")


def final_state(lat, y0, method, dt):
    return fputlab.Integrator(lat, y0, method=method, dt=dt).advance(T)


def main():
    p = argparse.ArgumentParser(description=__doc__,
                                formatter_class=argparse.RawDescriptionHelpFormatter)
    p.add_argument("--plot", help="also save an error-vs-dt plot to this file")
    a = p.parse_args()
    lat = fputlab.Lattice(N, ALPHA)
    errors = {}
    for amp in AMPLITUDES:
        y0 = lat.mode_state(1, amp)
        ref = final_state(lat, y0, "srkn14a6", 0.01)
        for m in METHODS:
            errors[amp, m] = [float(np.abs(final_state(lat, y0, m, dt) - ref).max())
                              for dt in STEPS]
    print(f"max |y(t={T:g}) - reference|, N = {N}, alpha = {ALPHA}")
    print(f"{'A':>5} {'method':<16}" + "".join(f"{'dt=' + format(dt, 'g'):>11}" for dt in STEPS)
          + "   observed orders")
    for amp in AMPLITUDES:
        for m in METHODS:
            e = errors[amp, m]
            orders = [np.log2(e[i] / e[i + 1]) for i in range(len(e) - 1)]
            print(f"{amp:>5g} {m:<16}" + "".join(f"{x:>11.2e}" for x in e)
                  + "   " + " ".join(f"{q:4.1f}" for q in orders))
    if a.plot:
        import matplotlib
        matplotlib.use("Agg")
        import matplotlib.pyplot as plt
        fig, ax = plt.subplots(figsize=(6, 4.5))
        for amp, color in zip(AMPLITUDES, ("C0", "C1", "C2")):
            for m, style in zip(METHODS, ("--o", "-s")):
                ax.loglog(STEPS, errors[amp, m], style, color=color, label=f"{m}, A = {amp:g}")
        ax.set_xlabel("dt")
        ax.set_ylabel(f"final-state error at t = {T:g}")
        ax.legend(fontsize=8)
        fig.tight_layout()
        fig.savefig(a.plot, dpi=120)
        print(f"wrote {a.plot}")


if __name__ == "__main__":
    main()
