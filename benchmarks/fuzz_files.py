"""Fuzz every reader of a file the user (or a hand-edited config) hands the program: macro files
in any encoding, curve CSVs and logs for `zuml fit`/`compare`, named battery files, crash-recovery
files, settings.ini, charger recordings for replay, and paths that are no file at all (missing,
a folder, empty, a device). Each input runs under fuzz_common.LIMIT_S (the fit: FIT_LIMIT_S).

Run from the repository root:  python benchmarks/fuzz_files.py [N [SEED [PARSER ...]]]
(N inputs per parser, default 20000; the fit gets N // 100, it takes up to seconds an input).
Prints per parser: inputs, crashes, hangs, the first of each kind, seconds; then a table.
A reader may raise only its own error (MacroFileError, CurveError, ...), and what it accepts
must be sound (finite numbers, the types the caller expects).
"""
from __future__ import annotations

import json
import math
import os
import random
import sys
import tempfile
from dataclasses import fields
from pathlib import Path

os.environ.setdefault("QT_QPA_PLATFORM", "offscreen")
ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(Path(__file__).resolve().parent))

from fuzz_common import Campaign, mutate_bytes, number_swap  # noqa: E402
from zuml_studio.device.drivers import CaptureError  # noqa: E402
from zuml_studio.device.replay import load_recording  # noqa: E402
from zuml_studio.file_errors import FileReadError  # noqa: E402
from zuml_studio.lang.compiler import compile_source  # noqa: E402
from zuml_studio.logs import LogFormatError  # noqa: E402
from zuml_studio.macro_file import MacroFileError, read_macro_file  # noqa: E402
from zuml_studio.recovery import RecoveryStore  # noqa: E402
from zuml_studio.sim.batteries import BatteryFileError, battery_names, load_battery  # noqa: E402
from zuml_studio.sim.chemistry import Chemistry  # noqa: E402
from zuml_studio.sim.curve import CurveError, read_curve, read_curve_csv  # noqa: E402
from zuml_studio.sim.fit import guess_series  # noqa: E402
from zuml_studio.sim.fit_discharge import fit_curve  # noqa: E402

DATA = ROOT / "tests" / "data"
FIT_LIMIT_S = 20.0
MACROS = [p.read_bytes() for p in sorted([*(ROOT / "macros").glob("*.zuml"),
                                          *DATA.glob("*.zuml")])]
CURVES = [p.read_bytes() for p in sorted((DATA / "curves").glob("*.csv"))]
LOGS = [p.read_bytes()[:20000] for p in sorted((DATA / "logs").iterdir())]
RECORDINGS = [p.read_bytes()[:8000] for p in sorted((DATA / "realdata").glob("*.txt"))]
BATTERY = {"format": 1, "name": "Pack A", "chemistry": "NiMh", "capacity_mah": 2000.0, "series": 4,
           "fitted_from": "x.csv", "parameters": {"r0_ohm": 0.02, "tau1_s": 30.0, "ocv_soc": [0.0, 0.5, 1.0],
                                                  "ocv_v": [1.1, 1.25, 1.4], "dip_v_per_charge": 0.004}}
PIECES = (b"\x00", b"\xef\xbb\xbf", b"\r", b"\r\n", b"\xff\xfe", b"nan", b"inf", b"-1e999", b"9" * 400,
          b"\xd0\x9f\xd1\x80\xd0\xb8", b"\xe2\x80\xae", b",,,,", b'"', b"#", b"\n" * 50, b"x" * 100000)
assert MACROS and CURVES and LOGS and RECORDINGS, "the fuzzer's seeds moved"


def encodings(rng: random.Random, data: bytes) -> bytes:
    """The same macro as another editor may have saved it: a BOM, CRLF, UTF-16, a legacy code page."""
    text = data.decode("utf-8-sig") + rng.choice(["", "\n// Заряд 4S — ½C\n", "\n// 充电\n", "\n// nabíjení\n"])
    kind = rng.randrange(6)
    if kind == 0:
        return b"\xef\xbb\xbf" + text.encode()
    if kind == 1:
        return text.replace("\n", "\r\n").encode()
    if kind == 2:
        return text.encode(rng.choice(["utf-16", "utf-16-le", "utf-32"]))
    if kind == 3:
        return text.encode(rng.choice(["cp1251", "koi8-r", "cp1250", "gb18030"]), "replace")
    if kind == 4:
        return text.replace("\n", "\r").encode()
    return text.encode()


def mutated_file(rng: random.Random, seeds: list[bytes]) -> bytes:
    choice = rng.random()
    if choice < 0.05:
        return b""
    if choice < 0.15:
        return rng.randbytes(rng.randint(1, 3000))
    data = rng.choice(seeds)
    if choice < 0.35:
        return data[:rng.randrange(len(data) + 1)]
    if choice < 0.55:
        text = data.decode("utf-8", "replace")
        for _ in range(rng.randint(1, 3)):
            text = number_swap(rng, text[rng.randrange(len(text) + 1):] if rng.random() < 0.1 else text)
        return text.encode()
    return mutate_bytes(rng, data, PIECES)


class Files:
    """Puts each input where a reader finds it; a few inputs are not files at all."""
    SPECIAL = ("missing", "folder", "device", "empty")

    def __init__(self, root: Path):
        self.root = root
        (root / "a folder.zuml").mkdir(exist_ok=True)

    def place(self, item: bytes | str, name: str = "input.zuml") -> Path:
        if item == "missing":
            return self.root / "no such file"
        if item == "folder":
            return self.root / "a folder.zuml"
        if item == "device":
            return Path("/dev/zero")
        path = self.root / name
        path.write_bytes(b"" if item == "empty" else item)
        return path


def sometimes_special(rng: random.Random, make):
    return rng.choice(Files.SPECIAL) if rng.random() < 0.02 else make(rng)


def finite_battery(battery) -> None:
    """What load_battery accepts must be a battery the simulator can run: every number finite."""
    values = [battery.capacity_mah, battery.series]
    for f in fields(Chemistry):
        v = getattr(battery.chem, f.name)
        values += list(v) if isinstance(v, tuple) else [v] if isinstance(v, (int, float)) else []
    bad = [v for v in values if isinstance(v, float) and not math.isfinite(v)]
    assert not bad, f"load_battery accepted non-finite numbers {bad}"


def main() -> int:
    n = int(sys.argv[1]) if len(sys.argv) > 1 else 20000
    seed = int(sys.argv[2]) if len(sys.argv) > 2 else 1
    wanted = set(sys.argv[3:])
    c = Campaign(seed)
    tmp = Path(tempfile.mkdtemp(prefix="zuml-fuzz-files-"))
    files = Files(tmp)
    os.environ["ZUML_STUDIO_CONFIG_DIR"] = str(tmp / "config")
    total = 0

    def want(name: str) -> bool:
        return not wanted or name in wanted

    # -- macro files ------------------------------------------------------------------------
    def macro_file(rng):
        if rng.random() < 0.3:
            return encodings(rng, rng.choice(MACROS))
        return mutated_file(rng, MACROS)

    def open_and_compile(item):
        compile_source(read_macro_file(files.place(item)).text)

    if want("macro file"):
        total += c.run("macro file", n, lambda rng: sometimes_special(rng, macro_file), open_and_compile,
                       (MacroFileError,))

    # -- curve CSVs and logs for zuml fit / compare ----------------------------------------
    def curve_text(item):
        curve = read_curve_csv(item.decode("utf-8", "replace"), "fuzz.csv")
        curve.decimated(30.0)
        assert all(math.isfinite(x) for x in curve.mah), "a curve's charge is not finite"

    if want("curve CSV"):
        total += c.run("curve CSV", n, lambda rng: mutated_file(rng, CURVES), curve_text, (CurveError,))

    def curve_file(item):
        curve = read_curve(files.place(item, "input.csv"))
        assert len(curve.t) == len(curve.v) == len(curve.i), "a curve's columns differ in length"

    if want("curve file"):
        total += c.run("curve file", n, lambda rng: sometimes_special(rng, lambda r: mutated_file(r, CURVES + LOGS)),
                       curve_file, (FileReadError, LogFormatError, CurveError))

    def fit_file(item):
        curve = read_curve(files.place(item, "input.csv"))
        chemistry = curve.chemistry if curve.chemistry in ("NiMh", "NiCd", "LiPo", "LiIon", "LiFe", "Pb") else "NiMh"
        result = fit_curve(curve.decimated(60.0), chemistry, guess_series(curve, chemistry))
        finite_battery(result.battery)

    if want("fit"):
        total += c.run("fit", max(20, n // 100), lambda rng: mutated_file(rng, CURVES), fit_file,
                       (FileReadError, LogFormatError, CurveError), FIT_LIMIT_S)

    # -- named battery files --------------------------------------------------------------------
    folder = tmp / "config" / "batteries"
    folder.mkdir(parents=True, exist_ok=True)
    seed_doc = json.dumps(BATTERY, indent=2).encode()

    def battery_doc(rng):
        if rng.random() < 0.3:
            doc = json.loads(seed_doc)
            key = rng.choice(list(doc) + list(doc["parameters"]))
            target = doc if key in doc else doc["parameters"]
            target[key] = rng.choice([None, [], {}, "x", -1, 0, 1e999, float("nan"), 10 ** 400, True, [1, "a"],
                                      -1e999, 2 ** 70, "NiMh"])
            return json.dumps(doc).encode()
        return mutated_file(rng, [seed_doc])

    def load_named(item):
        (folder / "Pack_A.json").write_bytes(item)
        battery_names(tmp / "config")
        finite_battery(load_battery("Pack A", tmp / "config"))

    if want("battery file"):
        total += c.run("battery file", n, battery_doc, load_named, (BatteryFileError,))

    # -- crash-recovery files --------------------------------------------------------------------
    store = RecoveryStore(tmp / "config")
    store.root.mkdir(parents=True, exist_ok=True)
    note = json.dumps({"original": "/home/u/a.zuml", "saved_at": 1.7e9, "pid": 1}).encode()

    def recovery_files(rng):
        if rng.random() < 0.3:
            doc = json.loads(note)
            doc[rng.choice(list(doc))] = rng.choice([None, [], {}, "x", -1, 1e999, float("nan"), 10 ** 400, True,
                                                     2 ** 70, 5])
            note_bytes = json.dumps(doc).encode()
        else:
            note_bytes = mutated_file(rng, [note]) if rng.random() < 0.9 else b"[1, 2]"
        return note_bytes, mutated_file(rng, MACROS)

    def pending(item):
        note_bytes, text = item
        (store.root / "0123456789abcdef.json").write_bytes(note_bytes)
        (store.root / "0123456789abcdef.zuml").write_bytes(text)
        for found in store.pending():
            assert found.original is None or isinstance(found.original, str), f"original {found.original!r}"
            assert isinstance(found.saved_at, (int, float)) and math.isfinite(found.saved_at), \
                f"saved_at {found.saved_at!r}"

    if want("recovery file"):
        total += c.run("recovery file", n, recovery_files, pending, ())

    # -- settings.ini, edited by hand --------------------------------------------------------------
    if want("settings.ini"):
        total += settings_fuzz(c, n, tmp)

    # -- recordings for zuml replay and the monitor's replay ---------------------------------------
    def recording(item):
        rec = load_recording(item)
        assert all(math.isfinite(t) and t >= 0 for t, _chunk in rec.records), "a record time is not finite"

    if want("recording"):
        total += c.run("recording", n, lambda rng: mutated_file(rng, RECORDINGS), recording, (CaptureError,))

    c.table()
    print(f"total findings: {total}")
    return 1 if total else 0


def settings_fuzz(c: Campaign, n: int, tmp: Path) -> int:
    """settings.ini as a user may have edited it: every value the window reads, garbled."""
    from PySide6.QtCore import QSettings
    from PySide6.QtWidgets import QApplication, QMainWindow
    from zuml_studio.ui.base.language import saved_preference
    from zuml_studio.ui.window.main_window import MainWindow
    from zuml_studio.ui.window.preferences import Preferences
    from zuml_studio.ui.base.settings_values import bytes_value, text_value

    app = QApplication.instance() or QApplication([])
    window = QMainWindow()
    config = tmp / "settings"
    config.mkdir(exist_ok=True)
    seed = (b"[General]\nlastDir=/home/u/macros\nrecentFiles=/home/u/a.zuml, /home/u/b.zuml\n"
            b"lastOpen=/home/u/a.zuml\ngeometry=@ByteArray(\\x1\\xd9\\xd0\\xcb\\0\\x3\\0\\0)\n"
            b"windowState=@ByteArray(\\0\\0\\0\\xff\\0\\0)\nlastLogDir=/home/u/logs\n\n"
            b"[editor]\nfontSize=12\n\n[appearance]\ntheme=dark\nlanguage=ru\n")
    values = (b"@ByteArray(", b"@Variant(\\0\\0\\0\\x7f\\0\\0\\0\\x18", b"@Invalid()", b", ", b"\\", b"\"",
              b"@Size(1 2)", b"@Rect(0 0 -5 99999999)", b"@Point(1 2)", b"nan", b"99999999999999999999", b"=")

    class Settings:
        """The window's reading of its settings, on a QSettings (MainWindow's methods need only that)."""
        def __init__(self, settings):
            self.settings = settings

    def read(item):
        (config / "settings.ini").write_bytes(item)
        settings = QSettings(str(config / "settings.ini"), QSettings.Format.IniFormat)
        Preferences.load(settings)
        saved_preference(config)
        MainWindow.recent_files(Settings(settings))
        geometry, state = bytes_value(settings, "geometry"), bytes_value(settings, "windowState")
        if geometry is not None:                         # as MainWindow._restore_layout
            window.restoreGeometry(geometry)
        if state is not None:
            window.restoreState(state, 1)
        for key in ("lastDir", "lastOpen", "lastLogDir"):
            value = text_value(settings, key, "")
            assert isinstance(value, str), f"{key} reads as {type(value).__name__} {value!r}"

    result = c.run("settings.ini", n, lambda rng: mutate_bytes(rng, seed, values), read, ())
    window.deleteLater()
    app.processEvents()
    return result


if __name__ == "__main__":
    sys.exit(main())
