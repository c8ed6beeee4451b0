"""Nothing lost, nothing silently wrong: output paths, resume with changed settings, corrupt
files, load() errors, temporary files and symlinks, CLI errors and strict JSON (issue 13)."""
import hashlib
import json
import os
import subprocess
import sys

import h5py
import numpy as np
import pytest

import fputlab
from fputlab.cli import main
from fputlab.io import chaos_to_file, load, simulate_to_file


def sha(path):
    return hashlib.sha256(open(path, "rb").read()).hexdigest()


def lat8(seed=1):
    return fputlab.Lattice(8, 0.25, "nonlinear", tau=10.0, seed=seed)


def run_cli(*args, **kw):
    """The installed command in a child process: (exit status, stdout, stderr)."""
    p = subprocess.run([sys.executable, "-m", "fputlab", *map(str, args)], capture_output=True,
                       text=True, timeout=kw.pop("timeout", 120), **kw)
    return p.returncode, p.stdout, p.stderr


def one_line_error(err: str) -> bool:
    lines = [ln for ln in err.splitlines() if ln.strip()]
    return len(lines) == 1 and lines[0].startswith("fputlab: ") and "Traceback" not in err


# ---- 1. path collisions -------------------------------------------------------------------------

def test_results_and_checkpoint_on_the_same_path_are_refused_before_writing(tmp_path, capsys):
    r = tmp_path / "r.h5"
    assert main(["simulate", "--N", "8", "--t-end", "10", "--out", str(r), "--checkpoint",
                 str(r)]) == 2
    assert "same file" in capsys.readouterr().err and not r.exists()
    # also through a symbolic link, and in the library
    (tmp_path / "link.ckpt").symlink_to(r)
    with pytest.raises(ValueError, match="checkpoint"):
        simulate_to_file(lat8(), 10.0, r, checkpoint=tmp_path / "link.ckpt")
    with pytest.raises(ValueError, match="checkpoint"):
        chaos_to_file(lat8(), 10.0, r, checkpoint=str(r))
    assert not r.exists()
    assert main(["chaos", "--N", "8", "--t-end", "10", "--out", str(r), "--checkpoint",
                 str(tmp_path / "." / "r.h5")]) == 2
    assert "same file" in capsys.readouterr().err and not r.exists()


def test_other_output_collisions_are_refused(tmp_path, capsys):
    p = str(tmp_path / "x.h5")
    assert main(["bifurcation", "--out", p, "--plot", p]) == 2
    assert "same file" in capsys.readouterr().err and not os.path.exists(p)
    assert main(["blowup", "--tau", "0", "5", "--realisations", "2", "--t-end", "10",
                 "--out", p, "--plot", p]) == 2
    assert "same file" in capsys.readouterr().err and not os.path.exists(p)
    assert main(["sweep", "--out", p, "--work-dir", p, "--realisations", "1", "--t-end", "1"]) == 2
    assert "same file" in capsys.readouterr().err and not os.path.exists(p)
    (tmp_path / "afile").write_text("x")
    assert main(["sweep", "--out", str(tmp_path / "s.h5"), "--work-dir", str(tmp_path / "afile"),
                 "--realisations", "1", "--t-end", "1"]) == 2
    assert "not a directory" in capsys.readouterr().err
    assert main(["sweep", "--out", str(tmp_path / "d" / "s.h5"), "--work-dir", str(tmp_path / "d"),
                 "--realisations", "1", "--t-end", "1"]) == 2
    assert "inside --work-dir" in capsys.readouterr().err


# ---- 2. an existing results file is never overwritten ------------------------------------------

def test_existing_results_are_not_overwritten_when_the_checkpoint_is_gone(tmp_path, capsys):
    out, ck = tmp_path / "A.h5", tmp_path / "A.ckpt"
    args = ["simulate", "--N", "8", "--t-end", "400", "--out", str(out), "--checkpoint", str(ck)]
    assert main(args) == 0
    capsys.readouterr()
    before = sha(out)
    ck.unlink()                                            # deleted
    assert main(args) == 2
    err = capsys.readouterr().err
    assert "exists" in err and "1001 samples up to t = 400" in err and "--overwrite" in err
    assert sha(out) == before
    dangling = tmp_path / "B.ckpt"                         # a dangling symlink
    dangling.symlink_to(tmp_path / "nowhere.ckpt")
    assert main(args[:-1] + [str(dangling)]) == 2
    assert "symbolic link" in capsys.readouterr().err and sha(out) == before
    assert main(args[:-2]) == 2                            # no checkpoint at all
    assert sha(out) == before
    assert main(args + ["--restart"]) == 2                 # restart from 0 replaces: refused too
    assert sha(out) == before
    with pytest.raises(FileExistsError, match="overwrite"):
        simulate_to_file(lat8(), 50.0, out)
    with pytest.raises(FileExistsError, match="overwrite"):
        chaos_to_file(lat8(), 50.0, out, checkpoint=tmp_path / "c.ckpt")
    assert sha(out) == before
    assert main(args + ["--overwrite", "--t-end", "20"]) == 0   # asked for: replaced
    assert load(out).t[-1] == 20.0


def test_summary_outputs_are_not_overwritten_without_overwrite(tmp_path, capsys):
    p = tmp_path / "c.h5"
    assert main(["coefficients", "--out", str(p)]) == 0
    before = sha(p)
    assert main(["coefficients", "--tau", "5", "--out", str(p)]) == 2
    assert "exists" in capsys.readouterr().err and sha(p) == before
    assert main(["coefficients", "--tau", "5", "--out", str(p), "--overwrite"]) == 0
    assert sha(p) != before


# ---- 3. resume with other settings --------------------------------------------------------------

def test_extending_a_finished_run_continues_to_the_new_end_bit_for_bit(tmp_path, capsys):
    out, ck, ref = tmp_path / "C.h5", tmp_path / "C.ckpt", tmp_path / "ref.h5"
    base = ["simulate", "--model", "nonlinear", "--tau", "10", "--N", "8", "--out", str(out),
            "--checkpoint", str(ck), "--json",
            "--checkpoint-steps", "3000"]
    assert main(base + ["--t-end", "400", "--sample-every", "1"]) == 0
    capsys.readouterr()
    # no --sample-every: the checkpoint's spacing (1), not t_end/1000, continues to t = 800
    assert main(base + ["--t-end", "800"]) == 0
    s = json.loads(capsys.readouterr().out)
    assert s["status"] == "completed" and s["resumed_from"] == 400.0 and s["samples"] == 801
    simulate_to_file(lat8(), 800.0, ref, sample_every=1.0)
    a, b = load(out), load(ref)
    assert a.status == "completed" and a.t[-1] == 800.0
    for k in ("t", "energy", "mode_energies"):
        assert getattr(a, k).tobytes() == getattr(b, k).tobytes(), k
    before = sha(out), sha(ck)
    assert main(base + ["--t-end", "1200", "--sample-every", "2"]) == 2   # another grid
    assert "sample_every" in capsys.readouterr().err
    assert main(base + ["--t-end", "100"]) == 2                            # before the checkpoint
    assert "t_end" in capsys.readouterr().err
    assert (sha(out), sha(ck)) == before and load(out).status == "completed"


def test_chaos_resume_with_other_settings_is_refused_before_touching_anything(tmp_path):
    out, ck = tmp_path / "c.h5", tmp_path / "c.ckpt"
    chaos_to_file(lat8(), 300.0, out, checkpoint=ck, n_samples=20)
    before = sha(out), sha(ck)
    for kw, word in ((dict(t_end=600.0), "t_end"), (dict(n_samples=40), "n_samples"),
                     (dict(renorm_interval=2.0), "renorm_interval"),
                     (dict(stop_when_chaotic=True), "stop_when_chaotic")):
        args = {"t_end": 300.0, "n_samples": 20, "checkpoint": ck, **kw}
        t_end = args.pop("t_end")
        with pytest.raises(ValueError, match=word):
            chaos_to_file(lat8(), t_end, out, **args)
        assert (sha(out), sha(ck)) == before
    s = chaos_to_file(lat8(), 300.0, out, checkpoint=ck, n_samples=20)    # the same: fine
    assert s.status == "completed" and s.resumed_from == 300.0


# ---- 14. temporaries and symlinked checkpoints --------------------------------------------------

def test_symlinked_checkpoint_stays_a_symlink_and_stale_temporaries_go(tmp_path):
    real_dir = tmp_path / "store"
    real_dir.mkdir()
    target = real_dir / "run.ckpt"
    link = tmp_path / "run.ckpt"
    link.symlink_to(target)                    # dangling until the first checkpoint
    out = tmp_path / "run.h5"
    # a temporary left by a process killed while writing (this pid does not exist)
    dead = subprocess.Popen([sys.executable, "-c", "pass"])
    dead.wait()
    stale = real_dir / f"run.ckpt.tmp-{dead.pid}"
    stale.write_bytes(b"half a checkpoint")
    stale_resume = tmp_path / f"run.h5.resume-{dead.pid}"      # a kill during a resume
    stale_resume.write_bytes(b"half a results file")
    alive = real_dir / f"run.ckpt.tmp-{os.getpid()}x"           # not a pid: not ours, kept
    alive.write_bytes(b"someone else's")
    simulate_to_file(lat8(), 50.0, out, checkpoint=link, checkpoint_every_steps=1000,
                     checkpoint_every_seconds=None)
    assert link.is_symlink() and os.readlink(link) == str(target) and target.is_file()
    assert not stale.exists() and alive.exists()
    alive.unlink()
    assert not [p for p in list(tmp_path.iterdir()) + list(real_dir.iterdir())
                if ".tmp-" in p.name]
    s = simulate_to_file(lat8(), 80.0, out, checkpoint=link, sample_every=0.05)
    assert s.resumed_from == 50.0 and s.status == "completed" and link.is_symlink()
    assert not stale_resume.exists()
    assert not [p for p in tmp_path.iterdir() if ".resume-" in p.name or ".tmp-" in p.name]


# ---- 4. corrupt files ---------------------------------------------------------------------------

def test_results_chunks_carry_checksums_and_damaged_data_is_an_error(tmp_path):
    out = tmp_path / "r.h5"
    simulate_to_file(lat8(), 100.0, out, sample_every=0.1, chunk_rows=64)
    with h5py.File(out) as f:
        assert f["mode_energies"].fletcher32 and f["t"].fletcher32
        off = f["mode_energies"].id.get_chunk_info(0).byte_offset
    data = bytearray(out.read_bytes())
    data[off + 20] ^= 0xFF
    out.write_bytes(bytes(data))
    with pytest.raises(OSError, match="damaged"):
        load(out)


def test_truncated_or_damaged_checkpoint_is_refused_before_hdf5_reads_it(tmp_path):
    out, ck = tmp_path / "r.h5", tmp_path / "r.ckpt"
    simulate_to_file(lat8(), 50.0, out, checkpoint=ck)
    good = ck.read_bytes()
    before = sha(out)
    for bad in (good[:len(good) // 2], good[:600], good + b"x", b"\0" * 512 + good[512:],
                good[:700] + bytes([good[700] ^ 1]) + good[701:]):
        ck.write_bytes(bad)
        with pytest.raises(OSError, match="corrupt|checksum"):
            simulate_to_file(lat8(), 60.0, out, checkpoint=ck)
        with pytest.raises(OSError, match="corrupt|checksum"):
            fputlab.io.checkpoint_time(ck)
        assert sha(out) == before


FUZZ = r"""
import os, random, sys, hashlib
import numpy as np
import fputlab
from fputlab.io import simulate_to_file, chaos_to_file, load
d, cases, seed = sys.argv[1], int(sys.argv[2]), int(sys.argv[3])
rng = random.Random(seed)
lat = fputlab.Lattice(4, 0.25, "nonlinear", tau=10.0, seed=1)
def run(kind, out, ck, t_end):
    if kind == "simulate":
        return simulate_to_file(lat, t_end, out, checkpoint=ck, sample_every=0.5, chunk_rows=8,
                                checkpoint_every_steps=2000, checkpoint_every_seconds=None)
    return chaos_to_file(lat, 60.0, out, checkpoint=ck, n_samples=30, segment=5.0,
                         checkpoint_every_steps=2000, checkpoint_every_seconds=None)
def arrays(path):
    r = load(path)
    a = [r.t, r.energy, r.mode_energies, r.v] + ([r.chaos[k] for k in sorted(r.chaos)] if r.chaos else [])
    return b"".join(x.tobytes() for x in a), r.status
counts = {"refused": 0, "same": 0}
for kind in ("simulate", "chaos"):
    out, ck = os.path.join(d, kind + ".h5"), os.path.join(d, kind + ".ckpt")
    ref_out = os.path.join(d, kind + "_ref.h5")
    run(kind, ref_out, None, 60.0)
    reference = arrays(ref_out)
    # an interrupted-looking pair: the checkpoint at t = 30 and the file as it was then
    if kind == "simulate":
        run(kind, out, ck, 30.0)
    else:
        s = chaos_to_file(lat, 60.0, out, checkpoint=ck, n_samples=30, segment=5.0,
                          checkpoint_every_steps=2000, checkpoint_every_seconds=None)
    pair = (open(out, "rb").read(), open(ck, "rb").read())
    for case in range(cases):
        which = rng.randrange(2)
        data = bytearray(pair[which])
        if rng.random() < 0.2:
            data = data[:rng.randrange(len(data))]
        else:
            for _ in range(rng.choice((1, 1, 2, 8))):
                data[rng.randrange(len(data))] ^= 1 << rng.randrange(8)
        open(out, "wb").write(bytes(data) if which == 0 else pair[0])
        open(ck, "wb").write(bytes(data) if which == 1 else pair[1])
        try:
            s = run(kind, out, ck, 60.0)
        except (ValueError, OSError) as err:
            assert str(err), "an error without a message"
            counts["refused"] += 1
            continue
        got = arrays(out)
        assert s.status == "completed" and got == reference, (kind, case, which, s)
        counts["same"] += 1
print(counts["refused"], counts["same"], flush=True)
"""


def test_mutation_fuzz_of_checkpoint_and_results(tmp_path):
    """Random bit flips and truncations of a small checkpoint and of its results file: every
    case either is refused with a message or resumes to exactly the uninterrupted results;
    never a crash or a hang (the whole loop runs in a child process with a time limit)."""
    p = subprocess.run([sys.executable, "-c", FUZZ, str(tmp_path), "150", "2026"],
                       capture_output=True, text=True, timeout=300)
    assert p.returncode == 0, p.stderr[-3000:]
    refused, same = map(int, p.stdout.split())
    assert refused + same == 300 and refused > 100


# ---- 5. load() errors ---------------------------------------------------------------------------

def test_load_names_what_is_missing_or_wrong(tmp_path):
    good = tmp_path / "good.h5"
    simulate_to_file(lat8(), 10.0, good, sample_every=0.5)

    def variant(name, edit):
        p = tmp_path / name
        p.write_bytes(good.read_bytes())
        with h5py.File(p, "a") as f:
            edit(f)
        return p

    p = variant("nomodes.h5", lambda f: f.__delitem__("mode_energies"))
    with pytest.raises(ValueError, match="'mode_energies' is missing"):
        load(p)
    p = variant("nov.h5", lambda f: f.__delitem__("v"))
    with pytest.raises(ValueError, match="'v' is missing"):
        load(p)

    def wrong_shape(f):
        del f["energy"]
        f["energy"] = np.zeros((3, 3))
    with pytest.raises(ValueError, match="'energy' has shape"):
        load(variant("shape.h5", wrong_shape))

    def text_energy(f):
        del f["energy"]
        f["energy"] = np.array([b"x"] * 21)
    with pytest.raises(ValueError, match="'energy'"):
        load(variant("text.h5", text_energy))

    def bad_utf8(f):
        f.attrs["status"] = np.bytes_(b"\xff\xfe")
    with pytest.raises(ValueError, match="UTF-8"):
        load(variant("utf8.h5", bad_utf8))
    (tmp_path / "garbage.h5").write_bytes(b"\x89HDF\r\n\x1a\n" + os.urandom(2000))
    with pytest.raises(OSError, match="garbage.h5"):
        load(tmp_path / "garbage.h5")


# ---- 12, 13. CLI: one line and exit 2; strict JSON -----------------------------------------------

@pytest.mark.parametrize("args", [
    ["simulate", "--N", "8", "--t-end", "1", "--out", "/proc/nope/r.h5"],
    ["simulate", "--N", "8", "--t-end", "1", "--out", "{tmp}/r.h5", "--checkpoint", "/proc/x/c"],
    ["chaos", "--N", "8", "--t-end", "1", "--out", "/proc/nope/c.h5"],
    ["sweep", "--out", "{tmp}/s.h5", "--work-dir", "{tmp}/file", "--t-end", "1"],
    ["demo", "--N", "1", "--out", "{tmp}/d.png"],
    ["simulate", "--N", "3000000000"],
    ["simulate", "--model", "nonlinear", "--tau", "10", "--N", "8", "--seed",
     "99999999999999999999999"],
    ["coefficients", "--out", "/proc/nope/c.h5"],
    ["bifurcation", "--plot", "/proc/nope/b.png"],
    ["simulate", "--N", "8", "--method", "euler"],
])
def test_cli_failures_are_one_line_and_exit_2(tmp_path, args):
    (tmp_path / "file").write_text("x")
    code, out, err = run_cli(*[a.replace("{tmp}", str(tmp_path)) for a in args])
    assert code == 2 and one_line_error(err), (code, err)


def test_cli_unreachable_scheduler_is_one_line(tmp_path):
    code, _, err = run_cli("sweep", "--out", tmp_path / "s.h5", "--scheduler", "tcp://127.0.0.1:9",
                           "--realisations", "1", "--t-end", "1",
                           env={**os.environ, "DASK_DISTRIBUTED__COMM__TIMEOUTS__CONNECT": "1s"})
    assert code == 2 and one_line_error(err), err


NO_DASK = """
import sys
class Block:
    def find_spec(self, name, path=None, target=None):
        if name == "dask" or name.startswith("dask."):
            raise ModuleNotFoundError(f"No module named {name!r}", name=name)
sys.meta_path.insert(0, Block())
from fputlab.cli import main
raise SystemExit(main(sys.argv[1:]))
"""


def test_cli_without_dask_is_one_line(tmp_path):
    p = subprocess.run([sys.executable, "-c", NO_DASK, "sweep", "--out", str(tmp_path / "s.h5"),
                        "--scheduler", "tcp://127.0.0.1:9", "--realisations", "1", "--t-end", "1"],
                       capture_output=True, text=True, timeout=120)
    assert p.returncode == 2 and one_line_error(p.stderr) and "dask" in p.stderr, p.stderr


JSON_COMMANDS = [
    ["simulate", "--N", "8", "--t-end", "5"],
    ["simulate", "--N", "8", "--t-end", "5", "--out", "{tmp}/s.h5"],
    ["blowup", "--tau", "0", "--t-end", "100"],                      # time NaN -> null
    ["blowup", "--tau", "0", "30", "--realisations", "2", "--t-end", "50", "--N", "8",
     "--workers", "1"],
    ["chaos", "--N", "4", "--t-end", "3", "--samples", "5", "--model", "homogeneous"],
    ["chaos", "--N", "4", "--t-end", "3", "--samples", "5", "--out", "{tmp}/c.h5"],
    ["sweep", "--tau", "0", "--N", "8", "--realisations", "1", "--t-end", "5", "--workers", "1",
     "--out", "{tmp}/w.h5"],
    ["coefficients"],
    ["tauc", "--realisations", "5"],
    ["bifurcation"],
    ["demo", "--t-end", "200", "--N", "8", "--out", "{tmp}/d.png"],
]


@pytest.mark.parametrize("args", JSON_COMMANDS, ids=lambda a: " ".join(a[:3]))
def test_every_json_output_is_strict_json(tmp_path, args):
    def strict(s):
        raise ValueError(f"not JSON: {s}")
    code, out, err = run_cli(*[a.replace("{tmp}", str(tmp_path)) for a in args], "--json")
    assert code == 0, err
    json.loads(out, parse_constant=strict)


def test_blowup_without_blowup_prints_null_time(capsys):
    assert main(["blowup", "--tau", "0", "--t-end", "100", "--json"]) == 0
    out = json.loads(capsys.readouterr().out)
    assert out["blew_up"] is False and out["time"] is None


def test_resume_check_survives_a_crash_or_hang_inside_libhdf5(tmp_path, monkeypatch):
    """The read-back before a resume runs in a child process: a fault there (here simulated:
    SIGSEGV, an endless loop) is an OSError, the files are untouched, this process lives on."""
    import signal
    import time

    import fputlab._lowlevel as ll
    import fputlab.io.files as files
    out, ck = tmp_path / "r.h5", tmp_path / "r.ckpt"
    simulate_to_file(lat8(), 50.0, out, checkpoint=ck)
    before = sha(out), sha(ck)

    def crashing(*args):
        os.kill(os.getpid(), signal.SIGSEGV)

    def hanging(*args):
        while True:
            time.sleep(1)

    monkeypatch.setattr(ll, "results_verify", crashing)
    with pytest.raises(OSError, match="SIGSEGV"):
        simulate_to_file(lat8(), 60.0, out, checkpoint=ck)
    monkeypatch.setattr(ll, "results_verify", hanging)
    monkeypatch.setattr(files, "VERIFY_TIMEOUT", 1.0)
    with pytest.raises(OSError, match="did not finish"):
        simulate_to_file(lat8(), 60.0, out, checkpoint=ck)
    assert (sha(out), sha(ck)) == before


# ---- 10. parameters are read-only ----------------------------------------------------------------

def test_lattice_parameters_are_read_only():
    lat = fputlab.Lattice(4096, 0.25, "nonlinear", tau=10, seed=1)
    for name, value in (("N", 2), ("alpha", 1.0), ("beta", 1.0), ("tau", 0.0), ("seed", 2),
                        ("model", "homogeneous"), ("model_code", 1), ("disorder", "uniform")):
        with pytest.raises(AttributeError, match=f"{name} is read-only"):
            setattr(lat, name, value)
    with pytest.raises(AttributeError):
        del lat.alpha
    assert lat.N == 4096 and lat.alpha == 0.25 and lat.force(np.zeros(4096)).shape == (4096,)
    import pickle
    back = pickle.loads(pickle.dumps(lat))       # rebuilt lattices keep their description
    assert back.tau == 10 and back.seed == 1 and back.v.tobytes() == lat.v.tobytes()


# ---- 11. quiet acceptance of bad input ------------------------------------------------------------

def test_bad_input_that_used_to_pass_quietly(capsys):
    lat = lat8()
    with pytest.raises(ValueError, match="method"):
        lat.integrate(1.0, method="yoshida4\x00junk")
    with pytest.raises(ValueError, match="method"):
        fputlab.chaos.lyapunov(lat, 10.0, method="yoshida4\x00junk")
    with pytest.raises(TypeError, match="mode k"):
        lat.integrate(10.0, stop_on=[("mode_energy", 1.0, 1.7)])
    with pytest.raises(ValueError, match="disorder"):
        fputlab.Lattice(8, 0.25, "nonlinear", disorder="cauchy")
    with pytest.raises(ValueError, match="realisations"):
        fputlab.blowup.blowup_sweep([10.0], realisations=0, t_max=1.0)
    with pytest.raises(ValueError, match="taus"):
        fputlab.blowup.blowup_sweep([], realisations=2, t_max=1.0)
    with pytest.raises(ValueError, match="realisations"):
        fputlab.chaos.chaotic_fraction(Ns=[4], realisations=0, t_end=1.0)
    with pytest.raises(ValueError, match="Ns"):
        fputlab.chaos.chaotic_fraction(Ns=[], realisations=2, t_end=1.0)
    for args, word in ((["simulate", "--model", "homogeneous", "--tau", "10", "--t-end", "1"], "--tau"),
                       (["chaos", "--model", "homogeneous", "--tau", "5", "--t-end", "1"], "--tau"),
                       (["blowup", "--tau", "20", "--realisations", "0", "--t-end", "1"], "--realisations"),
                       (["chaos", "--realisations", "0", "--t-end", "1"], "--realisations"),
                       (["figures", "--only", "99"], "99"),
                       (["bifurcation", "--N", "-5"], "--N")):
        assert main(args) == 2, args
        assert word in capsys.readouterr().err
    assert main(["simulate", "--model", "homogeneous", "--tau", "0", "--t-end", "1"]) == 0
    assert main(["simulate", "--model", "homogeneous", "--t-end", "1"]) == 0


# ---- 6, 9. limits --------------------------------------------------------------------------------

def test_memory_is_estimated_before_allocating(capsys):
    with pytest.raises(MemoryError, match=r"N = 1000000000.*bytes"):
        fputlab.Lattice(10**9)
    assert main(["simulate", "--N", "1000000000"]) == 2
    err = capsys.readouterr().err
    assert "N = 1000000000" in err and "bytes" in err
    lat = fputlab.Lattice(1000)
    with pytest.raises(MemoryError, match="samples"):
        lat.integrate(1e9, sample_every=0.01)          # 1e11 samples of 1000 mode energies
    if (fputlab._arrays.available_memory() or 0) < 60e9:
        with pytest.raises(MemoryError, match="chaos samples"):
            fputlab.chaos.lyapunov(lat, 10.0, n_samples=2**31 - 1)


def test_unbounded_work_and_big_integers_are_refused():
    lat = lat8()
    with pytest.raises(ValueError, match="renorm_interval"):
        fputlab.chaos.lyapunov(lat, 10.0, renorm_interval=1e-300)
    with pytest.raises(ValueError, match="t_end"):
        fputlab.chaos.lyapunov(lat, 1e300)
    with pytest.raises(ValueError, match="max_steps_per_segment"):
        simulate_to_file(lat, 10.0, "/nonexistent/x.h5", max_steps_per_segment=0)
    with pytest.raises(ValueError, match="segment"):
        chaos_to_file(lat, 10.0, "/nonexistent/x.h5", segment=0.0)
    with pytest.raises(ValueError, match="segment"):
        chaos_to_file(lat, 10.0, "/nonexistent/x.h5", segment=-1.0)
    for call in (lambda: lat.integrate(1e300), lambda: fputlab.blowup.blowup_time(lat, 1e300),
                 lambda: simulate_to_file(lat, 1e300, "/nonexistent/x.h5")):
        with pytest.raises(ValueError, match="more than 1e\\+13"):
            call()
    with pytest.raises(ValueError, match="dT"):
        fputlab.reduction.envelope_run(3.6, 0.9, 100.0, dT=1e-12)
    with pytest.raises(ValueError, match="sample spacing"):
        lat.integrate(10.0, dt=1.0, sample_every=0.1)
    with pytest.raises(ValueError, match="sample spacing"):
        simulate_to_file(lat, 10.0, "/nonexistent/x.h5", dt=1.0, sample_every=0.1)
    run = lat.integrate(0.5)                           # the default spacing respects dt
    assert np.all(np.diff(run.t) >= 0.01 - 1e-15) and run.completed
    for call, word in ((lambda: fputlab.Lattice(3_000_000_000), "N"),
                       (lambda: lat.mode_state(k=2**40), "k"),
                       (lambda: fputlab.chaos.lyapunov(lat, 10.0, n_samples=2**40), "n_samples"),
                       (lambda: fputlab.chaos.lyapunov(lat, 10.0, n_dev=2**33), "n_dev")):
        with pytest.raises(ValueError, match=word):
            call()


# ---- 8. pool workers die with their parent -------------------------------------------------------

POOL_PARENT = r"""
import os, sys, time
from fputlab.ensemble import process_pool
def pid(_):
    return os.getpid()
if __name__ == "__main__":
    pool = process_pool(2)
    pids = set(pool.map(pid, range(8)))
    print(" ".join(map(str, pids)), flush=True)
    time.sleep(600)
"""


@pytest.mark.parametrize("how", ["SIGKILL", "SIGTERM"])
def test_sweep_pool_workers_die_with_their_parent(tmp_path, how):
    import signal
    import time
    script = tmp_path / "parent.py"
    script.write_text(POOL_PARENT)
    proc = subprocess.Popen([sys.executable, str(script)], stdout=subprocess.PIPE, text=True)
    workers = [int(p) for p in proc.stdout.readline().split()]
    assert workers
    proc.send_signal(getattr(signal, how))
    proc.wait(timeout=60)

    def alive(pid):
        try:
            with open(f"/proc/{pid}/stat") as f:
                return f.read().split()[2] != "Z"
        except FileNotFoundError:
            return False
    deadline = time.monotonic() + 30
    while any(alive(p) for p in workers) and time.monotonic() < deadline:
        time.sleep(0.1)
    assert not any(alive(p) for p in workers)


# ---- 7. Ctrl-C during long C calls ---------------------------------------------------------------

INTERRUPT = r"""
import sys, fputlab
what = sys.argv[1]
lat = fputlab.Lattice(64, 0.25)
print("start", flush=True)
try:
    if what == "integrate":
        lat.integrate(3e8)                         # hours in one C call before
    elif what == "integrate-bdf":
        # one sample interval of cvode-bdf at N = 64 was one C call of minutes before its time
        # budget (fpl_integrator_set_budget)
        lat.integrate(3e8, method="cvode-bdf")
    elif what == "lyapunov":
        fputlab.chaos.lyapunov(lat, 3e8)
    else:
        fputlab.blowup.blowup_time(lat, 3e8)
except fputlab.Interrupted as err:
    r = err.result
    # integrate: samples so far (here only t = 0) and the state where it stopped, t in message
    t = (float(r.message.rsplit("=", 1)[1]) if what.startswith("integrate") else
         r.t_final if what == "lyapunov" else r.t_reached)
    print("interrupted", type(r).__name__, r.completed if what != "blowup" else r.blew_up, t > 0,
          flush=True)
"""


def _interrupt(cmd):
    import signal
    import time
    # SIGINT as a terminal delivers it (a test run in the background inherits it ignored)
    proc = subprocess.Popen(cmd, stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True,
                            preexec_fn=lambda: signal.signal(signal.SIGINT, signal.SIG_DFL))
    if cmd[1] == "-c":
        assert proc.stdout.readline().strip() == "start"
    time.sleep(1.5)
    proc.send_signal(signal.SIGINT)
    sent = time.monotonic()
    # the whole computation takes hours: finishing at all means the interrupt was seen
    out, err = proc.communicate(timeout=60)
    _interrupt.seconds = time.monotonic() - sent
    return proc.returncode, out, err


@pytest.mark.parametrize("what,kind", [("integrate", "Run"), ("integrate-bdf", "Run"),
                                       ("lyapunov", "ChaosResult"), ("blowup", "Blowup")])
def test_ctrl_c_stops_long_computations_and_keeps_the_result(what, kind):
    code, out, err = _interrupt([sys.executable, "-c", INTERRUPT, what])
    assert code == 0 and out.split() == ["interrupted", kind, "False", "True"], (out, err)
    assert _interrupt.seconds < 10, f"{what}: {_interrupt.seconds:.1f} s from Ctrl-C to exit"


def test_ctrl_c_in_the_cli_prints_what_was_computed_and_exits_130():
    code, out, err = _interrupt([sys.executable, "-c", "import sys\nfrom fputlab.cli import main\n"
                                 "print('start', flush=True)\nsys.exit(main(sys.argv[1:]))",
                                 "simulate", "--model", "homogeneous", "--N", "64", "--t-end", "3e8",
                                 "--json"])
    assert code == 130, err
    s = json.loads(out)
    assert s["completed"] is False and "interrupted" in s["message"] and s["samples"] >= 1


# ---- issue 16, item 6: a consistent command line -------------------------------------------------

def test_every_option_shows_its_default_and_time_options_share_names(capsys):
    import argparse

    from fputlab.cli import build_parser
    parser = build_parser()
    sub = next(a for a in parser._actions if isinstance(a, argparse._SubParsersAction))
    for name, sp in sub.choices.items():
        text = " ".join(sp.format_help().split())
        for action in sp._actions:
            if not action.option_strings or action.dest == "help" or action.default in (
                    None, False, argparse.SUPPRESS):
                continue
            shown = action.help or ""
            assert "default" in shown or "(default" in text.split(action.option_strings[-1], 1)[1], \
                (name, action.option_strings)
    for cmd in ("simulate", "chaos", "blowup", "sweep"):      # --t-end and --t-max both work
        for opt in ("--t-end", "--t-max"):
            assert parser.parse_args([cmd, opt, "5"]) is not None
    assert main(["methods"]) == 0
    rows = capsys.readouterr().out.splitlines()
    import re
    assert len({re.match(r"(\S+)\s+(\S+)", row).end(2) for row in rows}) == 1   # aligned


def test_ctrl_c_stops_a_sweep_and_its_workers_at_once(tmp_path):
    """Ctrl-C reaches the whole process group: the workers ignore it, the parent kills them and
    exits 130 with one line (no worker tracebacks, no wait for the running tasks)."""
    import signal
    import time
    cmd = [sys.executable, "-c", "import sys\nfrom fputlab.cli import main\nprint('start', "
           "flush=True)\nsys.exit(main(sys.argv[1:]))", "sweep", "--realisations", "4", "--N",
           "64", "--tau", "0", "--t-end", "1e7", "--out", str(tmp_path / "s.h5"), "--workers",
           "2", "--json"]

    def session():
        os.setsid()
        signal.signal(signal.SIGINT, signal.SIG_DFL)
    proc = subprocess.Popen(cmd, stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True,
                            preexec_fn=session)
    assert proc.stdout.readline().strip() == "start"
    time.sleep(3)
    os.killpg(proc.pid, signal.SIGINT)                # as a terminal's Ctrl-C does
    try:
        _, err = proc.communicate(timeout=60)         # the tasks alone take many minutes
    finally:
        try:
            os.killpg(proc.pid, signal.SIGKILL)
        except ProcessLookupError:
            pass
    assert proc.returncode == 130 and one_line_error(err), err
