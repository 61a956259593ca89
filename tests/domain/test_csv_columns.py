"""The CSV files' column names are a file format: users' files and the tests' exports hold them byte for
byte, so the named vocabulary must spell the heads exactly as the files have always had them."""
from zuml_studio.domain import csv_columns as c


def test_the_heads_are_spelled_as_the_files_have_them():
    assert ",".join(c.SAMPLE_COLUMNS) == "time_s,section,phase,voltage_v,current_a,temp_c,heatsink_c,mah_in,mah_out"
    assert ",".join(c.SESSION_COLUMNS) == ",".join(c.SAMPLE_COLUMNS) + ",event"
    assert ",".join(c.MONITOR_COLUMNS) == ("time_s,running,paused,section,repetition,cycle,phase,run,voltage_v,"
                                           "current_a,temp_c,heatsink_c,mah_in,mah_out,event")
    assert ",".join(c.CURVE_COLUMNS) == "time_s,voltage_v,current_a"
    assert ",".join(c.EXPORT_COLUMNS) == "t_s,voltage_v,current_a,temp_c,charge_in_mah,charge_out_mah,state"
    assert c.cell_columns(3) == ("cell1_v", "cell2_v", "cell3_v") and c.BALANCE_MASK == "balance_mask"
    assert all(map(c.is_cell_column, c.cell_columns(12))) and not c.is_cell_column(c.VOLTAGE_V)
