"""The retrieval study scripts run (a tiny recovery study) so that they cannot rot."""

import csv
import importlib.util
from pathlib import Path

SCRIPT = Path(__file__).resolve().parents[2] / "scripts" / "studies" / "retrieval_recovery.py"


def test_recovery_study_writes_its_table_and_figure(tmp_path, capsys):
    spec = importlib.util.spec_from_file_location("retrieval_recovery", SCRIPT)
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    module.main(["--samples", "2", "--rays", "300", "--out", str(tmp_path), "--figures", str(tmp_path)])
    rows = list(csv.DictReader((tmp_path / "retrieval_recovery.csv").read_text().splitlines()))
    assert len(rows) == 2 and {"iron_oxide_true", "iron_oxide_low", "iron_oxide_covered"} <= set(rows[0])
    assert (tmp_path / "retrieval_recovery.png").stat().st_size > 1000
    assert "| iron_oxide |" in capsys.readouterr().out
