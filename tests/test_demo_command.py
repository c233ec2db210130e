"""`geofeas demo` end to end on the bundled Solent recording: the command's output files and the
F1 a truthful operator reaches. In a file of its own so that a parallel test run puts it beside
the demo pipeline's module-scoped runs in tests/test_demo.py, not after them."""

import pandas as pd
import pytest


# F1 of the automatic matches with AIS and radar; with every source, where the aircraft and HF
# DF pairs geometry cannot decide go to the operator, F1 after 100 truthful decisions
@pytest.mark.parametrize(
    "sensors, decisions, bound, batch",
    [("ais,radar", 0, 0.9, 25), ("ais,radar,aircraft,hfdf", 100, 0.95, 10)],
)
def test_demo_command_end_to_end(tmp_path, capsys, sensors, decisions, bound, batch):
    from geofeas.cli import main

    out = tmp_path / "demo"
    args = [
        "demo",
        "--minutes",
        "10",
        "--sensors",
        sensors,
        "--out",
        str(out),
        "--no-progress",
        "--operator-batch",
        str(batch),
    ]
    assert main(args) == 0
    text = capsys.readouterr().out
    assert f"F1 after truthful decisions in review order (recomputed every {batch})" in text
    assert "removed 1 row(s): physically impossible jump" in text
    assert "precision" in text and "expected calibration error" in text
    # the oracle's bound is printed exactly when the picture has HF DF
    assert ("HF DF, what geometry cannot decide" in text) == ("hfdf" in sensors)
    for name in ("reports.csv", "pairs.csv", "metrics.csv", "metrics_by_sources.csv", "map.png"):
        assert (out / name).stat().st_size > 0
    metrics = pd.read_csv(out / "metrics.csv")
    default = metrics.iloc[0]
    assert default["config"] == "default" and default["combine"] == "chi2"
    assert default["precision"] >= 0.99
    operator = pd.read_csv(out / "operator.csv").set_index("decisions")
    assert operator.loc[0, "f1"] == pytest.approx(default["f1"], abs=1e-4)
    assert operator.loc[decisions, "f1"] > bound
    assert default["n_match"] + default["n_borderline"] + default["n_non-match"] == len(
        pd.read_csv(out / "pairs.csv")
    )
    reports = pd.read_csv(out / "reports.csv")
    assert set(reports["source"]) == set(sensors.split(","))
