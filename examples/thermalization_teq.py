r"""
T_eq(ε): the equipartition time of random-phase ensembles against the nonlinearity
==================================================================================

**Equations:** α-FPUT on a ring of N particles (β-FPUT: :math:`\beta r^4/4` instead of the
cubic term),

.. math::

   H = \sum_j \frac{p_j^2}{2} + \frac{(x_{j+1} - x_j)^2}{2} + \alpha\frac{(x_{j+1} - x_j)^3}{3};

waves :math:`a_k = (\omega_k X_k + i P_k)/\sqrt{2 \omega_k}`, :math:`e_k = \omega_k |a_k|^2`,
k = 1..N-1; :math:`f_k = M e_k/\sum e`; the information entropy :math:`S = \sum f_k \ln f_k` of
the ensemble-averaged spectrum; :math:`\eta(t) = S(t)/S(0)`; T_eq = the first time
:math:`\eta \le 0.1`, with a 90 % bootstrap interval over the orbits; the fit
:math:`T_{eq} \sim \varepsilon^{-a}` with a bootstrap interval of a.

**Parameters:** the built-in studies of ``fputlab.thermalization_study``
(docs/thermalization.md): α = 1, N = 32, band ±1..±4, :math:`\varepsilon = \alpha\sqrt{E/N}`
= 0.05..0.11, 16-64 orbits per ε (alpha); β = 1, :math:`\varepsilon = \beta E/N` = 0.015..1
(beta).

**Shows:** the measured exponent next to Onorato et al.'s 8 (α) and Lvov & Onorato's 4 → 2 (β),
and η(t) of every ε.

**Run:** ``python examples/thermalization_teq.py [--studies-dir studies/thermalization] [--out PNG]``
(draws from the committed studies, engine stores analysed on the fly; ``fputlab thermalization
alpha --work-dir D`` recomputes one, resumable, in about 10 CPU-minutes.)
"""
import argparse
from pathlib import Path

from fputlab.figures_thermalization import thermalization_figure
from fputlab.thermalization_study import ThermalizationStudy

try:
    ROOT = Path(__file__).resolve().parents[1]
except NameError:           # run by the docs gallery, which gives no __file__, from examples/
    ROOT = Path.cwd().resolve().parent

if __name__ == "__main__":
    p = argparse.ArgumentParser(description=__doc__,
                                formatter_class=argparse.RawDescriptionHelpFormatter)
    p.add_argument("--studies-dir", default=str(ROOT / "studies" / "thermalization"))
    p.add_argument("--studies", nargs="+", default=["alpha"])
    p.add_argument("--out", default="thermalization_teq.png")
    a = p.parse_args()
    if Path(a.out).exists():
        raise SystemExit(f"{a.out} exists; not overwritten (choose another --out)")
    results = [ThermalizationStudy(Path(a.studies_dir) / s).results() for s in a.studies]
    fig = thermalization_figure(results, a.out)
    for label, fit in fig.numbers.items():
        lo, hi = fit["interval"]
        print(f"{label}: T_eq ~ eps^-{fit['exponent']:.2f}, 90 % interval [{lo:.2f}, {hi:.2f}]")
    print(fig)
