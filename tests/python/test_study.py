"""The chaos study (fputlab.chaos.study): the default method classifies as the paper's methods do,
pieces resume bit for bit, a study directory is only continued with its own parameters, the
class table counts what was reached."""
import numpy as np
import pytest

from fputlab import Lattice, chaos
from fputlab.chaos.study import ChaosStudy, StudySpec

DEFAULT = StudySpec()


@pytest.mark.parametrize("method,dt", [("yoshida4", 0.01), (DEFAULT.method, DEFAULT.dt),
                                       ("aba864", 0.05)])
def test_methods_agree_on_a_chaotic_orbit(method, dt):
    # homogeneous N = 8, mode 1 at 4x the paper's amplitude: weakly chaotic, SALI < 1e-8 after
    # a few 1e4 (when exactly depends on the trajectory, not on the class)
    lat = Lattice(8, 0.25)
    res = chaos.lyapunov(lat, 1.2e5, y0=4 * lat.mode_state(), method=method, dt=dt,
                         stop_when_chaotic=True, n_samples=40)
    assert res.classify() == "chaotic", (method, res.t_final)
    assert 1e4 < res.t_chaotic < 1.2e5


@pytest.mark.parametrize("method,dt", [("yoshida4", 0.01), (DEFAULT.method, DEFAULT.dt),
                                       ("dop853", None)])
def test_methods_agree_on_model3_regular_and_blowup(method, dt):
    # model 3 (the paper's chaos study), tau = 10 %, N = 8: the paper's initial state is regular;
    # at 4.5x its amplitude seed 1 escapes over the barrier after t ~ 1.5e3 (when exactly is
    # trajectory-sensitive: 1554 with srkn14a6, 1886 with Yoshida 4). The splitting schemes'
    # tangent map and DOP853 on the variational equations (the paper's method) agree on the
    # classes.
    lat = Lattice(8, 0.25, "nonlinear", tau=10.0, seed=1)
    reg = chaos.lyapunov(lat, 3e3, method=method, dt=dt, n_samples=30)
    assert reg.classify() == "regular" and reg.sali.min() > 1e-3
    esc = chaos.lyapunov(lat, 3e3, y0=4.5 * lat.mode_state(), method=method, dt=dt)
    assert esc.classify() == "blow-up" and not esc.chaotic
    assert 1e3 < esc.t_blowup < 3e3 and np.all(np.isfinite(esc.mle))


def test_study_pieces_resume_bit_for_bit_and_count_classes(tmp_path):
    work = tmp_path / "study"
    study = ChaosStudy(work, Ns=(4, 64), realisations=2, t_end=4e4, n_samples=40)
    study.run(t_until=1e3, progress=False, workers=2)
    assert study.reached() == 1e3
    rows = {(r["t"], r["N"]): r for r in study.table((1e3, 4e4))}
    assert rows[(1e3, 4)]["regular"] == 2 and rows[(4e4, 64)]["not reached"] == 2
    # a second process continues the same study (the parameters come from the directory), one
    # orbit at a time instead of in the batched kernel's lanes: the numbers are the same
    again = ChaosStudy(work, batched=False)
    st = again.run(progress=False, workers=2)
    assert st["done"] == 4 and again.reached() == 4e4
    res = again.results()
    for N in (4, 64):
        for r in res[N]:
            lat = Lattice(N, 0.25, "nonlinear", tau=10.0, seed=r.params["seed"])
            direct = chaos.lyapunov(lat, 4e4, method=DEFAULT.method, dt=DEFAULT.dt,
                                    n_samples=40, stop_when_chaotic=True)
            np.testing.assert_array_equal(direct.mle, r.mle)
            np.testing.assert_array_equal(direct.sali, r.sali)
            assert direct.classify() == r.classify()
    # N = 64 seed 1 escapes at t ~ 3.2e4 (model 3, tau = 10 %): counted as blow-up, not chaos
    counts = again.classes(4e4)
    assert counts[64]["blow-up"] == 1 and counts[64]["chaotic"] == 0
    assert sum(counts[4].values()) == 2 and counts[4]["regular"] == 2


def test_study_refuses_other_parameters_and_bad_input(tmp_path):
    work = tmp_path / "s"
    ChaosStudy(work, Ns=(4,), realisations=1, t_end=100.0)
    with pytest.raises(ValueError, match="t_end"):
        ChaosStudy(work, t_end=200.0)
    with pytest.raises(TypeError, match="bogus"):
        ChaosStudy(tmp_path / "x", bogus=1)
    with pytest.raises(ValueError, match="realisations"):
        ChaosStudy(tmp_path / "y", realisations=0)
    with pytest.raises(ValueError, match="Ns"):
        ChaosStudy(tmp_path / "z", Ns=(4, 4))
    with pytest.raises(ValueError, match="method"):
        ChaosStudy(tmp_path / "w", method="nope")
    (tmp_path / "file").write_text("x")
    with pytest.raises(ValueError, match="not a directory"):
        ChaosStudy(tmp_path / "file")
    s = ChaosStudy(work)
    with pytest.raises(ValueError, match="t_until"):
        s.run(t_until=-1.0, progress=False)
    # a damaged orbit file is reported, never silently replaced
    s.run(progress=False, workers=1)
    f = next(work.glob("tasks/*.h5"))
    f.write_bytes(f.read_bytes()[:50])
    with pytest.raises(ValueError, match="unreadable"):
        ChaosStudy(work).results()


def test_batched_and_single_orbit_pieces_give_the_same_orbits(tmp_path):
    # the same study run (a) in batched pieces throughout, (b) single-orbit then batched, with
    # a pending chaos confirmation and a blow-up inside: identical state files' numbers
    kw = dict(Ns=(8, 64), realisations=5, t_end=4e4, n_samples=40)
    a = ChaosStudy(tmp_path / "a", **kw)
    a.run(t_until=5e3, progress=False, workers=2)
    a.run(progress=False, workers=2)
    b = ChaosStudy(tmp_path / "b", batched=False, **kw)
    b.run(t_until=5e3, progress=False, workers=2)
    ChaosStudy(tmp_path / "b").run(progress=False, workers=2)
    ra, rb = a.results(), b.results()
    for N in (8, 64):
        for x, y in zip(ra[N], rb[N]):
            np.testing.assert_array_equal(x.mle, y.mle)
            np.testing.assert_array_equal(x.sali, y.sali)
            assert (x.classify(), x.t_final, x.steps) == (y.classify(), y.t_final, y.steps)
            assert x.t_blowup == y.t_blowup or (np.isnan(x.t_blowup) and np.isnan(y.t_blowup))
    assert a.classes(4e4)[64]["blow-up"] >= 1


def _old_format_study(old, N_seeds, t_stop, **params):
    """A chaos study in the format before the engine, written as that format was: study.json
    and per orbit np.savez(steps, t, state, acc, s_t, s_mle, s_sali, s_gali, message, wall,
    failed) from an fpl_chaos handle (integrator state + fpl_chaos_save)."""
    import json
    from fputlab import _lowlevel as ll
    from fputlab.chaos.study import StudySpec
    spec = StudySpec(**params).validate()
    old.mkdir()
    (old / "study.json").write_text(json.dumps(
        {"format": "fputlab-chaos-study-1", **{k: getattr(spec, k) for k in
                                                 spec.__dataclass_fields__}, "Ns": list(spec.Ns)}))
    for (N, seed), t in zip(N_seeds, t_stop):
        lat = Lattice(N, spec.alpha, spec.model, tau=spec.tau, seed=seed)
        co = ll.chaos_options(spec.t_end, renorm_interval=spec.renorm_interval,
                              n_samples=spec.n_samples, sali_threshold=spec.sali_threshold,
                              stop_when_chaotic=spec.stop_when_chaotic)
        c = ll.ChaosHandle(lat._h, spec.method, ll.integrator_options(spec.dt, spec.rtol,
                                                                     spec.atol),
                           0.0, lat.mode_state(), None, co)
        arrays = [np.full(spec.n_samples, np.nan) for _ in range(4)]
        msg = ""
        if c.advance(t, *arrays) > 0:
            from fputlab._errors import last_error
            msg = last_error()
        ih = c.integrator()
        np.savez(old / f"orbit_N{N}_seed{seed}.npz", steps=np.int64(ih.steps()),
                 t=np.float64(ih.time()), state=ih.get_state().ravel(), acc=c.save(),
                 s_t=arrays[0], s_mle=arrays[1], s_sali=arrays[2], s_gali=arrays[3],
                 message=np.array(msg), wall=np.float64(0.0), failed=np.bool_(False))
    return spec


def _old_counts(old, spec, t_eval):
    """The old study's class counts at t_eval, read from its files as the old reader did:
    accumulators m, logsum, next, n_samples, chaotic, t_chaotic, mle, sali, gali, t_final,
    done, blew_up, t_blowup, completed, t_pending (fpl_chaos_save)."""
    from fputlab.chaos import classify_orbit
    out = {}
    for N in spec.Ns:
        counts = {"chaotic": 0, "regular": 0, "blow-up": 0, "undecided": 0, "not reached": 0}
        for r in range(spec.realisations):
            path = old / f"orbit_N{N}_seed{spec.first_seed + r}.npz"
            if not path.exists():
                counts["not reached"] += 1
                continue
            z = np.load(path)
            acc, k = z["acc"], int(z["acc"][3])
            cls = classify_orbit(z["s_t"][:k], z["s_mle"][:k], chaotic=bool(acc[4]),
                                 t_chaotic=acc[5], blew_up=bool(acc[11]), t_blowup=acc[12],
                                 t_final=acc[9], t_eval=t_eval)
            t_reached = acc[12] if acc[11] else acc[9]
            if cls not in ("chaotic", "blow-up") and t_reached < t_eval * (1 - 1e-12) and not (
                    acc[13] and acc[9] >= spec.t_end):
                counts["not reached"] += 1
            else:
                counts[cls] += 1
        out[N] = counts
    return out


def test_a_study_of_the_old_format_migrates_with_the_same_counts_and_continues(tmp_path):
    from fputlab.chaos.study import migrate_legacy
    params = dict(Ns=(4, 64), realisations=3, tau=20.0, t_end=2e4, n_samples=60)
    orbits = [(N, s) for N in (4, 64) for s in (1, 2, 3)]
    # one orbit never started, the others stopped at different times (an interrupted piece)
    old = tmp_path / "old"
    spec = _old_format_study(old, orbits[:-1], [1e3, 2e4, 5e3, 2e4, 2e4], **params)
    before = sorted(p.name for p in old.iterdir())
    migrated = migrate_legacy(old, tmp_path / "new")
    assert sorted(p.name for p in old.iterdir()) == before          # only read
    study = ChaosStudy(tmp_path / "new")
    assert study.spec == spec
    for t in (10.0, 300.0, 1e3, 3e3, 5e3, 1e4, 2e4):
        assert study.classes(t) == _old_counts(old, spec, t), t
    assert study.classes(2e4)[64]["blow-up"] >= 1
    assert migrated.to_xarray()["orbit_class"].shape == (2, 1, 3)
    # continued to t_end, it is the study run from scratch, bit for bit
    study.run(workers=2, progress=False)
    fresh = ChaosStudy(tmp_path / "fresh", **params)
    fresh.run(workers=2, progress=False)
    for N in (4, 64):
        for x, y in zip(study.results()[N], fresh.results()[N]):
            np.testing.assert_array_equal(x.mle, y.mle)
            np.testing.assert_array_equal(x.t, y.t)
            assert (x.classify(), x.t_final, x.steps) == (y.classify(), y.t_final, y.steps)
