"""The fields that make a pack's cells unequal, as ``zuml simulate`` takes them (``sim.simulate.BatterySetup``):
a weak cell's percent and which cell it is, the spread of capacity, resistance and start charge, and the seed
of its draw. The simulator's form and the device panel's virtual battery both show these widgets."""
from __future__ import annotations

from PySide6.QtWidgets import QLineEdit, QSpinBox

from ...i18n import _
from ...sim.simulate import SPREAD_MAX_PCT, parse_spread
from .number_boxes import spin_box

DEFAULT_SEED = 1


class CellFields:
    """The four widgets (their sizes are the form's) and what they say, checked."""

    def __init__(self):
        self.weak_pct: QSpinBox = spin_box(0, 90, 0, " %", _(
            "one cell holds this many percent less capacity than the others (off: none); the balancer and the "
            "per-cell curves show what happens to it"))
        self.weak_pct.setSpecialValueText(_("off"))
        self.weak_cell: QSpinBox = spin_box(0, 255, 0, "", _("which cell is the weak one, counted from the pack's "
                                                            "negative end (last: the top cell)"))
        self.weak_cell.setSpecialValueText(_("last"))
        self.weak_cell.setPrefix("#")
        self.spread = QLineEdit()
        self.spread.setPlaceholderText(_("off"))
        self.spread.setToolTip(_("cells drawn unequal: capacity, resistance and start charge each within ± "
                                 "CAP,R,SOC percent of the pack's (e.g. 3,10,2; each 0..{top:g}); empty: equal "
                                 "cells").format(top=max(SPREAD_MAX_PCT)))
        self.seed: QSpinBox = spin_box(1, 99999, DEFAULT_SEED, "", _("the draw of the spread: another number, "
                                                                    "other cells; the same, the same cells"))
        self.spread.textChanged.connect(self._spread_changed)
        self._spread_changed()

    def _spread_changed(self) -> None:
        self.seed.setEnabled(bool(self.spread.text().strip()))

    def weak_cell_number(self) -> int | None:
        """The weak cell, 1-based; None: the last."""
        return self.weak_cell.value() or None

    def cell_spread(self) -> tuple[float, float, float] | None:
        """The spread typed (None: empty); ValueError says in words what is typed wrong."""
        text = self.spread.text().strip()
        if not text:
            return None
        try:
            return parse_spread(text)
        except ValueError:
            raise ValueError(_("cell spread '{text}': write CAP,R,SOC, three percentages from 0 to {top:g}, "
                               "e.g. 3,10,2 (empty: equal cells)").format(text=text, top=max(SPREAD_MAX_PCT))) from None

    def summary(self) -> str:
        """The cells in a few words for a button's face: "equal", "−15 %" (the top cell), "−15 % #2",
        "±3,10,2 (seed 1)"."""
        parts = []
        if self.weak_pct.value():
            which = f" #{self.weak_cell.value()}" if self.weak_cell.value() else ""
            parts.append(f"−{self.weak_pct.value()} %{which}")
        if self.spread.text().strip():
            parts.append(_("±{spread} (seed {seed})").format(spread=self.spread.text().strip(),
                                                               seed=self.seed.value()))
        return ", ".join(parts) or _("equal")
