"""CSV that a spreadsheet or another program writes (issue 33 §1; the cases of
shared/repro/hostile-3/csv_hostile.py): encodings, quoting, separators, units the header does
not give, and header fields long enough to make a quadratic guess take minutes."""
import pytest

from zuml_studio.cli.main import main
from zuml_studio.logs import csv_import, read_log

HEADER = "Zeit [s];Spannung [V];Strom [A]"


def rows(n=200, sep=";", comma=True):
    out = []
    for i in range(n):
        fields = [f"{i * 10.0:.1f}", f"{7.4 + i * 0.004:.3f}", "2.000"]
        out.append(sep.join(x.replace(".", ",") if comma else x for x in fields))
    return out


def text(header=HEADER, sep=";", comma=True, n=200):
    return "\n".join([header.replace(";", sep)] + rows(n, sep, comma)) + "\n"


def reads_the_200_rows(data: bytes):
    log = read_log(data, "x.csv")
    assert (log.format, len(log.samples), log.bad_records) == ("csv", 200, 0)
    assert log.samples[-1].time_s == 1990.0 and log.samples[-1].voltage_v == pytest.approx(8.196)
    assert log.samples[0].current_a == 2.0
    return log


@pytest.mark.parametrize("encoding", ["utf-16-le", "utf-16-be"])
def test_utf16_with_its_byte_order_mark_reads(encoding):
    # Excel's "Unicode text": UTF-16 with a BOM, tab separated
    reads_the_200_rows(("\ufeff" + text(sep="\t")).encode(encoding))


def test_rfc4180_quoted_fields_with_decimal_commas_read():
    body = ['"' + '","'.join(r.split(";")) + '"' for r in rows()]
    quoted = "\n".join([HEADER.replace(";", ",")] + body) + "\n"
    g = csv_import.guess(quoted.encode())
    assert (g.separator, g.decimal_comma) == (",", True)
    reads_the_200_rows(quoted.encode())


def test_pipe_separators_with_decimal_commas_read():
    g = csv_import.guess(text(sep="|").encode())
    assert (g.separator, g.decimal_comma) == ("|", True)       # not the ',' of the decimal commas
    reads_the_200_rows(text(sep="|").encode())


@pytest.mark.parametrize("encoding", ["cp1251", "utf-8"])
def test_russian_header_reads(encoding):
    reads_the_200_rows(text("Время [с];Напряжение [В];Ток [А]").encode(encoding))


def test_a_unit_the_header_does_not_give_is_said_and_the_plausible_reading_is_taken(capsys, tmp_path):
    # 60 with no unit: 60 A (no charger gives more; a pack at 60 mA is not what the log says either way,
    # so it is said); 120 with no unit: 120 V, not 0.12 V.
    body = [f"{i * 10};{120 + i * 0.01:.2f};60,0".replace(".", ",") for i in range(200)]
    path = tmp_path / "nounit.csv"
    path.write_text("\n".join(["Zeit;Spannung;Strom"] + body) + "\n")
    log = read_log(path.read_bytes(), path.name)
    assert log.samples[0].voltage_v == 120.0 and log.samples[0].current_a == 60.0
    said = log.meta["csv_assumed"]
    assert any(line.startswith("Strom: no unit in the header: read as A (largest value 60") for line in said)
    assert any(line.startswith("Spannung: no unit in the header: read as V (largest value 120.") for line in said)
    assert main(["log", "info", str(path)]) == 0
    out = capsys.readouterr().out
    assert "  assumed      Strom: no unit in the header: read as A" in out


def test_a_current_beyond_any_charger_without_a_unit_is_milliamperes_and_said():
    body = [f"{i * 10};7,4;{500 + i}" for i in range(50)]
    log = read_log(("\n".join(["Zeit;Spannung;Strom"] + body) + "\n").encode(), "x.csv")
    assert log.samples[0].current_a == 0.5
    assert any("read as mA" in line for line in log.meta["csv_assumed"])


def test_no_unit_is_assumed_where_the_header_gives_every_unit():
    assert "csv_assumed" not in read_log(text().encode(), "x.csv").meta


@pytest.mark.parametrize("field", ["(" * 50000, "cell" + " " * 50000 + "x", "_a" * 50000 + "!"])
def test_a_header_field_of_50000_characters_is_guessed(field):
    # Linear and bounded (the time is measured in benchmarks/bench_csv_guess.py): a name is read up to
    # csv_import.MAX_NAME characters.
    data = "\n".join([HEADER + ";" + field] + [r + ";1" for r in rows()]) + "\n"
    g = csv_import.guess(data.encode())
    assert [c.role for c in g.columns] == ["time", "voltage", "current", "-"]
    reads_the_200_rows(data.encode())


def test_a_discharge_logged_with_positive_current_is_a_discharge():
    # DataExplorer's export "Entladen" with positive current: its voltage falls under load
    body = [f"{i * 10};{8.2 - i * 0.01:.3f};2,0".replace(".", ",") for i in range(100)]
    log = read_log(("\n".join([HEADER] + body) + "\n").encode(), "x.csv")
    assert {p.state for p in log.phases()} == {"discharge"}
    assert log.samples[-1].current_a == -2.0 and log.samples[-1].mah_in == 0 and log.samples[-1].mah_out > 500


def test_record_set_blocks_each_restarting_at_zero_keep_every_row_and_their_direction():
    # A DataExplorer-style export: a block per record set, each from time 0; "Entladen" with positive current.
    blocks = []
    for n, (name, v0, dv) in enumerate([("1) Laden", 7.0, 0.005), ("2) Pause", 8.0, 0.0), ("3) Entladen", 8.0, -0.005)]):
        blocks.append("### RECORDSET\n# device=x recordset='%s' timestep_ms=10000.0 startTimeStamp_epoch_ms=%d\n"
                      % (name, 1_000_000 + n * 2_000_000) + "Zeit [s];Spannung [V];Strom [A]\n" + "\n".join(
                          f"{i * 10};{v0 + i * dv:.3f};{0 if 'Pause' in name else 2}".replace(".", ",")
                          for i in range(150)))
    log = read_log(("\n".join(blocks) + "\n").encode(), "sets.csv")
    assert (len(log.samples), log.bad_records) == (450, 0)
    assert log.meta["record_sets"] == ["1) Laden", "2) Pause", "3) Entladen"]
    assert [p.state for p in log.phases()] == ["charge", "pause", "discharge"]
    assert [log.samples[k].time_s for k in (0, 150, 300)] == [0.0, 2000.0, 4000.0]     # at their time stamps
    assert log.samples[-1].current_a == -2.0
    assert "time_order" not in log.meta


def test_a_named_pipe_given_as_a_log_is_refused_as_a_device_is(tmp_path, capsys):
    import os
    fifo = tmp_path / "log.csv"
    os.mkfifo(fifo)
    assert main(["log", "info", str(fifo)]) == 2                  # no writer: reading it would hang
    assert capsys.readouterr().err.strip().endswith(f"{fifo}: a named pipe, not a log file")
