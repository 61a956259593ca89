"""A live run recorded into its pack: the collected telemetry written, read back and imported."""
import threading

import pytest

from zuml_studio.logs import read_log_file
from zuml_studio.packs.db import Logbook
from zuml_studio.packs.figures import session_figures
from zuml_studio.packs.health import health
from zuml_studio.packs.live import RunCollector, record_run
from zuml_studio.packs.register import add_pack
from zuml_studio.packs.sessions import pack_sessions

DATA = __import__("pathlib").Path(__file__).resolve().parents[1] / "data" / "logs"


def test_a_collected_run_becomes_a_live_session_with_the_logs_figures(tmp_path):
    log = read_log_file(DATA / "406DUO_Turnigy_4S_1500_A_Charge_0_CH1.txt")
    collector = RunCollector()
    collector.add(log.samples[0])                      # before START: not the run's
    collector.start()
    reader = threading.Thread(target=lambda: [collector.add(s) for s in log.samples])   # as the reader thread
    reader.start()
    reader.join()
    samples = collector.take()
    assert len(samples) == len(log.samples) and not collector.collecting
    book = Logbook(tmp_path / "p.sqlite3")
    pack = add_pack(book, "Turnigy 4S #2", "LiPo", 4, 1500)
    result = record_run(book, pack, samples, "iCharger 406DUO", passport=(2, 0), folder=tmp_path / "runs")
    assert result.status == "added", result.message
    (session,) = pack_sessions(book, pack)
    assert (session.source, session.recorded_from, session.passport_errors, session.passport_critical) == (
            "live", "run", 2, 0)
    expected = session_figures(log, 4)
    got = session.figures
    assert got.charge_in_mah == pytest.approx(expected.charge_in_mah, abs=0.5)
    assert got.energy_in_wh == pytest.approx(expected.energy_in_wh, rel=1e-3)
    assert got.cell_deviation_mv == pytest.approx(expected.cell_deviation_mv, abs=0.5)
    assert got.t_max_c == pytest.approx(expected.t_max_c, abs=0.05)
    assert any("passport counts 2 errors" in r for r in health(pack, [session]).reasons)


def test_a_run_with_no_sample_is_not_a_session(tmp_path):
    book = Logbook(tmp_path / "p.sqlite3")
    pack = add_pack(book, "P", "LiPo", 4, 1500)
    assert record_run(book, pack, [], "x", folder=tmp_path).status == "error"
    assert pack_sessions(book, pack) == []
