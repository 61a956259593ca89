"""The report's model lines: the fit's RMSE per quantity, "–" for a figure the fit does not give, the charge
it predicts next to the log's and the warning past 15 %."""
from types import SimpleNamespace

import numpy as np

from zuml_studio.packs.report_data import model_lines


def _fit(**figures):
    curve = SimpleNamespace(name="/logs/a.lov", mah=np.array([0.0, 1000.0, 2790.0]))
    return SimpleNamespace(figures=figures, curve=curve)


def test_no_model_says_so():
    assert model_lines(None) == ["No model fitted to this pack yet: its figures are –."]


def test_a_figure_the_fit_does_not_give_is_a_dash():
    lines = model_lines(_fit(rmse_v_per_cell_mv=8.24))
    assert lines[0] == "Fitted to a.lov"
    assert lines[1] == "fit quality (RMSE): voltage 8.2 mV per cell, CV current –, temperature –"
    assert lines[2] == "charge to the end: logged 2790 mAh, the model predicts –"
    assert len(lines) == 3


def test_a_predicted_charge_far_from_the_logs_is_not_to_be_trusted():
    peak = {"real_mah": 2790.0, "model_mah": 617.0, "real_dv_mv_per_cell": 5.0, "model_dv_mv_per_cell": 3.0}
    lines = model_lines(_fit(rmse_v_per_cell_mv=30.0, rmse_i_cv_pct=None, rmse_temp_c=1.25, peak=peak))
    assert lines[1].endswith("CV current –, temperature 1.2 °C") or lines[1].endswith("temperature 1.3 °C")
    assert lines[2] == "charge to the −ΔV peak: logged 2790 mAh, the model predicts 617 mAh"
    assert lines[3].startswith("the model's charge differs from the log's by 78 % (over 15 %)")
    close = dict(peak, model_mah=2700.0)
    assert len(model_lines(_fit(peak=close))) == 3
