"""Examples that are not figure scripts run and print what their header says."""
import re
import subprocess
import sys
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[2]


def test_harmonic_split_accuracy_example():
    out = subprocess.run([sys.executable, str(ROOT / "examples" / "harmonic_split_accuracy.py")],
                         capture_output=True, text=True, check=True, timeout=120).stdout
    rows = {}
    for line in out.splitlines():
        m = re.match(r"\s*([\d.]+) (aba864\S*)\s+((?:[\d.e+-]+\s+){4})(.*)", line)
        if m:
            rows[float(m.group(1)), m.group(2)] = [float(x) for x in m.group(3).split()]
    assert len(rows) == 6, out
    for amp in (3.0, 0.3, 0.1):
        # the harmonic split is more accurate at every step, and the more so at small amplitude
        assert all(h < p for h, p in zip(rows[amp, "aba864-harmonic"], rows[amp, "aba864"]))
    gap = {amp: rows[amp, "aba864"][1] / rows[amp, "aba864-harmonic"][1] for amp in (3.0, 0.1)}
    assert gap[0.1] > 100 * gap[3.0], gap


def test_lyapunov_spectrum_example():
    out = subprocess.run([sys.executable, str(ROOT / "examples" / "lyapunov_spectrum.py"),
                          "--t-end", "200"], capture_output=True, text=True, check=True,
                         timeout=120).stdout
    rows = [line.split() for line in out.splitlines() if re.match(r"\s*(8|16|32)\s+0\.", line)]
    assert [int(r[0]) for r in rows] == [8, 16, 32], out
    for N, lam1, pair, total, h_ks, d_ky in ([float(x) for x in r] for r in rows):
        assert lam1 > 0.05 and pair < 0.2 * lam1 and abs(total) < 1e-12 and h_ks > lam1
    assert out.count("CLVs N = 32") == 2
    regular = float(re.search(r"MEGNO regular N = 2 at t = 1e4: ([\d.]+)", out).group(1))
    assert 1.8 < regular < 2.05
    m = re.search(r"MEGNO chaotic N = 8 at t = 1e3: ([\d.]+), lambda t/2 = ([\d.]+)", out)
    assert float(m.group(1)) == pytest.approx(float(m.group(2)), rel=0.2)
