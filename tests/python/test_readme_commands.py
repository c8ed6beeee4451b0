"""Every `fputlab ...` command the README shows runs and exits 0.

Commands are taken from the README's sh blocks as written (continuation lines joined, the
trailing comment dropped, optional [..] parts left out); the only changes keep CI short: final
times are capped at 300, ensembles shrink to 2 realisations, and `figures` without --only makes
Figs. 1 and 5. Each runs in its own temporary directory, as a user in a fresh shell would."""
import re
import shlex
import subprocess
import sys
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[2]


def readme_commands():
    text = (ROOT / "README.md").read_text()
    cmds = []
    for block in re.findall(r"```sh\n(.*?)```", text, re.S):
        lines = block.replace("\\\n", " ").splitlines()
        for line in lines:
            line = line.split("#", 1)[0].strip()
            if line.startswith("fputlab "):
                cmds.append(re.sub(r"\[[^\]]*\]", "", line).split())
    return cmds


def shortened(argv):
    out, i = [], 0
    while i < len(argv):
        a = argv[i]
        if a in ("--t-end", "--t-max") and i + 1 < len(argv):
            out += [a, str(min(float(argv[i + 1]), 300.0))]
            i += 2
            continue
        if a == "--realisations" and i + 1 < len(argv):
            out += [a, "2"]
            i += 2
            continue
        out.append(a)
        i += 1
    if out[1] == "figures" and "--only" not in out:
        out += ["--only", "1", "5"]
    return out


COMMANDS = readme_commands()


def test_the_readme_shows_commands():
    assert len(COMMANDS) >= 10
    assert {c[1] for c in COMMANDS} >= {"demo", "simulate", "blowup", "chaos", "sweep",
                                        "figures", "methods"}


@pytest.mark.parametrize("argv", COMMANDS, ids=[" ".join(c[1:4]) for c in COMMANDS])
def test_readme_command_runs(argv, tmp_path):
    cmd = [sys.executable, "-m", "fputlab"] + shortened(argv)[1:]
    proc = subprocess.run(cmd, cwd=tmp_path, capture_output=True, text=True, timeout=600)
    assert proc.returncode == 0, f"{shlex.join(cmd)}\n{proc.stdout[-2000:]}\n{proc.stderr[-2000:]}"


def test_simulate_reports_an_energy_error_only_for_conservative_models():
    import json
    runs = {}
    for model in ("homogeneous", "nonlinear"):
        out = subprocess.run([sys.executable, "-m", "fputlab", "simulate", "--model", model,
                              "--N", "8", "--t-end", "50", "--json"], capture_output=True,
                             text=True, check=True).stdout
        runs[model] = json.loads(out)
    assert runs["homogeneous"]["max_relative_energy_error"] < 1e-8
    assert "max_relative_energy_error" not in runs["nonlinear"]


def test_human_output_has_no_python_reprs():
    # the text (non-JSON) summaries are for people: no dict/list reprs, numbers kept short
    out = subprocess.run([sys.executable, "-m", "fputlab", "chaos", "--tau", "10",
                          "--realisations", "2", "--N", "4", "8", "--t-end", "100"],
                         capture_output=True, text=True, check=True).stdout
    assert not re.search(r"[{}\[\]]|'", out), out
    assert re.search(r"classes: 4: chaotic 0, regular \d", out), out
