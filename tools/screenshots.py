"""Refresh the screenshots in docs/: the main window (docs/screenshot*.png), the device panel
during a charge on the built-in virtual charger (docs/device-panel*.png) and the Visual tab with
the LiPo macro (docs/visual-editor*.png), in English and Russian.

    .venv/bin/python tools/screenshots.py            # both languages
    .venv/bin/python tools/screenshots.py --lang ru
    .venv/bin/python tools/screenshots.py --theme dark   # docs/screenshot-dark.png: the window, English
    .venv/bin/python tools/screenshots.py --weak-cell    # docs/sim-weak-cell*.png, docs/live-weak-cell.png

Each language runs in a process of its own: the language is chosen once, at start (ZUML_LANG).
Offscreen Qt; the virtual charger runs at its default speed, so the panel shows about 25 minutes
of a 2 A NiMH charge after a few seconds."""
from __future__ import annotations

import argparse
import os
import subprocess
import sys
import tempfile
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
DOCS = ROOT / "docs"
SUFFIX = {"en": "", "ru": "-ru"}
PANEL_SIZE = (1366, 360)
VISUAL_SIZE = (800, 650)
RUN_S = 6.0
THEME_ENV = "ZUML_SCREENSHOT_THEME"     # the theme of a part shot (--device-panel, --visual-editor)
WINDOW_SIZE = (1366, 768)
WEAK_PACK = {"capacity_mah": 2200, "series": 4, "current_a": 2.2}     # a 4S LiPo 2200 mAh pack charged at 1C
WEAK_PCT = 15
LIVE_SPEED = 300        # the virtual charger's speed: the whole charge (about 50 simulated minutes) in ten seconds


def _application():
    """The QApplication in the chosen language, collecting on the GUI thread as the app does."""
    os.environ.setdefault("QT_QPA_PLATFORM", "offscreen")
    from PySide6.QtWidgets import QApplication

    from zuml_studio import i18n
    from zuml_studio.ui.base.gui_thread_gc import collect_on_gui_thread
    from zuml_studio.ui.base.language import install_qt_catalogue

    i18n.install(i18n.choose_language())
    app = QApplication.instance() or QApplication([])
    install_qt_catalogue(i18n.current_language())
    if os.environ.get(THEME_ENV):
        from zuml_studio.ui.base.theme import apply_theme

        apply_theme(os.environ[THEME_ENV])
    return app, collect_on_gui_thread()


def _visual_shot(out: Path) -> None:
    """The Visual tab alone at 800x650 with the LiPo macro, as the window wires it."""
    app, collector = _application()
    from zuml_studio import data
    from zuml_studio.ui.editor.code_editor import CodeEditor
    from zuml_studio.ui.editor.validation import Validator
    from zuml_studio.ui.visual import VisualEditor

    editor = CodeEditor()
    editor.setPlainText((data.standard_macros_dir() / "LiPo.zuml").read_text(encoding="utf-8"))
    validator = Validator(delay_ms=10)
    view = VisualEditor(editor)
    validator.validated.connect(view.show_result)
    validator.run_now(editor.toPlainText())
    view.resize(*VISUAL_SIZE)
    view.show()
    for _round in range(20):
        app.processEvents()
    view.grab().save(str(out))
    collector.timer.stop()


def _panel_shot(out: Path) -> None:
    """The device panel alone, 1366 px wide, connected to the virtual charger during a charge."""
    app, collector = _application()
    from PySide6.QtCore import QEventLoop, QTimer

    from zuml_studio import data
    from zuml_studio.lang.compiler import compile_source
    from zuml_studio.ui.device import DevicePanel

    record = compile_source((data.standard_macros_dir() / "NiMh-dV.zuml").read_text(encoding="utf-8")).record
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


def _settle(app, ms: int = 400) -> None:
    from PySide6.QtCore import QCoreApplication, QEvent, QEventLoop, QTimer

    loop = QEventLoop()
    QTimer.singleShot(ms, loop.quit)
    loop.exec()
    QCoreApplication.sendPostedEvents(None, QEvent.Type.DeferredDelete)
    app.processEvents()


def _window(config: Path):
    from zuml_studio.ui import create_main_window

    window = create_main_window(str(ROOT / "macros/LiPo.zuml"), config)
    window.ask_unsaved = lambda: "discard"
    window.ask_close_run = lambda: "stop"
    window.resize(*WINDOW_SIZE)
    window.show()
    return window


def _sim_weak_shot(out: Path, config: Path) -> None:
    """The window in Simulate mode: the standard LiPo macro on a 4S 2200 mAh pack with its top cell
    WEAK_PCT % weaker, the run's last phase (ended by the balancer's per-cell ceiling) selected."""
    app, collector = _application()
    window = _window(config)
    window.switch_mode("simulate")
    panel = window.sim_panel
    panel.form.set_values(**WEAK_PACK, weak_cell_pct=WEAK_PCT)
    window.validate_now()
    panel.simulate()
    if not panel.wait(120_000) or panel.result() is None:
        raise SystemExit(f"screenshots: the simulation did not finish: {panel.message_text()}")
    panel.table.selectRow(len(panel.result().phases) - 1)
    sizes = panel.splitter.sizes()          # room for the phase table's end reasons
    wider = 240
    panel.splitter.setSizes([sizes[0] + wider, sizes[1] - wider, *sizes[2:]] if panel.is_tall()
                            else [sizes[0], sizes[1] - wider, sizes[2] + wider])
    _settle(app)
    window.grab().save(str(out))
    window.close()
    collector.timer.stop()


def _live_weak_shot(out: Path, config: Path) -> None:
    """The window in Charge mode: the virtual charger with the same pack charging by the same macro
    at high speed, to its end (the phases' end reasons, the balancer's ceiling that ended it)."""
    app, collector = _application()
    from PySide6.QtCore import QEventLoop, QTimer

    from zuml_studio.ui.device import unsafe_dialog

    unsafe_dialog.confirm_warnings = lambda *args: True     # the lint's warnings: go ahead, no modal dialog
    window = _window(config)
    window.switch_mode("charge")
    panel = window.device_panel
    bar = panel.bar
    bar.v_chem.setCurrentIndex(bar.v_chem.findData("LiPo"))
    bar.v_mah.setValue(WEAK_PACK["capacity_mah"])
    bar.v_cells.setValue(WEAK_PACK["series"])
    bar.v_weak.setValue(WEAK_PCT)
    bar.v_speed.setValue(LIVE_SPEED)

    def until(signal, what: str) -> None:
        got: list = []
        loop = QEventLoop()
        signal.connect(lambda *args: (got.append(args), loop.quit()))
        QTimer.singleShot(30_000, loop.quit)
        loop.exec()
        if not got:
            raise SystemExit(f"screenshots: the virtual charger did not answer ({what}): {panel.message_text()}")

    if not panel.connect_to("virtual"):
        raise SystemExit(f"screenshots: cannot start the virtual charger: {panel.message_text()}")
    until(panel.connectedChanged, "connect")
    _settle(app, 1000)
    panel.flash()
    until(panel.flashFinished, "flash")
    panel.set_start_params(current_a=WEAK_PACK["current_a"], sensor=True)
    panel.start()
    until(panel.startFinished, "start")
    until(panel.runEnded, "the end of the charge")
    _settle(app, 1000)                  # the frames after the end: the run's last counters, the phases' line
    window.grab().save(str(out))
    panel.shutdown()
    window.close()
    collector.timer.stop()
    app.processEvents()


def _weak_cell_shots() -> None:
    """docs/sim-weak-cell.png (light, English), docs/sim-weak-cell-ru-dark.png (dark, Russian),
    docs/live-weak-cell.png (light, English); each window with a settings folder of its own."""
    for kind, language, theme, name in (("sim", "en", "light", "sim-weak-cell.png"),
                                        ("sim", "ru", "dark", "sim-weak-cell-ru-dark.png"),
                                        ("live", "en", "light", "live-weak-cell.png")):
        with tempfile.TemporaryDirectory() as config:
            Path(config, "settings.ini").write_text(f"[appearance]\ntheme={theme}\n", encoding="utf-8")
            env = dict(os.environ, ZUML_LANG=language, QT_QPA_PLATFORM="offscreen", ZUML_STUDIO_CONFIG_DIR=config)
            subprocess.run([sys.executable, __file__, f"--{kind}-weak-cell", str(DOCS / name), "--config", config],
                           env=env, check=True)
        print(f"docs/{name}")


def _shots(language: str) -> None:
    env = dict(os.environ, ZUML_LANG=language, QT_QPA_PLATFORM="offscreen")
    suffix = SUFFIX[language]
    window = DOCS / f"screenshot{suffix}.png"
    subprocess.run([sys.executable, "-m", "zuml_studio.ui.app", str(ROOT / "macros/NiMh.zuml"),
                    "--screenshot", str(window)], env=env, check=True)
    for kind in ("device-panel", "visual-editor"):
        subprocess.run([sys.executable, __file__, f"--{kind}", str(DOCS / f"{kind}{suffix}.png")], env=env, check=True)
    print(f"{language}: docs/screenshot{suffix}.png, docs/device-panel{suffix}.png, docs/visual-editor{suffix}.png")


def _dark_shot() -> None:
    """The main window in English in the dark theme (a settings file of its own chooses it)."""
    with tempfile.TemporaryDirectory() as config:
        Path(config, "settings.ini").write_text("[appearance]\ntheme=dark\n", encoding="utf-8")
        env = dict(os.environ, ZUML_LANG="en", QT_QPA_PLATFORM="offscreen", ZUML_STUDIO_CONFIG_DIR=config)
        out = DOCS / "screenshot-dark.png"
        subprocess.run([sys.executable, "-m", "zuml_studio.ui.app", str(ROOT / "macros/NiMh.zuml"),
                        "--screenshot", str(out)], env=env, check=True)
    print("dark: docs/screenshot-dark.png")


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--lang", choices=["en", "ru", "all"], default="all")
    parser.add_argument("--theme", choices=["light", "dark"], default="light",
                        help="dark: only docs/screenshot-dark.png, the window in English in the dark theme")
    parser.add_argument("--device-panel", metavar="OUT.png", help=argparse.SUPPRESS)
    parser.add_argument("--visual-editor", metavar="OUT.png", help=argparse.SUPPRESS)
    parser.add_argument("--weak-cell", action="store_true",
                        help="only the pictures of a 4S LiPo pack with a weak cell (simulator, live view)")
    parser.add_argument("--sim-weak-cell", metavar="OUT.png", help=argparse.SUPPRESS)
    parser.add_argument("--live-weak-cell", metavar="OUT.png", help=argparse.SUPPRESS)
    parser.add_argument("--config", help=argparse.SUPPRESS)
    args = parser.parse_args()
    if args.sim_weak_cell:
        _sim_weak_shot(Path(args.sim_weak_cell), Path(args.config))
        return
    if args.live_weak_cell:
        _live_weak_shot(Path(args.live_weak_cell), Path(args.config))
        return
    if args.weak_cell:
        _weak_cell_shots()
        return
    if args.theme == "dark" and not (args.device_panel or args.visual_editor):
        _dark_shot()
        return
    if args.theme == "dark":
        os.environ[THEME_ENV] = "dark"
    if args.device_panel:
        _panel_shot(Path(args.device_panel))
        return
    if args.visual_editor:
        _visual_shot(Path(args.visual_editor))
        return
    for language in (["en", "ru"] if args.lang == "all" else [args.lang]):
        _shots(language)


if __name__ == "__main__":
    main()
