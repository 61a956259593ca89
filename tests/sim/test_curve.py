"""Charges read for the fit from logs the fuzzer found holes in (benchmarks/fuzz_cli.py)."""
import numpy as np
import pytest

from helpers import ROOT
from zuml_studio.sim.curve import Curve, CurveError, read_curve, read_curve_csv
from zuml_studio.sim.fit import fit

DUO_WITH_SENSOR_GAPS = ROOT / "tests" / "data" / "logs" / "308DUO_LiFe_2.3Ah_Laden_0_CH1.txt"


def test_a_temperature_the_sensor_missed_now_and_then_is_filled_in():
    curve = read_curve(DUO_WITH_SENSOR_GAPS)
    assert curve.temp is not None and np.isfinite(curve.temp).all()


def test_the_fit_of_that_log_runs():
    # `zuml fit` on it raised scipy's "Residuals are not finite in the initial point"
    result = fit(read_curve(DUO_WITH_SENSOR_GAPS), "LiFe", 2, only_capacity=True, max_nfev=3)
    assert np.isfinite(result.battery.capacity_mah)


@pytest.mark.parametrize("column", ["t", "v", "i", "temp"])
def test_a_curve_with_a_number_that_is_not_finite_is_refused_with_its_sample(column):
    arrays = {k: np.arange(12, dtype=float) + 1 for k in ("t", "v", "i", "temp")}
    arrays[column][4] = np.nan
    with pytest.raises(CurveError, match=r"^x\.csv: sample 5: \w+ is not a finite number$"):
        Curve(arrays["t"], arrays["v"], arrays["i"], arrays["temp"], 0, "x.csv")


def test_the_ambient_of_a_model_is_the_first_temperature_within_the_model_range():
    t = np.arange(12, dtype=float)
    for first, ambient in ((85.0, 60.0), (-50.0, -20.0), (31.0, 31.0)):
        temp = np.full(12, 30.0)
        temp[0] = first
        assert Curve(t, t + 1, t + 1, temp, 0).ambient_c == ambient
    assert Curve(t, t + 1, t + 1, None, 0).ambient_c == 25.0


def test_a_curve_csv_with_a_header_and_no_sample():
    # found by benchmarks/fuzz_files.py: IndexError
    with pytest.raises(CurveError, match=r"^x\.csv: only 0 samples of charge$"):
        read_curve_csv("time_s,voltage_v,current_a\n", "x.csv")


def test_a_curve_csv_with_a_field_past_the_csv_limit_names_its_line():
    # found by benchmarks/fuzz_files.py: _csv.Error escaped
    text = "time_s,voltage_v,current_a\n0,1,1\n1,\"" + "9" * 200000 + "\",1\n"
    with pytest.raises(CurveError, match=r"^x\.csv: data line 3: field larger than field limit"):
        read_curve_csv(text, "x.csv")


from hypothesis import given, settings  # noqa: E402 - the property tests' own imports
from hypothesis import strategies as st  # noqa: E402 - the property tests' own imports

CELLS = st.sampled_from(["0", "1.5", "nan", "inf", "-1e999", "", "x", "1e400", '"', "9" * 30, " 2 "])


@settings(max_examples=60, deadline=None)
@given(st.lists(st.lists(CELLS, min_size=0, max_size=5), max_size=14), st.booleans())
def test_a_curve_csv_of_any_cells_is_a_curve_or_a_curve_error(rows, temp):
    header = "time_s,voltage_v,current_a" + (",temp_c" if temp else "")
    text = header + "\n" + "\n".join(",".join(row) for row in rows)
    try:
        curve = read_curve_csv(text, "x.csv")
    except CurveError:
        return
    assert np.isfinite(curve.mah).all()


def test_a_line_that_is_no_number_is_shown_cut():
    # found by benchmarks/fuzz_reports.py: a file whose line ends were lost echoed itself whole
    text = "time_s,voltage_v,current_a\n0,1,1\n1," + "7.5;" * 5000 + ",2\n"
    with pytest.raises(CurveError) as caught:
        read_curve_csv(text, "x.csv")
    assert str(caught.value) == "x.csv: data line 3: not a number in ['1', '7.5;7.5;7.5;7.5;7.5;7.5;…', '2']"


def test_time_that_goes_back_below_the_start_is_said_as_time_going_back():
    text = "time_s,voltage_v,current_a\n100,1,1\n110,1,1\n50,1,1\n" + "".join(f"{120 + k},1,1\n" for k in range(10))
    with pytest.raises(CurveError, match=r"^x\.csv: data line 4: time 50 s does not follow 110 s: time must rise"):
        read_curve_csv(text, "x.csv")
