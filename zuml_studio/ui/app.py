"""``zuml-studio [FILE] [--screenshot OUT.png]``: the application entry point."""
from __future__ import annotations

import argparse
import os
import sys

from .. import i18n
from ..i18n import _


def build_parser() -> argparse.ArgumentParser:
    parser = argparse.ArgumentParser(prog="zuml-studio", description=_("The IDE for ZUML 2.0 charger macros."))
    parser.add_argument("file", nargs="?", metavar="FILE", help=_("a .zuml macro to open"))
    parser.add_argument("--screenshot", metavar="OUT.png",
                        help=_("render the window offscreen with FILE open, checked and simulated, save it, exit"))
    parser.add_argument("--size", default="1600x1000", metavar="WxH", help=_("window size for --screenshot"))
    return parser


def _ensure_streams() -> None:
    """A windowed Windows build (pythonw, PyInstaller --windowed) has no stdout/stderr: writing a
    warning or a traceback there would raise. Send them to a log beside the settings instead."""
    if sys.stdout is not None and sys.stderr is not None:
        return
    from ..user_dirs import config_dir

    try:
        folder = config_dir()
        folder.mkdir(parents=True, exist_ok=True)
        log = open(folder / "zuml-studio.log", "a", encoding="utf-8", buffering=1)
    except OSError:
        log = open(os.devnull, "w", encoding="utf-8")
    if sys.stdout is None:
        sys.stdout = log
    if sys.stderr is None:
        sys.stderr = log


def data_errors_shown(previous):
    """An excepthook that also shows a broken installation's DataFileError in a dialog: one raised
    in a slot (a chemistry first used while typing) would otherwise reach only a console."""
    def hook(kind, exc, tb):
        from PySide6.QtWidgets import QMessageBox

        from ..data import DataFileError

        previous(kind, exc, tb)
        if isinstance(exc, DataFileError):
            QMessageBox.critical(None, "ZUML Studio", str(exc))
    return hook


def _install_language() -> str:
    """Our language, before the command line is parsed (its help is translated) and before any
    window is built (every text is translated where it is made)."""
    from ..user_dirs import config_dir
    from .base.language import install_language, saved_preference

    return install_language(saved_preference(config_dir()))


def main(argv: list[str] | None = None) -> int:
    _ensure_streams()
    from ..data import DataFileError
    try:
        language = _install_language()
    except DataFileError as exc:
        sys.stderr.write(f"zuml-studio: error: {exc}\n")
        return 2
    i18n.translate_argparse()          # its usage:, options and errors in the same language as the rest
    args = build_parser().parse_args(argv)
    if args.screenshot:
        os.environ.setdefault("QT_QPA_PLATFORM", "offscreen")
    from .base.qt_platform_libs import check

    lacking = check()
    if lacking:          # Qt would abort with a misleading message; say what is wrong instead
        sys.stderr.write(f"zuml-studio: {lacking}")
        return 1
    from PySide6.QtGui import QIcon
    from PySide6.QtWidgets import QApplication, QMessageBox

    from .. import APP_ID, data
    from . import create_main_window
    from .base.gui_thread_gc import collect_on_gui_thread
    from .base.language import install_qt_catalogue

    app = QApplication.instance() or QApplication(sys.argv[:1])
    app.setApplicationName("ZUML Studio")
    app.setOrganizationName("ZUML Studio")
    app.setDesktopFileName(APP_ID)
    app.collector = collect_on_gui_thread()
    try:
        install_qt_catalogue(language)
    except DataFileError as exc:
        sys.stderr.write(f"zuml-studio: error: {exc}\n")
        return 2
    if args.file and not os.path.isfile(args.file):
        sys.stderr.write("zuml-studio: error: " + _("{file}: no such file").format(file=args.file) + "\n")
        return 2
    try:
        app.setWindowIcon(QIcon(str(data.file_path("icon.svg"))))
        window = create_main_window(args.file)
    except DataFileError as exc:
        sys.stderr.write(f"zuml-studio: error: {exc}\n")
        if not args.screenshot:
            QMessageBox.critical(None, "ZUML Studio", str(exc))
        return 2
    if args.screenshot:
        return _screenshot(app, window, args.screenshot, args.size)
    sys.excepthook = data_errors_shown(sys.excepthook)
    window.show()
    window.offer_recovery()
    return run_windows(app, window, _rebuilt)


def run_windows(app, window, rebuild) -> int:
    """The event loop, again for each window closed by Restart Now (``window.restart_wanted``):
    ``rebuild(path)`` makes the next one, with the file the last one had open."""
    while True:
        code = app.exec()
        if not getattr(window, "restart_wanted", False):
            return code
        window = rebuild(window.path)


def _rebuilt(path: str | None):
    """The window built again after Restart Now, in the language now chosen."""
    from ..user_dirs import config_dir
    from . import create_main_window
    from .base.language import reinstall

    reinstall(config_dir())
    window = create_main_window(path)
    window.show()
    return window


SETTLE_MS = 300


def _screenshot(app, window, out: str, size: str) -> int:
    from PySide6.QtCore import QCoreApplication, QEvent, QEventLoop, QTimer

    try:
        width, height = (int(x) for x in size.lower().split("x"))
    except ValueError:
        sys.stderr.write("zuml-studio: error: " + _("--size {size!r} is not WxH").format(size=size) + "\n")
        return 2
    window.resize(width, height)
    window.device_panel          # built now, not by its timer in the middle of the settling below
    window.show()
    window.validate_now()
    if window.validator.last and window.validator.last.ok:
        window.sim_panel.simulate()
        window.sim_panel.wait(120_000)
        if window.sim_panel.result() is None:     # the picture would show an empty plot: say why
            sys.stderr.write("zuml-studio: " + window.sim_panel.message_text() + "\n")
    # A short run of the event loop, not just processEvents: Qt finishes the dock layout
    # (and hides a tab bar it no longer uses) only from the loop.
    loop = QEventLoop()
    QTimer.singleShot(SETTLE_MS, loop.quit)
    loop.exec()
    # Restoring a saved layout replaces the docks' tab bars and deletes the old ones later; outside
    # app.exec() this loop never gets to them, and they would be in the picture where they were.
    QCoreApplication.sendPostedEvents(None, QEvent.Type.DeferredDelete)
    if not window.grab().save(out):
        sys.stderr.write("zuml-studio: error: " + _("cannot write {path}").format(path=out) + "\n")
        return 2
    window.editor.document().setModified(False)
    window.close()
    return 0


if __name__ == "__main__":
    sys.exit(main())
