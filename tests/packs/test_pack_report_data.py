"""The report's model lines: the fit's RMSE per quantity with its window, the charge it predicts on its own
log's program next to the log's, and the warning past 15 % (the same words as the packs window's)."""
from zuml_studio.packs.report_data import model_lines

VOLTAGE = {"voltage": {"rmse": 8.2, "unit": "mV/cell", "window_s": [0.0, 600.0]}}


def _prediction(model_mah: float, trusted: bool) -> dict:
    return {"real_mah": 2790.0, "model_mah": model_mah, "charge_error_pct": (model_mah / 2790.0 - 1) * 100,
            "real_s": 10000.0, "model_s": 1080.0, "time_error_pct": -89.2, "trusted": trusted,
            "why": "IF(DELTA_PEAK>0.04V) STOP_FAZE", "ended_by": "own_end"}


def test_no_model_says_so():
    assert model_lines(None) == ["No model fitted to this pack yet: its figures are –."]


def test_a_fit_without_figures_shows_a_dash_and_says_its_log_cannot_be_predicted():
    lines = model_lines({"quality": {}, "own_program": None}, "/logs/a.lov")
    assert lines[0] == "Fitted to a.lov"
    assert lines[1] == "fit quality (RMSE): –"
    assert lines[2].startswith("Its own log's charge cannot be predicted")


def test_a_predicted_charge_far_from_the_logs_is_not_to_be_trusted():
    lines = model_lines({"quality": VOLTAGE, "own_program": _prediction(617.0, False)}, "a.lov")
    assert lines[1] == "RMSE voltage 8.2 mV per cell over 0.0–10.0 min"
    assert lines[2].startswith("On its own log's program: 617 mAh predicted, 2790 mAh logged (-77.9 %)")
    assert lines[3].startswith("⚠ do not trust this model for this pack")
    close = model_lines({"quality": VOLTAGE, "own_program": _prediction(2700.0, True)}, "a.lov")
    assert len(close) == 3 and "do not trust" not in " ".join(close)
