"""A pack's one-page report: its register entry, health verdict with reasons, trend plot and sessions
table, drawn once by ``paint_report`` on a page of ``PAGE`` units and written as PDF (Qt's PDF writer,
A4, vector) or PNG (the same drawing rasterised)."""
from __future__ import annotations

from pathlib import Path

from PySide6.QtCore import QMarginsF, QRect, QRectF, Qt
import numpy as np
from PySide6.QtGui import QColor, QFont, QImage, QPageLayout, QPageSize, QPainter, QPainterPath, QPdfWriter, QPen

from ...packs.health import TrendPoint
from ...packs.report_data import SessionCurve
from ...packs.summary import DATED_MARK, capacity_note, capacity_text, dates_note
from .trend_plot import PackTrendPlot
from ...errors import ZumlError
from ...i18n import _

PAGE = (800, 1131)                 # A4's proportions, in drawing units
PNG_SCALE = 1.5                    # 1200 × 1697 pixels
_MARGIN = 40


class ReportError(ZumlError):
    """The report could not be written; the message names the file."""


def _fmt(value, spec: str) -> str:
    return "–" if value is None else format(value, spec)


def paint_report(painter: QPainter, info: dict, points: list[TrendPoint], curves: list[SessionCurve] = (),
                 model: list[str] = ()) -> None:
    """``info``: ``packs.summary.pack_summary``; ``curves`` and ``model``: ``packs.report_data``'s; draws on
    a PAGE-sized window."""
    w, h = PAGE
    painter.fillRect(QRect(0, 0, w, h), QColor("white"))
    painter.setPen(QColor("black"))
    y = _MARGIN
    title = QFont(painter.font())
    title.setPixelSize(26)
    title.setBold(True)
    painter.setFont(title)
    painter.drawText(QRectF(_MARGIN, y, w - 2 * _MARGIN, 36), Qt.AlignmentFlag.AlignLeft, info["name"])
    y += 40
    body = QFont(painter.font())
    body.setPixelSize(13)
    body.setBold(False)
    painter.setFont(body)
    line = 19
    details = _("{chemistry}, {cells} cells in series, {capacity:g} mAh rated").format(
            chemistry=info["chemistry"], cells=info["cells"], capacity=info["capacity_mah"])
    extras = [f"{label}: {info[key]}" for key, label in (("bought", _("bought")), ("serial", _("serial")))
              if info[key]]
    for text in [details + ("; " + "; ".join(extras) if extras else ""), info["notes"]]:
        if text:
            painter.drawText(QRectF(_MARGIN, y, w - 2 * _MARGIN, line), Qt.AlignmentFlag.AlignLeft, text)
            y += line
    y += 8
    verdict = {"good": _("good"), "poor": _("poor"), "unknown": _("unknown")}[info["health"]["verdict"]]
    bold = QFont(body)
    bold.setBold(True)
    painter.setFont(bold)
    painter.drawText(QRectF(_MARGIN, y, w - 2 * _MARGIN, line), Qt.AlignmentFlag.AlignLeft,
                     _("Health: {verdict}").format(verdict=verdict))
    y += line
    painter.setFont(body)
    for reason in info["health"]["reasons"]:
        rect = QRectF(_MARGIN + 14, y, w - 2 * _MARGIN - 14, 2 * line)
        used = painter.boundingRect(rect, Qt.TextFlag.TextWordWrap, "• " + reason)
        painter.drawText(rect, Qt.TextFlag.TextWordWrap, "• " + reason)
        y += used.height() + 2
    y += 10
    plot = PackTrendPlot()
    plot.setBackground("white")
    size = QRectF(0, 0, w - 2 * _MARGIN, 300)
    plot.ci.setGeometry(size)          # laid out without being shown: the report is drawn off screen
    plot.show_trend(points)
    plot.scene().render(painter, QRectF(_MARGIN, y, size.width(), size.height()), size)
    y += 308
    half = (w - 2 * _MARGIN - 20) / 2
    small = QFont(body)
    small.setPixelSize(11)
    painter.setFont(small)
    _paint_curves(painter, QRectF(_MARGIN, y, half, 170), _("Voltage per cell, each session (V over hours)"),
                  [(c.label, c.t_h, c.v_cell) for c in curves])
    _paint_curves(painter, QRectF(_MARGIN + half + 20, y, half, 170),
                  _("Cell drift: highest − lowest cell, each session (mV over hours)"),
                  [(c.label, c.t_h, c.spread_mv) for c in curves])
    y += 178
    painter.setPen(QColor("black"))
    painter.setFont(bold)
    painter.drawText(QRectF(_MARGIN, y, w - 2 * _MARGIN, line), Qt.AlignmentFlag.AlignLeft,
                     _("The model fitted to this pack"))
    y += line
    painter.setFont(body)
    for text in model:
        rect = QRectF(_MARGIN + 14, y, w - 2 * _MARGIN - 14, 2 * line)
        used = painter.boundingRect(rect, Qt.TextFlag.TextWordWrap, text)
        painter.drawText(rect, Qt.TextFlag.TextWordWrap, text)
        y += used.height() + 1
    y += 8
    _paint_sessions(painter, info["sessions"], y, line, bold, body)


_COLOURS = ("#1f77b4", "#d62728", "#2ca02c", "#9467bd", "#ff7f0e", "#8c564b", "#e377c2", "#17becf")


def _paint_curves(painter: QPainter, rect: QRectF, title: str, series: list[tuple[str, np.ndarray, np.ndarray]]) -> None:
    """A small plot of one line per session (its date in the legend), on axes fitted to them; says so
    when there is nothing to draw (unknown is not a flat line)."""
    painter.setPen(QColor("black"))
    painter.drawText(QRectF(rect.left(), rect.top(), rect.width(), 16), Qt.AlignmentFlag.AlignLeft, title)
    area = QRectF(rect.left() + 40, rect.top() + 20, rect.width() - 48, rect.height() - 38)
    painter.setPen(QPen(QColor("#888888"), 0.8))
    painter.drawRect(area)
    drawn = [(label, x, y) for label, x, y in series if np.isfinite(y).any() and len(x) > 1]
    if not drawn:
        painter.drawText(area, Qt.AlignmentFlag.AlignCenter, _("– (no session's log has it)"))
        return
    x_top = max(float(np.nanmax(x)) for _l, x, _y in drawn) or 1.0
    lo = min(float(np.nanmin(y)) for _l, _x, y in drawn)
    hi = max(float(np.nanmax(y)) for _l, _x, y in drawn)
    if hi - lo < 1e-9:
        lo, hi = lo - 0.5, hi + 0.5
    pad = (hi - lo) * 0.05
    lo, hi = lo - pad, hi + pad
    painter.setPen(QColor("black"))
    for value, align in ((hi, Qt.AlignmentFlag.AlignTop), (lo, Qt.AlignmentFlag.AlignBottom)):
        painter.drawText(QRectF(rect.left(), area.top() if align == Qt.AlignmentFlag.AlignTop else area.bottom() - 14,
                                38, 14), align | Qt.AlignmentFlag.AlignRight, f"{value:.3g}")
    painter.drawText(QRectF(area.left(), area.bottom() + 1, 40, 14), Qt.AlignmentFlag.AlignLeft, "0")
    painter.drawText(QRectF(area.right() - 60, area.bottom() + 1, 60, 14), Qt.AlignmentFlag.AlignRight,
                     _("{hours:.3g} h").format(hours=x_top))
    for n, (_label, x, y) in enumerate(drawn):
        colour = QColor(_COLOURS[n % len(_COLOURS)])
        painter.setPen(QPen(colour, 1.2))
        px = area.left() + x / x_top * area.width()
        py = area.bottom() - (y - lo) / (hi - lo) * area.height()
        path = QPainterPath()
        pen_down = False
        for a, b in zip(px.tolist(), py.tolist()):
            if b != b:                              # NaN: not read here, the line breaks
                pen_down = False
                continue
            if pen_down:
                path.lineTo(a, b)
            else:
                path.moveTo(a, b)
                pen_down = True
        painter.drawPath(path)
    _legend(painter, area, [label for label, _x, _y in drawn])


def _legend(painter: QPainter, area: QRectF, labels: list[str]) -> None:
    """The sessions' dates in their colours, in the plot's top left corner, on the paper's white."""
    y = area.top() + 2
    painter.fillRect(QRectF(area.left() + 2, y, 72, 11 * len(labels) + 2), QColor(255, 255, 255, 220))
    for n, label in enumerate(labels):
        painter.setPen(QColor(_COLOURS[n % len(_COLOURS)]))
        painter.drawText(QRectF(area.left() + 4, y, 90, 12), Qt.AlignmentFlag.AlignLeft, label)
        y += 11


def _paint_sessions(painter: QPainter, sessions: list[dict], y: float, line: int, bold: QFont, body: QFont) -> None:
    w, h = PAGE
    columns = ((_("date"), 80), (_("in mAh"), 62), (_("out mAh"), 70), (_("capacity"), 70), (_("mΩ/cell"), 66),
               (_("ΔV mV"), 56), (_("T max °C"), 74), (_("file"), w - 2 * _MARGIN - 478))
    small = QFont(body)
    small.setPixelSize(11)
    painter.setFont(bold)
    x = _MARGIN
    for name, width in columns:
        name = painter.fontMetrics().elidedText(name, Qt.TextElideMode.ElideRight, width - 4)
        painter.drawText(QRectF(x, y, width - 4, line), Qt.AlignmentFlag.AlignLeft, name)
        x += width
    y += line
    painter.drawLine(_MARGIN, int(y), w - _MARGIN, int(y))
    y += 3
    painter.setFont(small)
    room = int((h - _MARGIN - y) // 16) - 2        # the notes under the table
    shown = sessions if len(sessions) <= room else sessions[-(room - 1):]
    for s in shown:
        cells = (s["recorded"][:10] + DATED_MARK.get(s["recorded_from"], "?"), _fmt(s["charge_in_mah"], ".0f"), _fmt(s["charge_out_mah"], ".0f"),
                 capacity_text(s), _fmt(s["resistance_mohm_per_cell"], ".1f"),
                 _fmt(s["cell_deviation_mv"], ".0f"), _fmt(s["t_max_c"], ".1f"), Path(s["file"]).name)
        x = _MARGIN
        for (_name, width), text in zip(columns, cells):
            text = painter.fontMetrics().elidedText(text, Qt.TextElideMode.ElideMiddle, width - 4)
            painter.drawText(QRectF(x, y, width - 4, 16), Qt.AlignmentFlag.AlignLeft, text)
            x += width
        y += 16
    notes = [_("(the {n} earliest sessions are in the CSV export)").format(n=len(sessions) - len(shown))] \
        if len(shown) < len(sessions) else []
    notes += [n for n in (capacity_note(sessions), dates_note(sessions)) if n]
    for note in notes:
        painter.drawText(QRectF(_MARGIN, y, w - 2 * _MARGIN, 16), Qt.AlignmentFlag.AlignLeft, note)
        y += 16


def report_image(info: dict, points: list[TrendPoint], curves: list[SessionCurve] = (), model: list[str] = (),
                 scale: float = PNG_SCALE) -> QImage:
    image = QImage(int(PAGE[0] * scale), int(PAGE[1] * scale), QImage.Format.Format_RGB32)
    image.fill(QColor("white"))
    painter = QPainter(image)
    painter.setRenderHint(QPainter.RenderHint.Antialiasing)
    painter.scale(scale, scale)
    paint_report(painter, info, points, curves, model)
    painter.end()
    return image


def write_report(path: str | Path, info: dict, points: list[TrendPoint], curves: list[SessionCurve] = (),
                 model: list[str] = ()) -> None:
    """A PDF when the name ends in .pdf, else a PNG."""
    path = str(path)
    if path.lower().endswith(".pdf"):
        writer = QPdfWriter(path)
        writer.setPageLayout(QPageLayout(QPageSize(QPageSize.PageSizeId.A4), QPageLayout.Orientation.Portrait,
                                         QMarginsF(0, 0, 0, 0)))
        writer.setResolution(96)
        writer.setTitle(info["name"])
        painter = QPainter()
        if not painter.begin(writer):
            raise ReportError(_("{path}: cannot write the PDF").format(path=path))
        page = writer.pageLayout().paintRectPixels(writer.resolution())
        painter.scale(page.width() / PAGE[0], page.height() / PAGE[1])
        paint_report(painter, info, points, curves, model)
        painter.end()
        if not Path(path).is_file() or Path(path).stat().st_size == 0:
            raise ReportError(_("{path}: cannot write the PDF").format(path=path))
        return
    if not report_image(info, points, curves, model).save(path, "PNG"):
        raise ReportError(_("{path}: cannot write the PNG").format(path=path))
