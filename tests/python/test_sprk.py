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


@pytest.mark.parametrize("call", ["Integrator", "integrate", "simulate_to_file"])
def test_compensated_sums_refused_for_other_methods(call, tmp_path):
    lat = fputlab.Lattice(N=8, alpha=0.25)
    with pytest.raises(ValueError, match="compensated_sums.*sprk-.*'yoshida4'"):
        if call == "Integrator":
            fputlab.Integrator(lat, lat.mode_state(), method="yoshida4", compensated_sums=True)
        elif call == "integrate":
            lat.integrate(1.0, method="yoshida4", compensated_sums=True)
        else:
            fputlab.io.simulate_to_file(lat, 1.0, tmp_path / "r.h5", method="yoshida4",
                                        compensated_sums=True)
    with pytest.raises(TypeError, match="compensated_sums"):
        fputlab.Integrator(lat, lat.mode_state(), method="yoshida4", compensated_sums="yes")
    assert fputlab.Integrator(lat, lat.mode_state()).compensation is None


def _orbit_and_deviation(lat):
    y = np.stack([lat.mode_state(1, 2.0), np.sin(1.0 + np.arange(2 * lat.N))])
    return y


@pytest.mark.skipif(not HAVE_SPRK, reason=f"SUNDIALS {SUNDIALS} has no SPRKStep")
def test_compensated_sums_reduce_roundoff_and_restart_bit_for_bit():
    lat = fputlab.Lattice(N=16, alpha=0.25)
    y0 = _orbit_and_deviation(lat)
    kw = dict(method="sprk-sofroniou10", dt=0.01)
    # less round-off: energy error of the compensated run well below the plain one's
    plain = lat.integrate(200.0, y0=y0[0], sample_every=20.0, **kw)
    comp = lat.integrate(200.0, y0=y0[0], sample_every=20.0, compensated_sums=True, **kw)
    assert comp.relative_energy_error.max() < 0.2 * plain.relative_energy_error.max()
    full = fputlab.Integrator(lat, y0, compensated_sums=True, **kw).advance(30.0)
    a = fputlab.Integrator(lat, y0, compensated_sums=True, **kw)
    a.advance(12.345)                       # off the grid: the internal state stays at 12.34
    steps, t, state, carry = a.steps, a.t, a.state, a.compensation
    assert steps == 1234 and carry.shape == state.shape
    assert 0 < np.abs(carry).max() < 1e-13  # the round-off the next step adds back
    b = fputlab.Integrator(lat, y0, compensated_sums=True, **kw)
    b.restore(steps, t, state, compensation=carry)
    assert b.advance(30.0).tobytes() == full.tobytes()
    c = fputlab.Integrator(lat, y0, compensated_sums=True, **kw)
    c.restore(steps, t, state)              # without the carry: round-off apart only
    d = np.abs(c.advance(30.0) - full).max()
    assert 0 < d < 1e-12
    with pytest.raises(ValueError, match="compensation"):
        fputlab.Integrator(lat, y0, **kw).restore(steps, t, state, compensation=carry)


@pytest.mark.skipif(not HAVE_SPRK, reason=f"SUNDIALS {SUNDIALS} has no SPRKStep")
def test_compensated_sums_checkpoint_restart_is_bit_for_bit(tmp_path):
    import h5py
    from fputlab.io import load, simulate_to_file
    lat = fputlab.Lattice(N=16, alpha=0.25)
    y0 = _orbit_and_deviation(lat)
    kw = dict(method="sprk-yoshida6", dt=0.01, sample_every=5.0, y0=y0[0], deviations=y0[1:],
              store_states=True, checkpoint_every_seconds=None, compensated_sums=True)
    simulate_to_file(lat, 60.0, tmp_path / "ref.h5", **kw)
    out, ck = tmp_path / "run.h5", tmp_path / "run.ckpt"
    simulate_to_file(lat, 25.0, out, checkpoint=ck, **kw)
    with h5py.File(ck) as f:
        assert f.attrs["compensated_sums"] == 1
        assert 0 < np.abs(f["compensation"][()]).max() < 1e-13
    with pytest.raises(ValueError, match="compensated_sums"):
        simulate_to_file(lat, 60.0, out, checkpoint=ck, **{**kw, "compensated_sums": False})
    s = simulate_to_file(lat, 60.0, out, checkpoint=ck, **kw)    # extends the finished run
    assert s.status == "completed" and s.resumed_from == 25.0
    ref, run = load(tmp_path / "ref.h5"), load(out)
    assert run.t.tobytes() == ref.t.tobytes()
    assert run.states.tobytes() == ref.states.tobytes()
    assert run.mode_energies.tobytes() == ref.mode_energies.tobytes()
