"""ARKODE SPRKStep methods from Python: listed only when the linked SUNDIALS has SPRKStep
(>= 6.6), refused with a message naming the SUNDIALS version otherwise; when present they agree
with the splitting schemes and DOP853 and conserve energy."""
import numpy as np
import pytest

import fputlab
from fputlab._native import ffi, lib

SUNDIALS = ffi.string(lib.fpl_sundials_version()).decode()
HAVE_SPRK = tuple(int(p) for p in SUNDIALS.split(".")[:2]) >= (6, 6)
SPRK = ["sprk-mclachlan4", "sprk-yoshida6", "sprk-suzuki-umeno8", "sprk-sofroniou10"]


def test_listing_follows_the_linked_sundials():
    listed = [m for m in fputlab.methods() if m.startswith("sprk-")]
    assert listed == (SPRK if HAVE_SPRK else [])


@pytest.mark.skipif(HAVE_SPRK, reason="this SUNDIALS has SPRKStep")
def test_refused_without_sprkstep():
    lat = fputlab.Lattice(N=8, alpha=0.25)
    with pytest.raises(ValueError, match=r"SPRKStep.*SUNDIALS >= 6\.6.*" + SUNDIALS):
        lat.integrate(10.0, method="sprk-yoshida6", dt=0.05)


@pytest.mark.skipif(not HAVE_SPRK, reason=f"SUNDIALS {SUNDIALS} has no SPRKStep")
@pytest.mark.parametrize("method,dt", [("sprk-mclachlan4", 0.02), ("sprk-yoshida6", 0.05),
                                       ("sprk-suzuki-umeno8", 0.1), ("sprk-sofroniou10", 0.2)])
def test_agrees_with_dop853_and_conserves_energy(method, dt):
    lat = fputlab.Lattice(N=16, alpha=0.25)
    y0 = lat.mode_state(1, 2.0)
    run = lat.integrate(100.0, method=method, dt=dt, sample_every=10.0, y0=y0, store_states=True)
    ref = lat.integrate(100.0, method="dop853", rtol=1e-13, atol=1e-15, sample_every=10.0, y0=y0,
                        store_states=True)
    assert np.allclose(run.t, ref.t)
    assert np.max(np.abs(run.states - ref.states)) < 1e-6
    assert run.relative_energy_error.max() < 1e-7
