"""The bond potential's barrier (fpl_lattice_barrier, Lattice.barrier) against the closed forms,
and the default blow-up criteria built on it."""
import math

import numpy as np
import pytest

import fputlab
from fputlab import Lattice, blowup

INF = math.inf


@pytest.mark.parametrize("alpha,beta,expected", [
    (0.25, 0.0, (-4.0, INF)),                  # FPUT-alpha: V'(r) = r (1 + alpha r)
    (-0.5, 0.0, (-INF, 2.0)),
    (0.0, 0.0, (-INF, INF)),                   # harmonic
    (0.0, 1.0, (-INF, INF)),                   # FPUT-beta, beta > 0: no barrier
    (0.0, -1.0, (-1.0, 1.0)),                  # FPUT-beta, beta < 0: +-1/sqrt(-beta)
    (1.0, 2 / 3, (-INF, INF)),                 # alpha^2 < 4 beta: no non-zero root
    (1.0, 0.25, (-INF, INF)),                  # alpha^2 = 4 beta: a double root, no barrier
    (1.0, 0.2, ((-1 + math.sqrt(0.2)) / 0.4, INF)),
    (0.5, -0.1, ((0.5 - math.sqrt(0.65)) / 0.2, (0.5 + math.sqrt(0.65)) / 0.2)),
    (-1.0, 0.2, (-INF, (1 - math.sqrt(0.2)) / 0.4)),
])
def test_barrier_closed_forms(alpha, beta, expected):
    lower, upper = Lattice(8, alpha, beta=beta).barrier
    assert lower == pytest.approx(expected[0], rel=1e-14)
    assert upper == pytest.approx(expected[1], rel=1e-14)
    for r in (lower, upper):
        if math.isfinite(r):     # a simple root of V' = r + alpha r^2 + beta r^3: a sign change
            dV = lambda s: s + alpha * s**2 + beta * s**3
            assert abs(dV(r)) < 1e-12 * abs(r)
            assert dV(0.999 * r) * dV(1.001 * r) < 0


def test_barrier_is_accurate_for_a_tiny_beta():
    """The nearer root -> -1/alpha as beta -> 0 (no cancellation in the quadratic formula)."""
    lower, upper = Lattice(8, 1.0, beta=1e-12).barrier
    assert lower == pytest.approx(-1.0 - 1e-12, rel=1e-15)
    assert upper == INF


@pytest.mark.parametrize("boundary", ["fixed", "periodic"])
def test_toda_has_no_barrier(boundary):
    assert Lattice(8, 1.0, "toda", boundary=boundary).barrier == (-INF, INF)


def test_default_criteria_follow_the_barrier():
    assert blowup.default_criteria(Lattice(8, 0.25)) == [("stretch", 4.0)]
    assert blowup.default_criteria(Lattice(8, 0.5, beta=-1.0)) == \
        [("stretch", pytest.approx(min(-Lattice(8, 0.5, beta=-1.0).barrier[0],
                                       Lattice(8, 0.5, beta=-1.0).barrier[1])))]
    assert blowup.default_criteria(Lattice(8, 1.0, beta=2 / 3)) == [("displacement", 100.0)]
    assert blowup.default_criteria(Lattice(8, 1.0, "toda")) == [("displacement", 100.0)]


def test_no_barrier_is_no_blowup():
    """alpha = 1, beta = 2/3 has no barrier: the energetic mode-1 orbit stays bounded and is not
    reported as a blow-up (it was, at t ~ 1-25, with the barrier at 1/alpha whatever beta)."""
    lat = Lattice(16, 1.0, beta=2 / 3)
    y0 = lat.mode_state(1, 5.0)
    res = fputlab.chaos.lyapunov(lat, 30.0, y0=y0, n_samples=5)
    assert not res.blew_up and res.completed
    assert not blowup.blowup_time(lat, 30.0, y0=y0).blew_up
    # the orbit does stretch bonds past 1/alpha: the old default would have called it a blow-up
    assert fputlab.chaos.lyapunov(lat, 30.0, y0=y0, n_samples=5, blowup_stretch=1.0).blew_up


def test_barrier_still_catches_the_fput_alpha_escape():
    lat = Lattice(16, 1.0)
    y0 = lat.mode_state(1, 5.0)
    res = fputlab.chaos.lyapunov(lat, 30.0, y0=y0, n_samples=5)
    assert res.blew_up and "barrier" in res.message
