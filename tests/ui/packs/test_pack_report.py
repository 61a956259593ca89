"""Issue 33 §4 end to end: a folder of real logs of one pack in two formats (an Ultramat's .osd and the
record-set CSV exported from it) and another pack's log imports with each session dated by its log, the
charge kept once with both files listed, capacity only from a full discharge, in/out within 2 % of the
current integrated independently, the foreign log skipped with its reason; the report draws it all."""
import lzma
import shutil

import numpy as np
from PySide6.QtGui import QImage, QPainter

from helpers import ROOT
from zuml_studio.logs import read_log_file
from zuml_studio.packs.db import Logbook
from zuml_studio.packs.health import trend
from zuml_studio.packs.register import add_pack
from zuml_studio.packs.report_data import model_lines, session_curves
from zuml_studio.packs.sessions import import_files, pack_sessions
from zuml_studio.packs.summary import pack_summary
from zuml_studio.ui.packs.report import PAGE, paint_report

LOGS = ROOT / "tests" / "data" / "logs"
REAL = ROOT / "tests" / "data" / "realdata"


class _Recording(QPainter):
    """Keeps every text the report draws."""
    def __init__(self, device):
        super().__init__(device)
        self.texts = []

    def drawText(self, *args):
        self.texts.append(args[-1])
        return super().drawText(*args)


def _integrated(path):
    """In and out (mAh) as a plain trapezoid of the log's current, steps over a minute left out."""
    c = read_log_file(path).columns
    dt = np.diff(c.t)
    ok = (dt > 0) & (dt <= 60.0)
    mean = (c.current[1:] + c.current[:-1]) / 2.0
    return (float((np.clip(mean, 0, None) * dt)[ok].sum() / 3.6),
            float((-np.clip(mean, None, 0) * dt)[ok].sum() / 3.6))


def test_a_folder_of_one_packs_logs_imports_truthfully_and_the_report_shows_it(qapp, tmp_path):
    folder = tmp_path / "logs"
    folder.mkdir()
    shutil.copy(LOGS / "UltramatACDCEQ_2014-09-16_4S_NiMH_cycle.osd", folder / "cycle.osd")
    (folder / "cycle_export.csv").write_bytes(lzma.decompress((REAL / "NiMH_4S_Ultramat_ACDC_EQ_cycle.csv.xz")
                                                              .read_bytes()))
    shutil.copy(LOGS / "PolaronACDC_2014-08-15_LiIo_2_4000.osd", folder / "other.osd")
    book = Logbook(tmp_path / "book.sqlite3")
    pack = add_pack(book, "Ultramat 4S", "NiMH", 4, 2000)
    results = {r.path.rsplit("/", 1)[-1]: r for r in import_files(book, pack, [folder])}

    assert results["other.osd"].status == "foreign" and "2 cells" in results["other.osd"].message
    assert sorted(r.status for r in results.values()) == ["added", "foreign", "known"]   # the charge once
    sessions = pack_sessions(book, pack)
    assert len(sessions) == 1
    s = sessions[0]
    assert (s.recorded[:10], s.recorded_from) == ("2014-09-15", "log")        # its own date, not the file's
    assert len(s.as_dict()["same_files"]) == 1                                # both files listed
    assert s.figures.capacity_from == "discharge" and s.figures.capacity_mah > 0
    q_in, q_out = _integrated(folder / "cycle.osd")
    assert abs(s.figures.charge_in_mah - q_in) <= 0.02 * q_in
    assert abs(s.figures.charge_out_mah - q_out) <= 0.02 * q_out

    curves, missing = session_curves(pack, sessions)
    assert len(curves) == 1 and not missing
    image = QImage(PAGE[0], PAGE[1], QImage.Format.Format_RGB32)
    painter = _Recording(image)
    paint_report(painter, pack_summary(book, pack), trend(pack, sessions), curves, model_lines(None))
    painter.end()
    text = "\n".join(painter.texts)
    for shown in ("Ultramat 4S", "2014-09-15", f"{s.figures.capacity_mah:.0f}", f"{s.figures.charge_in_mah:.0f}",
                  "Cell drift", "Voltage per cell", "The model fitted to this pack", "–"):
        assert shown in text, shown
