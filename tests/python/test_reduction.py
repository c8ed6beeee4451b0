"""Two-mode reduction (paper Sec. 4) against independent computations: the paper's numbers, a
brute-force numpy projection, Monte Carlo over the disorder, scipy integrators and root finders,
finite-difference Jacobians and the full lattice."""
import math

import numpy as np
import pytest
from scipy.integrate import solve_ivp
from scipy.optimize import brentq, fsolve

import fputlab
from fputlab import Lattice
from fputlab import reduction as red

MODELS = ["homogeneous", "hamiltonian", "nonlinear"]


def mode_matrix(N):
    j = np.arange(1, N + 1)
    return np.sqrt(2.0 / (N + 1)) * np.sin(np.outer(j, j) * np.pi / (N + 1))


def numpy_acceleration(model, x, v, alpha):
    """x'' of Eqs. (eqnmotions), (dis1), (varnonlin), written out independently of the library."""
    X = np.concatenate([[0.0], x, [0.0]])
    V = np.concatenate([[1.0], v, [1.0]])
    d, r = np.diff(X), np.diff(V * X)
    bond = {"homogeneous": d + alpha * d**2, "hamiltonian": r + alpha * r**2,
            "nonlinear": d + alpha * r**2}[model]
    return np.diff(bond)


def brute_force_coefficients(model, N, v, alpha, rng):
    """Project the acceleration at x = A[:, :2] Q onto modes 1, 2 for several Q, keep the even
    (quadratic) part and solve the least-squares problem for (c11, c22, c12) of each mode."""
    A = mode_matrix(N)
    Qs = rng.uniform(-2, 2, size=(8, 2))
    rows, rhs = [], []
    for q in Qs:
        x = A[:, :2] @ q
        even = 0.5 * (numpy_acceleration(model, x, v, alpha) + numpy_acceleration(model, -x, v, alpha))
        rows.append([q[0] ** 2, q[1] ** 2, q[0] * q[1]])
        rhs.append(A[:, :2].T @ even)
    sol, *_ = np.linalg.lstsq(np.array(rows), np.array(rhs), rcond=None)
    return sol[:, 0], sol[:, 1]     # a (mode 1), b (mode 2)


# ---- coefficients ---------------------------------------------------------------------------

def test_paper_coefficients_at_tau_zero():
    c = red.two_mode_coefficients(64, 0.25)
    assert round(c.A_tilde, 5) == 3.62805 and round(c.B_tilde, 5) == 0.90728   # paper, Fig. 5
    w1, w2 = 2 * np.sin(np.pi / 130), 2 * np.sin(2 * np.pi / 130)
    eps = w2 - 2 * w1
    assert c.eps == pytest.approx(eps, rel=1e-14) and eps < 0
    assert c.A[2] == pytest.approx(c.a[2] / eps) and c.A_tilde == pytest.approx(c.A[2] / (2 * w1))
    assert c.B_tilde == pytest.approx(c.B[0] / (2 * w2))
    # homogeneous selection rules: only Q1 Q2 drives mode 1 and Q1^2 drives mode 2
    np.testing.assert_allclose([c.a[0], c.a[1], c.b[1], c.b[2]], 0, atol=1e-18)


@pytest.mark.parametrize("model", MODELS)
def test_coefficients_match_brute_force_projection(model, rng):
    N = 23
    v = 1 + 0.15 * rng.standard_normal(N)
    c = red.two_mode_coefficients(N, 0.3, v, model=model)
    a, b = brute_force_coefficients(model, N, v if model != "homogeneous" else np.ones(N), 0.3, rng)
    np.testing.assert_allclose(c.a, a, rtol=1e-10, atol=1e-14)
    np.testing.assert_allclose(c.b, b, rtol=1e-10, atol=1e-14)
    if model != "homogeneous":   # the disorder must matter
        assert abs(c.a[0]) > 1e-6
    # the Lattice shortcut uses the lattice's own N, alpha, model and v
    lat = Lattice(N, 0.3, model, v=v) if model != "homogeneous" else Lattice(N, 0.3)
    np.testing.assert_array_equal(red.two_mode_coefficients(lat).raw, c.raw)


def test_one_realisation_is_a_quadratic_in_tau():
    N, seed = 64, 7
    z = (fputlab.draw_disorder(N, 30.0, seed) - 1) / 0.1           # the standard draws
    taus = np.array([0.0, 2.5, 6.0, 10.0, 13.0, 20.0, 30.0])
    vals = np.array([red.two_mode_coefficients(N, 0.25, 1 + t / 300 * z).raw for t in taus])
    for i in range(6):
        p = np.polyfit(taus, vals[:, i], 2)
        scale = np.abs(vals[:, i]).max()
        assert np.abs(np.polyval(p, taus) - vals[:, i]).max() < 1e-12 * scale
    # the closed-form quadratics of RealisationQuadratics give the same numbers
    rq = red.realisation_quadratics(N, 0.25, R=1, seed0=seed)
    np.testing.assert_allclose(rq.raw[0, :, 0] + rq.raw[0, :, 1] * 13.0 + rq.raw[0, :, 2] * 169.0,
                               vals[4], rtol=1e-10, atol=1e-20)
    At = red.RealisationQuadratics.evaluate(rq.A_tilde, taus)[0]
    np.testing.assert_allclose(At, vals[:, 2] * red.two_mode_coefficients(N).A_tilde
                               / red.two_mode_coefficients(N).a[2], rtol=1e-10)


@pytest.mark.parametrize("kind,tau", [("gaussian", 15.0), ("uniform", 8.0)])
def test_exact_moments_match_monte_carlo(kind, tau):
    N, K = 32, 20000
    rng = np.random.default_rng(2024)
    if kind == "gaussian":
        v = 1 + tau / 300 * rng.standard_normal((K, N))
    else:
        v = 1 + tau / 100 * rng.uniform(-1, 1, (K, N))
    samples = np.array([red.two_mode_coefficients(N, 0.25, row).raw for row in v])
    mom = red.coefficient_moments(tau, N, 0.25, kind=kind)
    mean, cov = mom.mean[0], mom.cov[0]
    se = samples.std(axis=0, ddof=1) / math.sqrt(K)
    assert np.all(np.abs(samples.mean(axis=0) - mean) < 4 * se)
    # variance: standard error of the sample variance from the sample fourth central moment
    dev = samples - samples.mean(axis=0)
    var, m4 = dev.var(axis=0, ddof=1), (dev**4).mean(axis=0)
    se_var = np.sqrt((m4 - var**2) / K)
    assert np.all(np.abs(var - np.diag(cov)) < 4 * se_var)
    # covariance of a_3 and b_1 (hence of A~ and B~)
    c23 = np.mean(dev[:, 2] * dev[:, 3])
    se_c = np.std(dev[:, 2] * dev[:, 3]) / math.sqrt(K)
    assert abs(c23 - cov[2, 3]) < 4 * se_c
    # the closed form is not the tau = 0 value: the disorder shifts the mean by many SEs
    assert np.abs(samples.mean(axis=0)[3] - red.two_mode_coefficients(N).b[0]) > 10 * se[3]


def test_critical_tolerance_three_ways():
    ct = red.critical_tolerance(64, 0.25, R=40, seed0=1)
    c0, c2 = ct.exact_B_coefficients
    # E[B~](tau) = c0 + c2 tau^2 vanishes at the exact tau_c, against the closed-form mean
    mom = red.coefficient_moments([ct.exact, 0.0], 64)
    assert abs(mom.B_tilde_mean[0]) < 1e-12 and mom.B_tilde_mean[1] == pytest.approx(0.90728, abs=5e-6)
    assert 9.5 < ct.exact < 11.0
    # the fit of an R-realisation mean is exact (a mean of quadratics): tiny SSE as in the paper
    assert ct.sse_B < 1e-20 and ct.fit_B[2] == pytest.approx(0.9072786, abs=1e-6)
    # each realisation's tau_c is a root of its own B~, checked with the C projection
    z = (fputlab.draw_disorder(64, 30.0, 3) - 1) / 0.1
    tc = ct.per_realisation[2]                                  # seed0 + 2 = 3
    c_at = red.two_mode_coefficients(64, 0.25, 1 + tc / 300 * z)
    assert abs(c_at.B_tilde) < 1e-10
    c_before = red.two_mode_coefficients(64, 0.25, 1 + 0.99 * tc / 300 * z)
    assert c_before.B_tilde > 0
    s = ct.summary()
    assert s["R"] == 40 and s["q05"] <= s["median"] <= s["q95"]


# ---- integrators ----------------------------------------------------------------------------

def test_two_mode_run_matches_scipy():
    c = red.two_mode_coefficients(32, 0.25, 1 + 0.03 * np.random.default_rng(1).standard_normal(32))
    (w1, w2), a, b = c.omega, c.a, c.b

    def f(t, y):
        q1, q2, p1, p2 = y
        return [p1, p2, -w1**2 * q1 + a[0] * q1**2 + a[1] * q2**2 + a[2] * q1 * q2,
                -w2**2 * q2 + b[0] * q1**2 + b[1] * q2**2 + b[2] * q1 * q2]

    ts = np.linspace(0, 3000, 7)
    run = red.two_mode_run(c, 3000, dt=0.02, times=ts, Q0=[3.0, 0.5], P0=[0.0, 0.1])
    ref = solve_ivp(f, (0, 3000), [3.0, 0.5, 0.0, 0.1], method="DOP853", t_eval=ts, rtol=1e-12,
                    atol=1e-12)
    np.testing.assert_allclose(run.Q, ref.y[:2].T, atol=1e-7)
    np.testing.assert_allclose(run.P, ref.y[2:].T, atol=1e-8)


@pytest.mark.parametrize("model", MODELS)
def test_galerkin_with_all_modes_is_the_lattice(model):
    N = 12
    lat = Lattice(N, 0.25, model, tau=10.0, seed=5) if model != "homogeneous" else Lattice(N, 0.25)
    ts = np.arange(0, 1001) * 0.01 * 5                       # on the dt grid, t <= 50
    full = fputlab.integrate(lat, ts[-1], dt=0.01, times=ts, store_states=True)
    g = red.Galerkin(lat, N)
    A = mode_matrix(N)
    x0 = lat.mode_state()[:N]
    run = g.run(ts[-1], dt=0.01, times=ts, Q0=A @ x0)
    x = run.Q @ A.T
    assert np.abs(x - full.states[:, :N]).max() < 1e-11
    np.testing.assert_allclose(run.mode_energies, full.mode_energies, atol=1e-13)


def test_galerkin_two_modes_is_the_two_mode_system():
    lat = Lattice(64, 0.25, "nonlinear", tau=5.0, seed=2)
    g, c = red.Galerkin(lat, 2), red.two_mode_coefficients(lat)
    q = np.array([1.7, -0.4])
    expected = -np.array(c.omega) ** 2 * q + np.array(
        [c.a @ [q[0] ** 2, q[1] ** 2, q[0] * q[1]], c.b @ [q[0] ** 2, q[1] ** 2, q[0] * q[1]]])
    np.testing.assert_allclose(g.acceleration(q), expected, rtol=1e-12, atol=1e-15)


def test_galerkin_bad_input():
    lat = Lattice(8, 0.25, "nonlinear", tau=5.0, seed=1)
    for M in (0, -1, 9, float("nan"), 2.5):
        with pytest.raises(ValueError, match="M"):
            red.Galerkin(lat, M)
    with pytest.raises(TypeError, match="M"):
        red.Galerkin(lat, "two")
    g = red.Galerkin(lat, 3)
    with pytest.raises(ValueError, match=r"Q0\[1\]"):
        g.run(1.0, Q0=[1.0, np.nan, 0.0])
    with pytest.raises(ValueError, match="Q0"):
        g.run(1.0, Q0=[1.0, 0.0])
    with pytest.raises(ValueError, match="dt"):
        g.run(1.0, dt=float("nan"))
    with pytest.raises(ValueError, match="t_end"):
        g.run(float("nan"))
    with pytest.raises(ValueError, match=r"Q\[0\]"):
        g.acceleration([np.inf, 0, 0])


def test_two_mode_blow_up_is_reported():
    c = red.TwoModeCoefficients(64, np.array([0.5, 0.0, 0.0]), np.zeros(3))
    with pytest.raises(fputlab.IntegrationError, match="between t") as err:
        red.two_mode_run(c, 1e4, dt=0.01, sample_every=10.0, Q0=[1.0, 0.0])
    partial = err.value.result
    assert 0 < partial.t.size < 1001 and np.all(np.isfinite(partial.Q))
    back = red.two_mode_run(c, 1e4, dt=0.01, sample_every=10.0, Q0=[1.0, 0.0], on_failure="return")
    assert not back.completed and back.t.size == partial.t.size


# ---- envelope equations ---------------------------------------------------------------------

def test_envelope_equations_track_the_two_mode_system():
    """Multiple scales: with detuning and nonlinearity both O(lambda eps) (amplitude lambda Q_1(0),
    omega_2 = 2 omega_1 + lambda eps) the envelope error relative to the amplitude is O(lambda) on
    a fixed slow-time window."""
    c = red.two_mode_coefficients(64, 0.25)
    w1, eps = c.omega[0], c.eps
    rel = []
    for lam in (1.0, 0.5, 0.25):
        e = lam * eps
        omega = (w1, 2 * w1 + e)
        At, Bt = c.a[2] / (e * 2 * w1), c.b[0] / (e * 2 * omega[1])
        Q1 = lam * math.sqrt(65 / 2)
        t_end = 1.0 / abs(e)
        run = red.two_mode_run(c, t_end, dt=0.1, sample_every=2.0, Q0=[Q1, 0.0], omega=omega)
        env = red.envelope_run(At, Bt, e * t_end, q0=[Q1 / 2, 0.0], dT=1e-3)
        rel.append(red.envelope_error(run, env, e).max() / Q1)
        # mode 2 really is excited: the test is not about a trivial solution
        assert np.abs(run.Q[:, 1]).max() > 0.3 * Q1
    assert rel[0] < 0.01
    assert 1.8 < rel[0] / rel[1] < 2.2 and 1.8 < rel[1] / rel[2] < 2.2


def test_envelope_rk4_against_scipy():
    run = red.envelope_run(3.6, 0.9, -2.0, dT=1e-3)

    def f(T, y):
        q = y[:2] + 1j * y[2:]
        d = red.envelope_rhs(q, 3.6, 0.9)
        return np.concatenate([d.real, d.imag])

    ref = solve_ivp(f, (0, -2.0), [math.sqrt(65 / 8), 0, 0, 0], method="DOP853", rtol=1e-12,
                    atol=1e-12, t_eval=[-0.37, -1.2, -2.0])
    q = run.at(ref.t)                                   # interpolated between grid points
    np.testing.assert_allclose(q.real, ref.y[:2].T, atol=1e-8)
    np.testing.assert_allclose(q.imag, ref.y[2:].T, atol=1e-8)


# ---- reduced system -------------------------------------------------------------------------

def paper_field(A, B, C):
    """Eqs. (delta3), (theta3) with P = C + k Delta, transcribed from the paper."""
    k = (A - B) / (A + B)

    def f(y):
        D, th = y
        P = C + k * D
        root = np.sqrt(2 * (P - D))
        return np.array([root * np.sin(2 * th) * (P + D) * (A + B) / 2,
                         -(2 * A * np.cos(2 * th) * (D - P) + B * np.cos(2 * th) * (D + P) - root)
                         / (2 * root)])
    return f


@pytest.mark.parametrize("A,B,expected", [
    (3.63, 0.91, [(0.0, 5.09, "centre"), (np.pi / 2, 4.34, "centre")]),
    (5.3932, -0.0015, [(np.pi / 2, 9.1274, "centre"), (np.pi / 2, 15.4383, "saddle")]),
])
def test_paper_equilibria(A, B, expected):
    rs = red.ReducedSystem(A, B, N=64)
    assert rs.C == pytest.approx(65 / 8 - (A - B) / (A + B) * 65 / 8)   # P = Delta = r1^2 at t = 0
    eqs = rs.equilibria()
    digits = 2 if A == 3.63 else 4
    f = paper_field(A, B, rs.C)
    for e, (theta, delta, kind) in zip(eqs, expected):
        assert e.theta == theta and round(e.delta, digits) == delta and e.kind == kind
        assert e.well_defined
        assert np.abs(f([e.delta, e.theta])).max() < 1e-10
        # a root finder started off the equilibrium lands on it
        root = fsolve(f, [e.delta * 1.03, e.theta + 0.05], xtol=1e-13)
        assert root[0] == pytest.approx(e.delta, abs=1e-8)
        assert np.mod(root[1] - e.theta, np.pi) == pytest.approx(0, abs=1e-8) or \
            np.mod(root[1] - e.theta, np.pi) == pytest.approx(np.pi, abs=1e-8)
        # eigenvalues against a finite-difference Jacobian of the transcribed field
        h = 1e-6
        J = np.column_stack([(f([e.delta, e.theta] + h * d) - f([e.delta, e.theta] - h * d)) / (2 * h)
                             for d in np.eye(2)])
        ev = np.sort_complex(np.linalg.eigvals(J))
        np.testing.assert_allclose(ev, np.sort_complex(np.array(e.eigenvalues)), atol=1e-6)


@pytest.mark.parametrize("A,B", [(3.63, 0.91), (4.97, 0.05), (5.3932, -0.0015), (-0.4, 0.3),
                                 (0.05, 0.05)])
def test_closed_forms_are_all_the_equilibria(A, B):
    """Scan theta' along the lines sin 2 theta = 0 (where Delta' vanishes) with brentq: the roots
    inside the well-defined region are exactly the closed-form equilibria."""
    rs = red.ReducedSystem(A, B, N=64)
    f = paper_field(A, B, rs.C)
    lo, hi = rs.region()
    lo, hi = max(lo, -200.0), min(hi, 200.0)
    found = []
    for theta in (0.0, np.pi / 2):
        grid = np.linspace(lo, hi, 20001)[1:-1]
        g = np.array([f([d, theta])[1] for d in grid])
        for i in np.flatnonzero(np.isfinite(g[:-1]) & np.isfinite(g[1:]) & (g[:-1] * g[1:] < 0)):
            found.append((theta, brentq(lambda d: f([d, theta])[1], grid[i], grid[i + 1],
                                        xtol=1e-13)))
    closed = sorted((e.theta, e.delta) for e in rs.equilibria() if e.well_defined)
    found = sorted(found)
    assert [t for t, _ in found] == [t for t, _ in closed]
    np.testing.assert_allclose([d for _, d in found], [d for _, d in closed], atol=1e-7)
    # and the vectorised map used for Figs. 7-8 agrees
    m = red.equilibrium_map(A, B, rs.r1sq)
    for e in rs.equilibria():
        assert float(m[f"delta{e.j}"]) == pytest.approx(e.delta, rel=1e-9)
        assert bool(m[f"well_defined{e.j}"]) == e.well_defined


def test_bifurcation_curves_and_classification():
    r1sq = red.r1_squared(64)
    assert r1sq == 65 / 8
    cv = red.bifurcation_curves(np.array([2.0]), r1sq)
    assert 1 + 12 * 2.0 * cv["blue"][0] * r1sq == pytest.approx(0)
    assert 1 - 4 * 2.0 * cv["red"][0] * r1sq == pytest.approx(0)
    # on the red curve Delta_2 reaches the boundary r_1 = 0 (Delta_crit^2); above it both are centres
    A = 2.0
    B = cv["red"][0]
    rs = red.ReducedSystem(A, B, N=64)
    assert rs.equilibria()[1].delta == pytest.approx(rs.delta_crit[1], rel=1e-9)
    assert red.classify(3.63, 0.91) == 1 and red.classify(5.3932, -0.0015) == 2
    assert red.classify(2.0, 0.5 * B) == 3 and red.classify(2.0, -0.1) == 0


def test_reduced_constant_and_invariant_are_conserved():
    rs = red.ReducedSystem(3.63, 0.91, N=64)

    def f(T, y):
        return rs.rhs(*y)

    y0 = [rs.P_of(4.0), 4.0, 1.0]          # a regular point of the well-defined region
    sol = solve_ivp(f, (0, 3.0), y0, method="DOP853", rtol=1e-11, atol=1e-12, dense_output=True)
    P, D, th = sol.sol(np.linspace(0, 3.0, 200))
    assert np.ptp(D) > 1.0                             # it moves
    C = P - rs.k * D
    assert np.abs(C - rs.C).max() < 1e-8
    inv = (P + D) / 2 * (1 + 2 * rs.A * np.sqrt((P - D) / 2) * np.cos(2 * th))
    assert np.ptp(inv) < 1e-8
    # and along the envelope equations from the paper's initial state (through r_2 = 0)
    run = red.envelope_run(3.63, 0.91, 2.0, dT=1e-3)
    P, D, th = red.to_reduced(run.q)
    assert np.abs(P - rs.k * D - rs.C).max() < 1e-9
    np.testing.assert_allclose(rs.invariant(D, th), rs.r1sq, atol=1e-8)


def test_blow_up_orbit_escapes_past_the_saddle():
    rs = red.ReducedSystem(5.3932, -0.0015, N=64)
    T, D, th, P = rs.trajectory(200.0, P_max=60.0)
    assert D[0] == pytest.approx(rs.r1sq) and D.max() > 50      # starts at the bottom, escapes
    assert rs.region() == (pytest.approx(rs.r1sq), math.inf)


# ---- figures (smoke: each writes a PNG quickly) ----------------------------------------------

def test_figures_write_pngs(tmp_path):
    from fputlab import figures_reduction as F
    r4 = F.fig4(tmp_path / "f4.png", t_end=2000.0, Ms=(2, 4), taus=(0.0, 10.0))
    assert r4["tau=10,M=4"]["completed"]
    r5 = F.fig5(tmp_path / "f5.png", R=20)
    assert r5["fit"] > 0
    for n in (6, 7, 8, 9, 10):
        kwargs = {"t_end": 3e4} if n == 6 else {}
        F.FIGURES[n](tmp_path / f"f{n}.png", **kwargs)
    for name in ["f4", "f5", "f6", "f7", "f8", "f9", "f10"]:
        data = (tmp_path / f"{name}.png").read_bytes()
        assert data[:8] == b"\x89PNG\r\n\x1a\n" and len(data) > 10_000


def test_paper_like_seed_is_what_the_figures_say():
    from fputlab.figures_reduction import PAPER_LIKE_SEED
    c = red.two_mode_coefficients(Lattice(64, 0.25, "nonlinear", tau=10.0, seed=PAPER_LIKE_SEED))
    assert abs(c.A_tilde - 4.97) < 0.05 and abs(c.B_tilde - 0.05) < 0.002
