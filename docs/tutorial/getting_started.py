"""
Getting started
===============

A first session with fputlab, in the order of the paper: the FPUT recurrence, its breakdown
with disorder, blow-up above the threshold, and chaos. The FPUT-α lattice of :math:`N`
particles with fixed ends :math:`x_0 = x_{N+1} = 0` obeys

.. math::

   \\ddot x_j = (x_{j+1} - 2x_j + x_{j-1})
   + \\alpha\\left[(v_{j+1}x_{j+1} - v_j x_j)^2 - (v_j x_j - v_{j-1}x_{j-1})^2\\right],

with :math:`v_j = 1` for the homogeneous chain (model 1) and :math:`v_j = 1 + (\\tau/300) z_j`,
:math:`z_j` standard normal, for the disordered chain of model 3. The energy of normal mode
:math:`k` is :math:`E_k = (P_k^2 + \\omega_k^2 Q_k^2)/2` with :math:`\\omega_k = 2\\sin(k\\pi/(2(N+1)))`.

Parameters: :math:`N = 64`, :math:`\\alpha = 0.25`, the initial state
:math:`x_j = \\sin(\\pi j/(N+1))`, :math:`p = 0` (all energy in mode 1); Yoshida 4 at
:math:`dt = 0.01`. It shows the FPUT recurrence, its breakdown with disorder, a blow-up above
the threshold :math:`\\tau_c`, and the chaos indicators λ(t) and SALI(t). It runs in seconds.
"""

# %%
# The homogeneous chain: FPUT recurrence
# --------------------------------------
# A :class:`~fputlab.lattice.Lattice` holds the physics; ``integrate`` runs it (Yoshida 4 at
# dt = 0.01 by default, starting from mode 1) and returns a ``Run`` of samples.
import matplotlib.pyplot as plt

import fputlab
from fputlab import plotting

lat = fputlab.Lattice(N=64, alpha=0.25)
run = lat.integrate(7e4, sample_every=50.0)
run

# %%
# Almost all the energy comes back to mode 1 near :math:`t \approx 5.6\times 10^4`:
share = run.mode_energies[:, 0] / run.mode_energies[0, 0]
late = run.t > 3e4
print(f"E_1 returns to {share[late].max():.1%} of its start at t = {run.t[late][share[late].argmax()]:.4g}")
print(f"largest relative energy error: {run.relative_energy_error.max():.1e}")

fig, ax = plt.subplots(figsize=(7, 3.5))
plotting.plot_mode_energies(run, ax=ax)
ax.set_title("Homogeneous chain: energy returns to mode 1")

# %%
# Disorder breaks the recurrence
# ------------------------------
# Model 3 with τ = 10 % of variability in the nonlinear couplings (disorder seed 3, the
# realisation of the paper-like Fig. 2): the same seed always gives the same :math:`v_j`.
dis = fputlab.Lattice(N=64, alpha=0.25, model="nonlinear", tau=10.0, seed=3)
print("v_1..v_4 =", dis.v[:4].round(4))
run_dis = dis.integrate(7e4, sample_every=50.0)

fig, ax = plt.subplots(figsize=(7, 3.5))
plotting.plot_mode_energies(run_dis, ax=ax)
ax.set_title("Disordered chain (τ = 10 %): the energy stays in mode 1")

# %%
# Above the threshold: blow-up
# ----------------------------
# Beyond :math:`\tau_c \approx 10\,\%` the two-mode theory predicts, and the lattice shows,
# escape over the cubic barrier in finite time. ``blowup_time`` integrates until a blow-up
# criterion fires.
from fputlab import blowup

hot = fputlab.Lattice(N=64, alpha=0.25, model="nonlinear", tau=20.0, seed=1)
b = blowup.blowup_time(hot, 1e4)
print(f"blow-up at t = {b.time:.6g} ({b.criterion})")

# %%
# Chaos indicators
# ----------------
# :func:`fputlab.chaos.lyapunov` carries two deviation vectors with the tangent map of the
# integrator and returns the finite-time maximum Lyapunov exponent λ(t) and SALI(t). A regular
# orbit has λ ~ 1/t and SALI bounded away from zero; here a small homogeneous chain, to keep
# the build fast.
from fputlab import chaos

small = fputlab.Lattice(N=8, alpha=0.25)
indicators = chaos.lyapunov(small, 2e4)

fig, (ax1, ax2) = plt.subplots(1, 2, figsize=(8, 3.2), layout="constrained")
plotting.plot_mle(indicators, ax=ax1)
plotting.plot_sali(indicators, ax=ax2)

# %%
# Labelled data
# -------------
# Every result converts to an xarray Dataset with units and long names.
run.to_xarray()
