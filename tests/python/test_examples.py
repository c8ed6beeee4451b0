"""Examples that are not figure scripts run and print what their header says."""
import re
import subprocess
import sys
from pathlib import Path

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
