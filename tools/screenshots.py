"""Refresh the screenshots in docs/: the main window (docs/screenshot*.png) and the device panel
during a charge on the built-in virtual charger (docs/device-panel*.png), in English and Russian.

    .venv/bin/python tools/screenshots.py            # both languages
    .venv/bin/python tools/screenshots.py --lang ru

Each language runs in a process of its own: the language is chosen once, at start (ZUML_LANG).
Offscreen Qt; the virtual charger runs at its default speed, so the panel shows about 25 minutes
of a 2 A NiMH charge after a few seconds."""
from __future__ import annotations

import argparse
import os
import subprocess
import sys
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
DOCS = ROOT / "docs"
SUFFIX = {"en": "", "ru": "-ru"}
PANEL_SIZE = (1366, 360)
RUN_S = 6.0


def _panel_shot(out: Path) -> None:
    """The device panel alone, 1366 px wide, connected to the virtual charger during a charge."""
    os.environ.setdefault("QT_QPA_PLATFORM", "offscreen")
    from PySide6.QtCore import QEventLoop, QTimer
    from PySide6.QtWidgets import QApplication

    from zuml_studio import data, i18n
    from zuml_studio.lang.compiler import compile_source
    from zuml_studio.ui.device import DevicePanel
    from zuml_studio.ui.gui_thread_gc import collect_on_gui_thread
    from zuml_studio.ui.language import install_qt_catalogue

    i18n.install(i18n.choose_language())
    app = QApplication.instance() or QApplication([])
    install_qt_catalogue(i18n.current_language())
    collector = collect_on_gui_thread()
    record = compile_source(data.read_text("macros/NiMh-dV.zuml")).record
    sessions = Path(os.environ.get("TMPDIR", "/tmp")) / "zuml-screenshot-sessions"
    panel = DevicePanel(lambda: (record, "NiMh-dV"), sessions, port_lister=lambda: [])
    panel.resize(*PANEL_SIZE)
    panel.show()

    def spin(seconds: float) -> None:
        loop = QEventLoop()
        QTimer.singleShot(int(seconds * 1000), loop.quit)
        loop.exec()

    def until(signal, what: str) -> list:
        got: list = []
        loop = QEventLoop()
        signal.connect(lambda *args: (got.extend(args), loop.quit()))
        QTimer.singleShot(30_000, loop.quit)
        loop.exec()
        if not got:
            raise SystemExit(f"screenshots: the virtual charger did not answer ({what}): {panel.message_text()}")
        return got

    if not panel.connect_to("virtual"):
        raise SystemExit(f"screenshots: cannot start the virtual charger: {panel.message_text()}")
    until(panel.connectedChanged, "connect")
    spin(1.0)
    panel.flash()
    until(panel.flashFinished, "flash")
    panel.set_start_params(current_a=2.0, sensor=True)
    panel.start()
    until(panel.startFinished, "start")
    spin(RUN_S)
    panel.grab().save(str(out))
    panel.shutdown()
    collector.timer.stop()
    app.processEvents()


def _shots(language: str) -> None:
    env = dict(os.environ, ZUML_LANG=language, QT_QPA_PLATFORM="offscreen")
    suffix = SUFFIX[language]
    window = DOCS / f"screenshot{suffix}.png"
    subprocess.run([sys.executable, "-m", "zuml_studio.ui.app", str(ROOT / "zuml_studio/data/macros/NiMh.zuml"),
                    "--screenshot", str(window)], env=env, check=True)
    subprocess.run([sys.executable, __file__, "--panel-only", str(DOCS / f"device-panel{suffix}.png")], env=env,
                   check=True)
    print(f"{language}: {window.relative_to(ROOT)}, docs/device-panel{suffix}.png")


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--lang", choices=["en", "ru", "all"], default="all")
    parser.add_argument("--panel-only", metavar="OUT.png", help=argparse.SUPPRESS)
    args = parser.parse_args()
    if args.panel_only:
        _panel_shot(Path(args.panel_only))
        return
    for language in (["en", "ru"] if args.lang == "all" else [args.lang]):
        _shots(language)


if __name__ == "__main__":
    main()
