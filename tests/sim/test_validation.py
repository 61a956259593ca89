"""The battery models against real charges (issue #14) and discharges (issue #26): every training
curve in tests/data/curves/training.toml is fitted and must meet the issue's figures; the default
models, with only the capacity and start state fitted, must meet twice those figures, and so must the
default with the pack's resistance measured at its log's rests (rest_steps.json, written by
tools/extract_curves.py from the whole source log) on every curve whose log has such a step.
Curves where the model cannot are marked, with the figure that fails (docs/validation.md)."""
import json
import tomllib
from pathlib import Path

import pytest

from zuml_studio.sim.curve import read_curve
from zuml_studio.sim.fit import LI, NI
from zuml_studio.sim.fit_checks import HEAT_PARAMS, withheld
from zuml_studio.sim.fit_discharge import fit_curve
from zuml_studio.sim.measured_r import MeasuredR, fit_with_measured_r

CURVES = Path(__file__).resolve().parent.parent / "data" / "curves"
TRAINING = tomllib.loads((CURVES / "training.toml").read_text())
REST_STEPS = json.loads((CURVES / "rest_steps.json").read_text())
# Figures the model does not reach on a curve, with why (see docs/validation.md).
KNOWN_MISSES = {
    ("nimh_4s_ultramat_05c", "default"): "RMSE 67 mV/cell (limit 40): this pack's resistance, measured in its "
                                         "log's rests, is 184 mOhm/cell (about twice the others' per capacity, "
                                         "1.6x the default's 112); one default cannot meet all four",
    ("nimh_4s_akkumaster_dis_015c", "default"): "RMSE 57 mV/cell (limit 50): at 145 min one cell empties (the pack "
                                                "falls 4.6 to 3.45 V, 3 x 1.15 V, within a minute): a weak cell, "
                                                "which a pack of identical cells cannot show (the fit finds it)",
    ("nicd_4s_akkumatik_08c", "default"): "RMSE 145 mV/cell (limit 40): this pack with its leads steps 194 mOhm/cell "
                                          "at its rests, 10x the NiCd default's cell (a 2C charge would stop at "
                                          "1.8 V/cell with it); with that resistance it meets the limits",
    ("nicd_4s_akkumatik_dis_1c", "default"): "RMSE 166 mV/cell (limit 50): the same pack's resistance, 10x the NiCd "
                                             "default's cell; its log has no discharge step to measure it",
}


def limits(chemistry: str, factor: float, direction: str = "charge") -> dict:
    if direction == "discharge":
        # The issue's discharge limits: RMSE(V) per cell and the delivered capacity within 3 %.
        v = 20 if chemistry in LI else 25 if chemistry in NI else 30
        return {"v": v * factor, "capacity_pct": 3 * factor}
    if chemistry in LI:
        return {"v": 15 * factor, "i_cv": 10 * factor}
    if chemistry in NI:
        return {"v": 20 * factor, "peak_pct": 10 * factor, "dv": 3 * factor, "temp": 5 * factor}
    return {"v": 25 * factor, "i_cv": 15 * factor}


def check(fig: dict, lim: dict) -> list[str]:
    bad = []
    if fig["rmse_v_per_cell_mv"] > lim["v"]:
        bad.append(f"RMSE V {fig['rmse_v_per_cell_mv']} > {lim['v']} mV/cell")
    if "i_cv" in lim and fig["rmse_i_cv_pct"] is not None and fig["rmse_i_cv_pct"] > lim["i_cv"]:
        bad.append(f"CV current {fig['rmse_i_cv_pct']} > {lim['i_cv']} %")
    if "capacity_pct" in lim:
        c = fig["capacity"]
        if abs(c["model_mah"] - c["real_mah"]) > lim["capacity_pct"] / 100 * c["real_mah"]:
            bad.append(f"delivered {c['model_mah']} mAh, real {c['real_mah']}")
    if "peak_pct" in lim:
        p = fig["peak"]
        if abs(p["model_mah"] - p["real_mah"]) > lim["peak_pct"] / 100 * p["real_mah"]:
            bad.append(f"peak at {p['model_mah']} mAh, real {p['real_mah']}")
        if abs(p["model_dv_mv_per_cell"] - p["real_dv_mv_per_cell"]) > lim["dv"]:
            bad.append(f"-dV {p['model_dv_mv_per_cell']}, real {p['real_dv_mv_per_cell']} mV/cell")
        t = fig["temp_rise"]
        if t is not None and abs(t["model_c"] - t["real_c"]) > lim["temp"]:
            bad.append(f"temperature rise {t['model_c']}, real {t['real_c']} °C")
    return bad


def cases():
    for name, entry in TRAINING.items():
        for kind in ("fitted", "default") + (("measured_r",) if REST_STEPS.get(name) else ()):
            marks = [pytest.mark.xfail(strict=True, reason=KNOWN_MISSES[(name, kind)])] \
                if (name, kind) in KNOWN_MISSES else []
            yield pytest.param(name, kind, id=f"{name}-{kind}", marks=marks)


@pytest.mark.parametrize("name,kind", list(cases()))
def test_model_meets_the_issue_figures(name, kind):
    entry = TRAINING[name]
    curve = read_curve(CURVES / f"{name}.csv")
    direction = entry.get("direction", "charge")
    assert curve.direction == direction
    if kind == "measured_r":
        result, _scale = fit_with_measured_r(curve, entry["chemistry"], entry["cells"],
                                             MeasuredR.from_dict(REST_STEPS[name]))
    else:
        result = fit_curve(curve, entry["chemistry"], entry["cells"], only_capacity=kind == "default")
    assert result.figures["direction"] == direction
    bad = check(result.figures, limits(entry["chemistry"], 1.0 if kind == "fitted" else 2.0, direction))
    assert not bad, f"{name} ({kind}): " + "; ".join(bad)
    claims_only_what_it_fixed(result.figures, direction)


def claims_only_what_it_fixed(fig: dict, direction: str) -> None:
    """Issue 35 §2: a discharge's model delivers the log's charge within 3 % or says it is no fit; heat terms
    whose temperature rise misses the pack's by more than 3 °C are withheld; a capacity the window does not
    fix is withheld with the range it covered."""
    if direction == "discharge":
        assert fig["capacity"]["ok"] == (abs(fig["capacity"]["error_pct"]) <= 3.0)
    hidden = withheld(fig)
    if fig["heat"] is not None:
        rise_ok = abs(fig["temp_rise"]["model_c"] - fig["temp_rise"]["real_c"]) <= 3.0
        assert rise_ok == fig["heat"]["fitted"] == (not hidden & set(HEAT_PARAMS))
    cover = fig["coverage"]
    assert cover["fixed"] == (cover["share"] >= 0.5) == ("capacity_mah" not in hidden)


def test_the_measured_resistance_column_covers_every_curve_whose_log_has_a_step():
    # issue 26: the Ultramat NiMH pack (184-204 mOhm/cell at its rests) was the blocked default; with its
    # measured resistance the default meets twice the limits there, while the plain default keeps its 67.
    assert set(REST_STEPS) == set(TRAINING)
    assert {n for n, r in REST_STEPS.items() if r} >= {"nimh_4s_ultramat_05c", "nimh_5s_polaron_03c",
                                                        "nimh_4s_estation_1c", "pb_6s_ub121000_dis_01c"}
    assert 180 <= REST_STEPS["nimh_4s_ultramat_05c"]["mohm_per_cell"] <= 230
    assert ("nimh_4s_ultramat_05c", "default") in KNOWN_MISSES
    assert ("nimh_4s_ultramat_05c", "measured_r") not in KNOWN_MISSES


def test_every_training_curve_has_its_csv_and_a_source():
    readme = (CURVES.parent / "README.md").read_text()
    for name, entry in TRAINING.items():
        assert (CURVES / f"{name}.csv").is_file()
        assert entry["source_file"] in readme


def test_validation_md_is_regenerated_with_every_curve_and_its_three_columns():
    # docs/validation.md is written by tools/validation.py: its summary holds every training curve, with
    # the measured-resistance column where (and only where) the curve's source log has a step.
    doc = (CURVES.parent.parent.parent / "docs" / "validation.md").read_text()
    assert "| curve | battery | direction | rate | RMSE V default (mV/cell) | default, measured resistance | " \
           "fitted | delivered, fitted |" in doc
    for name, entry in TRAINING.items():
        row = next((ln for ln in doc.splitlines() if ln.startswith(f"| [{name}](#{name}) |")), None)
        assert row is not None, name
        cells = [c.strip() for c in row.strip("|").split("|")]
        assert cells[2] == entry.get("direction", "charge")
        step = REST_STEPS[name]
        assert cells[5] == "no step" if step is None else cells[5].endswith(f"({step['mohm_per_cell']:.0f} mΩ)")
        assert (cells[7] == "–") == (cells[2] == "charge")


def test_the_polaron_nimh_discharges_heat_terms_are_withheld_and_the_akkumatik_held_end_is_followed():
    # The fitted Polaron NiMH discharge warms 11 °C where the pack warmed 3 °C: its heat terms are no result.
    polaron = fit_curve(read_curve(CURVES / "nimh_5s_polaron_dis_03c.csv"), "NiMh", 5).figures
    assert not polaron["heat"]["fitted"] and set(HEAT_PARAMS) <= withheld(polaron)
    # The Akkumatik NiCd discharge ends held at 3.40-3.45 V with its current stepped from 1 A to 0.2 A: driven by
    # that voltage the model delivers the log's charge (cut at the first 3.40 V it fell 6.8 % short).
    akkumatik = fit_curve(read_curve(CURVES / "nicd_4s_akkumatik_dis_1c.csv"), "NiCd", 4).figures
    assert akkumatik["capacity"]["ok"] and akkumatik["rmse_i_cv_pct"] < 10
