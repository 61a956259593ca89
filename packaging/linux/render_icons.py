"""Render the icon files from the one master SVG (resources/icon.svg) with Qt's SVG renderer:
packaging/linux/icons/{48,128,256}.png, packaging/windows/zuml-studio.ico, packaging/macos/zuml-studio.icns.
Run after editing the SVG:  .venv/bin/python packaging/linux/render_icons.py"""
from __future__ import annotations

import os
import sys
from pathlib import Path

os.environ.setdefault("QT_QPA_PLATFORM", "offscreen")

from PySide6.QtCore import Qt
from PySide6.QtGui import QGuiApplication, QImage, QPainter
from PySide6.QtSvg import QSvgRenderer

ROOT = Path(__file__).resolve().parents[2]
MASTER = ROOT / "resources" / "icon.svg"
PNG_SIZES = (48, 128, 256)
TARGETS = [(ROOT / "packaging" / "linux" / "icons" / f"{size}.png", size) for size in PNG_SIZES] + [
    (ROOT / "packaging" / "windows" / "zuml-studio.ico", 256),
    (ROOT / "packaging" / "macos" / "zuml-studio.icns", 512),
]


def render(renderer: QSvgRenderer, size: int) -> QImage:
    image = QImage(size, size, QImage.Format.Format_ARGB32_Premultiplied)
    image.fill(Qt.GlobalColor.transparent)
    painter = QPainter(image)
    painter.setRenderHint(QPainter.RenderHint.Antialiasing)
    renderer.render(painter)
    painter.end()
    return image


def main() -> int:
    _app = QGuiApplication.instance() or QGuiApplication(sys.argv[:1])
    renderer = QSvgRenderer(str(MASTER))
    if not renderer.isValid():
        print(f"{MASTER}: not a valid SVG", file=sys.stderr)
        return 1
    for path, size in TARGETS:
        path.parent.mkdir(parents=True, exist_ok=True)
        if not render(renderer, size).save(str(path)):
            print(f"{path}: Qt cannot write it", file=sys.stderr)
            return 1
        print(path.relative_to(ROOT))
    return 0


if __name__ == "__main__":
    sys.exit(main())
