"""ABA(8,6,4) on two splits: why "aba864-harmonic" gains accuracy as the nonlinearity shrinks.

Equations: the homogeneous FPUT-alpha chain, fixed ends,
    H = sum p_j^2/2 + sum_b [ R_b^2/2 + alpha R_b^3/3 ],   R_b = x_b - x_{b-1}.
"aba864" splits H = T(p) + V(x): the kick carries the whole force, which is not small, so the
error is O(h^4) at every amplitude. "aba864-harmonic" splits H = H_harmonic + eps H_anharmonic:
the harmonic chain is integrated exactly (normal modes turned by w_k h), the kick carries only
alpha R^2, and the error is O(eps h^8 + eps^2 h^6 + eps^3 h^4) with eps ~ alpha * amplitude.
Parameters: N = 8, alpha = 0.25, x_j(0) = A sin(pi j/(N+1)), p = 0, A = 3, 0.3, 0.1;
t = 100; reference srkn14a6 at dt = 0.01.
Shows: the final-state error of both schemes for dt = 2, 1, 1/2, 1/4 and the observed orders.
aba864: order 4 at every A. aba864-harmonic: orders ~6 over the large steps once A is small
(where h^2 >> eps; it returns to 4 as h^2 approaches eps), and errors 15x (A = 3) to
1e4-1e5x (A = 0.1) smaller, the gap growing as A shrinks (measured at dt = 1: 7.9e-3 vs 5.4e-4
at A = 3; 1.3e-6 vs 3.6e-11 at A = 0.1). The exact harmonic part also removes the step limit
set by the highest frequency.
Run: python examples/harmonic_split_accuracy.py [--plot FILE]
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
