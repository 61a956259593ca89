"""The window fits the screen: made for it on first start, a saved geometry kept only if it fits."""
from PySide6.QtCore import QRect

from zuml_studio.ui.base.window_geometry import first_geometry, fits


def test_first_geometry_fits_small_and_scaled_screens():
    for available in (QRect(0, 0, 1366, 728), QRect(0, 0, 1280, 690), QRect(0, 27, 1920, 1053)):
        rect = first_geometry(available)
        assert available.contains(rect), available
        assert rect.width() <= 1500 and rect.height() <= 950
    assert first_geometry(QRect(0, 0, 2560, 1400)).size().toTuple() == (1500, 950)


def test_fits():
    screen = QRect(0, 0, 1366, 728)
    assert fits(QRect(0, 0, 1366, 728), screen)
    assert not fits(QRect(0, 0, 1500, 950), screen)
    assert not fits(QRect(2000, 0, 800, 600), screen)


def test_a_saved_geometry_that_no_longer_fits_is_not_restored(make_window, tmp_path):
    config = tmp_path / "geometry-config"
    w = make_window(None, config)
    available = w.screen().availableGeometry()
    saved = (available.width() + 600, available.height() + 400)       # saved on a bigger screen
    w.resize(*saved)
    assert w.close()
    fresh = type(w)(config)          # as constructed, before the fixture resizes it
    # Never the saved size; at most the first-start size (or the window's minimum, where the
    # offscreen screen is smaller than that: the minimum depends on fonts and lazily built docks).
    most = first_geometry(available).size().expandedTo(fresh.minimumSizeHint())
    assert fresh.width() < saved[0] and fresh.height() < saved[1]
    assert fresh.width() <= most.width() and fresh.height() <= most.height()
    fresh.ask_unsaved = lambda: "discard"
    fresh.close()
    fresh.device_panel.shutdown()


def test_a_saved_frame_is_read_as_it_was_saved(make_window):
    from zuml_studio.ui.base.window_geometry import saved_frame
    w = make_window()
    w.setGeometry(10, 20, 700, 500)
    frame = saved_frame(bytes(w.saveGeometry()))
    assert frame == w.frameGeometry()
    assert saved_frame(b"garbage") is None and saved_frame(b"\0" * 30) is None
