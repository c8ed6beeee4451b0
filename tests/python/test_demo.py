"""The main job runs end to end and writes its figure."""
import json

from fputlab.cli import main


def test_demo_writes_png_and_summary(tmp_path, capsys):
    out = tmp_path / "fig1.png"
    assert main(["demo", "--out", str(out), "--t-end", "2000", "--N", "16", "--json"]) == 0
    assert out.stat().st_size > 10_000
    summary = json.loads(capsys.readouterr().out)
    assert summary["N"] == 16 and summary["max_relative_energy_error"] < 1e-9


def test_methods_listed(capsys):
    assert main(["methods"]) == 0
    assert "yoshida4" in capsys.readouterr().out
