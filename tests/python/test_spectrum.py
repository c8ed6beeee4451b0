"""Lyapunov spectrum, covariant Lyapunov vectors and MEGNO against independent computations:
the symplectic structure of the spectrum, a plain numpy/scipy Benettin run on the variational
equations written out here, lyapunov()'s mLE, matrix products with known Oseledets vectors,
the covariance of the CLVs under an independently integrated tangent flow, and MEGNO's limits."""
import math

import numpy as np
import pytest
from scipy.integrate import solve_ivp

import fputlab
from fputlab.chaos import (covariant_lyapunov_vectors, covariant_vectors_from_qr,
                           inverse_participation_ratio, kaplan_yorke_dimension, ks_entropy,
                           lyapunov, lyapunov_spectrum)


def chaotic_lattice(model, N, seed=4, amplitude=1.5):
    """An FPUT-beta chain (no escape) at high energy from a random state: chaotic within
    t ~ 100."""
    if model == "homogeneous":
        lat = fputlab.Lattice(N, 0.0, model, beta=1.0)
    else:
        lat = fputlab.Lattice(N, 0.0, model, beta=1.0, tau=20.0, seed=seed)
    return lat, amplitude * np.random.default_rng(seed).uniform(-1, 1, 2 * N)


def flow(model, v, alpha, beta):
    """The equations of motion and their variational equations, from the paper's equations
    (docs/conventions.md), for y = [x, p] and deviation vectors as columns of W (2N x k)."""
    N = v.size
    mass = v if model == "hamiltonian" else np.ones(N)
    V = np.concatenate([[1.0], v, [1.0]])

    def bonds(x):
        X = np.concatenate([[0.0], x, [0.0]])
        d, r = np.diff(X), np.diff(V * X)
        lin, nl = (r, r) if model == "hamiltonian" else (d, r if model == "nonlinear" else d)
        return lin, nl

    def dbonds(dx):
        dX = np.concatenate([np.zeros((1,) + dx.shape[1:]), dx, np.zeros((1,) + dx.shape[1:])])
        dd, dr = np.diff(dX, axis=0), np.diff(V[:, None] * dX, axis=0)
        return (dr, dr) if model == "hamiltonian" else (dd, dr if model == "nonlinear" else dd)

    def f(t, z):
        x, p = z[:N], z[N:2 * N]
        W = z[2 * N:].reshape(2 * N, -1)
        lin, nl = bonds(x)
        force = mass * np.diff(lin + alpha * nl**2 + beta * nl**3)
        dlin, dnl = dbonds(W[:N])
        curv = (2 * alpha * nl + 3 * beta * nl**2)[:, None]
        dforce = mass[:, None] * np.diff(dlin + curv * dnl, axis=0)
        return np.concatenate([p / mass, force, (W[N:] / mass[:, None]).ravel(), dforce.ravel()])
    return f


def numpy_spectrum(lat, y0, w0, T, tau=1.0):
    """Benettin's method written out: scipy DOP853 on the variational equations, numpy QR."""
    f = flow(lat.model, lat.v, lat.alpha, lat.beta)
    z, Q = y0.copy(), np.linalg.qr(w0.T)[0]
    logsum = np.zeros(w0.shape[0])
    for m in range(int(round(T / tau))):
        sol = solve_ivp(f, (m * tau, (m + 1) * tau), np.concatenate([z, Q.ravel()]),
                        method="DOP853", rtol=1e-12, atol=1e-12)
        end = sol.y[:, -1]
        z = end[:z.size]
        Q, R = np.linalg.qr(end[z.size:].reshape(z.size, -1))
        logsum += np.log(np.abs(np.diag(R)))
    return logsum / T


@pytest.mark.parametrize("model,N", [("homogeneous", 4), ("hamiltonian", 5), ("nonlinear", 4)])
def test_whole_spectrum_matches_a_numpy_benettin_run(model, N, rng):
    # a moderate amplitude: the orbits of the two computations separate slowly enough over T
    lat, y0 = chaotic_lattice(model, N, amplitude=1.0)
    w0 = rng.standard_normal((2 * N, 2 * N))
    ref = numpy_spectrum(lat, y0, w0, 25.0)
    assert ref[0] > 0.05
    for method, dt in (("yoshida4", 0.002), ("dop853", None)):
        res = lyapunov_spectrum(lat, 25.0, y0=y0, w0=w0, method=method, dt=dt, rtol=1e-12,
                                atol=1e-12)
        assert res.completed and res.exponents.shape == (2 * N,)
        np.testing.assert_allclose(res.exponents, ref, atol=2e-6, err_msg=method)


@pytest.mark.parametrize("model", ["homogeneous", "hamiltonian"])
def test_hamiltonian_spectrum_pairs_and_sums_to_zero(model):
    N = 5
    lat, y0 = chaotic_lattice(model, N)
    res = lyapunov_spectrum(lat, 3000.0, y0=y0, method="srkn14a6", dt=0.05)
    lam = res.exponents
    assert abs(lam.sum()) < 1e-12                  # det of the symplectic tangent map is 1
    assert lam[0] > 0.02                           # chaotic
    pairs = lam + lam[::-1]
    assert np.max(np.abs(pairs)) < 0.05 * lam[0], pairs
    assert np.all(np.diff(lam[:N - 1]) < 0)        # descending (the QR order)
    assert res.ks_entropy == pytest.approx(lam[lam > 0].sum())
    assert res.history.shape == (2 * N, res.t.size) and res.history[:, -1] == pytest.approx(lam)


def test_model3_spectrum_sums_to_zero():
    lat, y0 = chaotic_lattice("nonlinear", 6)
    res = lyapunov_spectrum(lat, 1000.0, y0=y0, method="yoshida4", dt=0.01)
    assert abs(res.exponents.sum()) < 1e-12        # the kinetic split preserves volume
    assert res.exponents[0] > 0.02


def test_first_exponent_is_lyapunovs_mle(rng):
    lat, y0 = chaotic_lattice("homogeneous", 6)
    w0 = rng.standard_normal((3, 12))
    res = lyapunov_spectrum(lat, 500.0, y0=y0, w0=w0, k=3)
    ref = lyapunov(lat, 500.0, y0=y0, w0=w0[:1], n_dev=1, blowup_stretch=-1)
    assert res.exponents[0] == pytest.approx(ref.mle_final, rel=1e-9)
    assert res.mle == res.exponents[0]


def test_transient_and_result_object():
    lat, y0 = chaotic_lattice("homogeneous", 4)
    res = lyapunov_spectrum(lat, 50.0, y0=y0, t_transient=10.0, n_samples=10)
    # the transient moves the start: the same as starting from the orbit at t = 10
    y10 = fputlab.integrate(lat, 10.0, y0=y0, sample_every=10.0, store_states=True).states[-1]
    same = lyapunov_spectrum(lat, 50.0, y0=y10[:8], t0=10.0, n_samples=10)
    np.testing.assert_allclose(res.exponents, same.exponents, rtol=1e-10)
    assert res.t_final == pytest.approx(60.0)
    text = repr(res)
    assert "\n" not in text and "lambda_1=" in text and "k=8" in text
    ds = res.to_xarray()
    assert ds["history"].dims == ("exponent", "t") and ds.sizes["exponent"] == 8


def test_bad_input_names_the_parameter():
    lat = fputlab.Lattice(4)
    with pytest.raises(ValueError, match="k must be"):
        lyapunov_spectrum(lat, 10.0, k=9)
    with pytest.raises(ValueError, match="w0"):
        lyapunov_spectrum(lat, 10.0, k=2, w0=np.zeros((3, 8)))
    with pytest.raises(ValueError, match="renorm"):
        lyapunov_spectrum(lat, 10.0, renormalize_every=-1.0)
    with pytest.raises(TypeError, match="lattice"):
        lyapunov_spectrum("lattice", 10.0)


def test_entropy_and_kaplan_yorke_closed_forms():
    lam = [0.5, 0.1, -0.2, -0.6]
    assert ks_entropy(lam) == pytest.approx(0.6)
    assert kaplan_yorke_dimension(lam) == pytest.approx(3 + 0.4 / 0.6)
    assert kaplan_yorke_dimension([-0.1, -0.2]) == 0.0
    assert kaplan_yorke_dimension([0.3, 0.1]) == 2.0


# ---- covariant Lyapunov vectors ---------------------------------------------------------------

def forward_qr(mats, k, rng):
    """Plain forward QR through a sequence of matrices: Q_i (rows) and R_i (positive diagonal)."""
    Q = np.linalg.qr(rng.standard_normal((mats[0].shape[0], k)))[0]
    Qs, Rs = [Q.T.copy()], []
    for A in mats:
        Q, R = np.linalg.qr(A @ Q)
        s = np.sign(np.diag(R))
        Q, R = Q * s, s[:, None] * R
        Qs.append(Q.T.copy())
        Rs.append(R)
    return np.array(Qs), np.array(Rs)


def test_clvs_of_a_constant_matrix_are_its_eigenvectors(rng):
    P = rng.standard_normal((4, 4))
    A = P @ np.diag([2.0, 1.3, 0.7, 0.4]) @ np.linalg.inv(P)
    Qs, Rs = forward_qr([A] * 120, 4, rng)
    n = 20                                       # window: steps 50..69, backward transient 50
    V = covariant_vectors_from_qr(Qs[50:50 + n], Rs[50:119])
    E = P / np.linalg.norm(P, axis=0)
    for i in range(n):
        cos = np.abs(np.sum(V[i] * E.T, axis=1))
        np.testing.assert_allclose(cos, 1.0, atol=1e-10)


def test_clvs_of_a_random_product_are_covariant(rng):
    """A_i V_i is parallel to V_{i+1} for a product of random matrices (no closed form), and the
    first CLV is the first (backward) Lyapunov vector."""
    mats = [np.diag([1.5, 1.0, 0.6]) + 0.3 * rng.standard_normal((3, 3)) for _ in range(90)]
    Qs, Rs = forward_qr(mats, 3, rng)
    V = covariant_vectors_from_qr(Qs[30:50], Rs[30:89])
    for i in range(19):
        w = mats[30 + i] @ V[i].T
        w /= np.linalg.norm(w, axis=0)
        np.testing.assert_allclose(np.abs(np.sum(w * V[i + 1].T, axis=0)), 1.0, atol=1e-10)
    np.testing.assert_allclose(np.abs(np.sum(V[:, 0] * Qs[30:50, 0], axis=1)), 1.0, atol=1e-12)


def test_lattice_clvs_are_covariant_under_the_tangent_flow():
    """The CLV at t_i, carried by the variational equations (scipy, written out in this file)
    to t_{i+1}, is the CLV there up to its norm."""
    lat, y0 = chaotic_lattice("homogeneous", 4)
    res = covariant_lyapunov_vectors(lat, 4.0, t_forward=40.0, t_backward=40.0, y0=y0, dt=0.002)
    assert res.vectors.shape == (4, 8, 8) and res.t.tolist() == [40.0, 41.0, 42.0, 43.0]
    f = flow("homogeneous", lat.v, lat.alpha, lat.beta)
    for i in range(3):
        z = np.concatenate([res.states[i], res.vectors[i].T.ravel()])
        end = solve_ivp(f, (res.t[i], res.t[i + 1]), z, method="DOP853", rtol=1e-12,
                        atol=1e-12).y[:, -1]
        W = end[8:].reshape(8, 8)
        W /= np.linalg.norm(W, axis=0)
        cos = np.abs(np.sum(W * res.vectors[i + 1].T, axis=0))
        np.testing.assert_allclose(cos, 1.0, atol=1e-6)
    assert np.all((res.ipr >= 1 / 4 - 1e-12) & (res.ipr <= 1 + 1e-12))


def test_clvs_with_memory_mapped_factors(tmp_path):
    lat, y0 = chaotic_lattice("homogeneous", 4)
    kw = dict(t_forward=10.0, t_backward=10.0, y0=y0, k=3)
    a = covariant_lyapunov_vectors(lat, 3.0, **kw)
    b = covariant_lyapunov_vectors(lat, 3.0, scratch_dir=tmp_path, **kw)
    np.testing.assert_array_equal(np.asarray(a.vectors), np.asarray(b.vectors))
    assert any(tmp_path.iterdir())
    del b


def test_inverse_participation_ratio_closed_forms():
    one = np.zeros(8)
    one[2] = 1.0
    assert inverse_participation_ratio(one) == pytest.approx(1.0)
    assert inverse_participation_ratio(np.ones(8)) == pytest.approx(1 / 4)
    half = np.array([1.0, 1.0, 0, 0, 0, 0, 0, 0])
    assert inverse_participation_ratio(half) == pytest.approx(0.5)


# ---- MEGNO -------------------------------------------------------------------------------------

def test_megno_tends_to_two_on_a_quasi_periodic_orbit():
    lat = fputlab.Lattice(2, 0.0, beta=1.0)
    res = lyapunov(lat, 1e4, y0=lat.mode_state(1, 1.0), renorm_interval=0.1, n_samples=12)
    assert res.classify() == "regular"
    assert res.megno.shape == res.t.shape
    assert abs(res.megno_final - 2.0) < 0.05
    assert np.all(np.diff(res.megno[-4:]) > 0)    # approaching 2 from below


def test_megno_grows_as_lambda_t_over_two_on_a_chaotic_orbit():
    lat, y0 = chaotic_lattice("homogeneous", 4)
    res = lyapunov(lat, 1e4, y0=y0, renorm_interval=0.1, n_samples=12, blowup_stretch=-1)
    assert res.classify() == "chaotic"
    slope = (res.megno[-1] - res.megno[-3]) / (res.t[-1] - res.t[-3])
    assert slope == pytest.approx(res.mle_final / 2, rel=0.1)


def test_megno_of_a_harmonic_chain_stays_bounded():
    """Linear dynamics: the deviation vector does not grow, so MEGNO -> 0 (a stable orbit)."""
    lat = fputlab.Lattice(6, 0.0)
    res = lyapunov(lat, 2e3, renorm_interval=0.1, n_samples=8)
    assert abs(res.megno_final) < 0.1


def test_megno_of_the_batched_lanes_is_the_single_orbits():
    from fputlab.chaos import lyapunov_batch
    lats = [fputlab.Lattice(8, 0.25, "nonlinear", tau=10.0, seed=s) for s in (1, 2, 3)]
    batch = lyapunov_batch(lats, 500.0, method="srkn14a6", dt=0.5, n_samples=20)
    for lat, b in zip(lats, batch):
        one = lyapunov(lat, 500.0, method="srkn14a6", dt=0.5, n_samples=20)
        assert b.megno.shape == b.t.shape
        np.testing.assert_allclose(b.megno, one.megno, rtol=1e-10, atol=1e-12)


def test_megno_in_the_chaos_study():
    from fputlab.chaos import chaotic_fraction
    out = chaotic_fraction(Ns=(8,), realisations=2, t_end=300.0, workers=1)
    ds = out.to_xarray()
    assert "megno" in ds and "megno_t" in ds
    for seed, orbit in zip((1, 2), out.orbits(8)):
        lat = fputlab.Lattice(8, 0.25, "nonlinear", tau=10.0, seed=seed)
        one = lyapunov(lat, 300.0, method="srkn14a6", dt=0.5, stop_when_chaotic=True)
        # the lanes and the single-orbit handle agree; the study samples on its own log grid
        assert float(ds["megno"].sel(N=8, seed=seed).squeeze()) == pytest.approx(
            one.megno_final, rel=1e-10)
        assert orbit.megno.shape == orbit.t.shape and np.all(np.isfinite(orbit.megno))


# ---- the spectrum study kind --------------------------------------------------------------------

def test_spectrum_study_is_lyapunov_spectrum_per_realisation_and_continues(tmp_path):
    from fputlab.chaos import lyapunov_spectra
    kw = dict(Ns=(4, 6), realisations=2, tau=10.0, model="hamiltonian", alpha=0.0, beta=1.0,
              amplitude=3.0, workers=1)
    out = lyapunov_spectra(t_end=200.0, **kw)
    ds = out.to_xarray()
    assert ds["exponents"].dims == ("N", "tau", "seed", "exponent") and ds.sizes["exponent"] == 12
    for N in (4, 6):
        for seed in (1, 2):
            lat = fputlab.Lattice(N, 0.0, "hamiltonian", beta=1.0, tau=10.0, seed=seed)
            one = lyapunov_spectrum(lat, 200.0, y0=lat.mode_state(1, 3.0), method="srkn14a6",
                                    dt=0.5)
            got = ds["exponents"].sel(N=N, seed=seed).squeeze().values
            np.testing.assert_array_equal(got[:2 * N], one.exponents)
            assert np.all(np.isnan(got[2 * N:]))
            assert float(ds["ks_entropy"].sel(N=N, seed=seed).squeeze()) == one.ks_entropy
    rows = out.summary()
    assert [(r["N"], r["n"]) for r in rows] == [(4, 2), (6, 2)]
    # in a work_dir, to 200 and then on to 400: bit for bit the run straight to 400
    lyapunov_spectra(t_end=200.0, work_dir=tmp_path / "s", **kw)
    resumed = lyapunov_spectra(t_end=400.0, work_dir=tmp_path / "s", **kw).to_xarray()
    straight = lyapunov_spectra(t_end=400.0, **kw).to_xarray()
    np.testing.assert_array_equal(resumed["exponents"].values, straight["exponents"].values)
    np.testing.assert_array_equal(resumed["history"].values, straight["history"].values)
