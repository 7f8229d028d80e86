"""The retrieval study scripts run (a tiny recovery study) so that they cannot rot."""

import csv
import importlib.util
from pathlib import Path

import pytest

from sandlight.measured import _shared_usgs_folder

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


@pytest.mark.skipif(_shared_usgs_folder() is None, reason="shared USGS splib07a folder not available")
def test_powder_study_fits_the_gds69_series_and_writes_its_table(tmp_path, capsys):
    spec = importlib.util.spec_from_file_location("retrieval_powder", SCRIPT.with_name("retrieval_powder.py"))
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    module.main(
        ["--rays", "300", "--parts", "gds69", "--fractions", "ag", "--out", str(tmp_path), "--figures", str(tmp_path)]
    )
    rows = list(csv.DictReader((tmp_path / "retrieval_powder.csv").read_text().splitlines()))
    assert len(rows) == 4 and {"diameter_um", "diameter_low_95", "sieve_midpoint_um", "spearman"} <= set(rows[0])
    assert (tmp_path / "retrieval_powder.png").stat().st_size > 1000
    assert "Spearman" in capsys.readouterr().out
