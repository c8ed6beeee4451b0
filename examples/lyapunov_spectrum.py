r"""
Lyapunov spectrum, covariant Lyapunov vectors and MEGNO of FPUT-β chains
========================================================================

**Equations:** fixed ends, α = 0,

.. math::

   H = \sum_j \frac{p_j^2}{2 m_j} + \sum_b \left[\frac{R_b^2}{2} + \beta\frac{R_b^4}{4}\right],

model 1 (``"homogeneous"``, :math:`m_j = 1`, :math:`R_b = x_b - x_{b-1}`) and model 2
(``"hamiltonian"``, masses :math:`m_j = v_j`, :math:`R_b = v_b x_b - v_{b-1} x_{b-1}`,
:math:`v_j` Gaussian around 1 with τ percent spread). The deviation vectors follow the tangent
map of srkn14a6 (a symplectic scheme) and are re-orthonormalised by a Householder QR every time
unit: :math:`\lambda_i = (1/t) \sum \ln R_{ii}` (``fputlab.chaos.lyapunov_spectrum``). CLVs by
Ginelli's backward iteration (``fputlab.chaos.covariant_lyapunov_vectors``); MEGNO
:math:`\langle Y\rangle(t)` from ``fputlab.chaos.lyapunov``.

**Parameters:** β = 1, energy density E/N = 1 (random momenta, x = 0, seed 1), N = 8, 16, 32,
t = ``--t-end`` (default 2000) after a transient of 100; CLVs of N = 32, ordered and τ = 30 %,
over a window of 20 with transients of 100; MEGNO of N = 2 (E/N = 0.05, regular) and of N = 8.

**Shows:** the spectra of the three sizes fall on one curve against i/(2N) (the thermodynamic
limit); they pair, :math:`\lambda_i + \lambda_{2N+1-i} = 0`, and sum to zero (printed: the
largest pair sum and the total); the Kolmogorov-Sinai entropy and the Kaplan-Yorke dimension per
N; the participation number 1/IPR of the CLVs (how many sites they occupy), for the ordered
against the disordered chain; MEGNO → 2 for the regular orbit, ~ λt/2 for the chaotic one.

**Run:** ``python examples/lyapunov_spectrum.py [--t-end 2000] [--plot FILE]``
"""
import argparse

import numpy as np

import fputlab
from fputlab.chaos import covariant_lyapunov_vectors, lyapunov, lyapunov_spectrum

BETA, ENERGY_DENSITY, SIZES = 1.0, 1.0, (8, 16, 32)
METHOD, DT = "srkn14a6", 0.1


def state(lat, energy_density, seed=1):
    """x = 0 and random momenta scaled to the energy E = energy_density * N."""
    p = np.random.default_rng(seed).standard_normal(lat.N)
    mass = lat.v if lat.model == "hamiltonian" else np.ones(lat.N)
    p *= np.sqrt(2 * energy_density * lat.N / np.sum(p**2 / mass))
    return np.concatenate([np.zeros(lat.N), p])


def main():
    ap = argparse.ArgumentParser(description=__doc__,
                                 formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--t-end", type=float, default=2000.0)
    ap.add_argument("--plot", help="write the four panels to this image file")
    a = ap.parse_args()

    spectra = []
    print(f"{'N':>3} {'lambda_1':>9} {'max|pair sum|':>14} {'sum':>9} {'h_KS':>7} {'D_KY':>6}")
    for N in SIZES:
        lat = fputlab.Lattice(N, 0.0, beta=BETA)
        res = lyapunov_spectrum(lat, a.t_end, y0=state(lat, ENERGY_DENSITY), method=METHOD,
                                dt=DT, t_transient=100.0)
        lam = res.exponents
        spectra.append(res)
        print(f"{N:3d} {lam[0]:9.4f} {np.max(np.abs(lam + lam[::-1])):14.2e} "
              f"{lam.sum():9.1e} {res.ks_entropy:7.3f} {res.kaplan_yorke_dimension:6.2f}")

    clvs = []
    for tau in (0.0, 30.0):
        lat = fputlab.Lattice(32, 0.0, "hamiltonian", beta=BETA, tau=tau, seed=2)
        c = covariant_lyapunov_vectors(lat, 20.0, t_forward=100.0, t_backward=100.0,
                                       y0=state(lat, ENERGY_DENSITY), method=METHOD, dt=DT)
        clvs.append(c)
        part = (1 / c.ipr).mean(axis=0)
        print(f"CLVs N = 32, tau = {tau:4.1f} %: sites occupied (1/IPR) by v_1 {part[0]:.1f}, "
              f"middle v_32 {part[31]:.1f}, v_64 {part[-1]:.1f} (of 32)")

    regular = fputlab.Lattice(2, 0.0, beta=BETA)
    chaotic = fputlab.Lattice(8, 0.0, beta=BETA)
    megno = [lyapunov(regular, 1e4, y0=state(regular, 0.05), renorm_interval=0.1, n_samples=30),
             lyapunov(chaotic, 1e3, y0=state(chaotic, ENERGY_DENSITY), renorm_interval=0.1,
                      n_samples=30)]
    print(f"MEGNO regular N = 2 at t = 1e4: {megno[0].megno_final:.3f} (-> 2)")
    r = megno[1]
    print(f"MEGNO chaotic N = 8 at t = 1e3: {r.megno_final:.1f}, lambda t/2 = "
          f"{r.mle_final * r.t[-1] / 2:.1f}")

    if a.plot:
        import matplotlib
        matplotlib.use("Agg")
        import matplotlib.pyplot as plt

        from fputlab import plotting
        fig, ax = plt.subplots(2, 2, figsize=(10, 7), constrained_layout=True)
        plotting.plot_spectrum(spectra, ax=ax[0, 0])
        plotting.plot_spectrum_convergence(spectra[-1], ax=ax[0, 1], every=4)
        plotting.plot_clv_localisation(clvs, ax=ax[1, 0], labels=["ordered", "tau = 30 %"])
        plotting.plot_megno(megno, ax=ax[1, 1], labels=["regular (N = 2)", "chaotic (N = 8)"])
        ax[1, 1].set_yscale("log")
        fig.savefig(a.plot, dpi=120)
        print(f"wrote {a.plot}")


if __name__ == "__main__":
    main()
