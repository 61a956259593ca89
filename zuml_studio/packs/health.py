"""A pack's trend over its sessions and its health verdict with the reasons for it.

The limits are the hobby's rules of thumb the issue names: a pack is worn when it holds less than 80 %
of its rated capacity, when its resistance has grown to 1.5 times its first measured value, or when a
cell ends a charge more than 30 mV off the others (a drifting cell); and, where a live run read the
battery's passport, when it counts a critical error (docs/zuml-2.0.md §4: not fit for use)."""
from __future__ import annotations

from dataclasses import dataclass

from .register import Pack
from .sessions import Session
from ..i18n import _

CAPACITY_MIN_SHARE = 0.80
RESISTANCE_MAX_GROWTH = 1.5
CELL_DEVIATION_MAX_MV = 30.0
# A pack measured at more than this share of its rating is not judged by it: the rating or the log is
# wrong (a 224 % "good" pack is a typo or another pack's log).
CAPACITY_MAX_SHARE = 1.3


@dataclass(frozen=True)
class TrendPoint:
    recorded: str
    file: str
    capacity_pct: float | None        # of the rated capacity; from a discharge only (a charge may start part full)
    resistance_mohm_per_cell: float | None
    cell_deviation_mv: float | None

    def as_dict(self) -> dict:
        return {"recorded": self.recorded, "file": self.file, "capacity_pct": self.capacity_pct,
                "resistance_mohm_per_cell": self.resistance_mohm_per_cell,
                "cell_deviation_mv": self.cell_deviation_mv}


@dataclass(frozen=True)
class Health:
    verdict: str                      # "good", "poor" or "unknown" (no session measures anything checked)
    reasons: tuple[str, ...]

    def as_dict(self) -> dict:
        return {"verdict": self.verdict, "reasons": list(self.reasons)}


def trend(pack: Pack, sessions: list[Session]) -> list[TrendPoint]:
    """One point per session, oldest first; a session filed though it seems another pack's (``--force``)
    is left out."""
    out = []
    for s in sessions:
        if s.foreign_reason:
            continue
        f = s.figures
        pct = (round(f.capacity_mah / pack.capacity_mah * 100.0, 1)
               if f.capacity_mah is not None and f.capacity_from == "discharge" else None)
        out.append(TrendPoint(s.recorded, s.file, pct, f.resistance_mohm_per_cell, f.cell_deviation_mv))
    return out


def health(pack: Pack, sessions: list[Session]) -> Health:
    points = trend(pack, sessions)
    failed: list[str] = []
    passed: list[str] = []
    unsure: list[str] = []          # what keeps a verdict from being given
    capacity = [p for p in points if p.capacity_pct is not None]
    if capacity and capacity[-1].capacity_pct > CAPACITY_MAX_SHARE * 100.0:
        last = capacity[-1]
        unsure.append(_("the discharge on {date} took {mah:.0f} mAh ({pct:.0f} %) of a pack rated {rated:.0f} mAh: "
                        "check the pack's rating, or whether the log is this pack's").format(
                date=last.recorded[:10], mah=last.capacity_pct * pack.capacity_mah / 100.0, pct=last.capacity_pct,
                rated=pack.capacity_mah))
    elif capacity:
        last = capacity[-1]
        text = _("capacity {pct:.0f} %, {mah:.0f} of {rated:.0f} mAh rated, on {date}").format(
                pct=last.capacity_pct, mah=last.capacity_pct * pack.capacity_mah / 100.0, rated=pack.capacity_mah,
                date=last.recorded[:10])
        (failed if last.capacity_pct < CAPACITY_MIN_SHARE * 100.0 else passed).append(
                text + (_(", below {limit:.0f} %").format(limit=CAPACITY_MIN_SHARE * 100.0)
                        if last.capacity_pct < CAPACITY_MIN_SHARE * 100.0 else ""))
    resistance = [p for p in points if p.resistance_mohm_per_cell is not None]
    if len(resistance) >= 2 and resistance[0].resistance_mohm_per_cell > 0:
        first, last = resistance[0], resistance[-1]
        growth = last.resistance_mohm_per_cell / first.resistance_mohm_per_cell
        text = _("resistance {last:.0f} mΩ/cell on {date}, {growth:.2f}× its first value ({first:.0f} mΩ/cell on "
                 "{first_date})").format(last=last.resistance_mohm_per_cell, date=last.recorded[:10], growth=growth,
                                         first=first.resistance_mohm_per_cell, first_date=first.recorded[:10])
        (failed if growth >= RESISTANCE_MAX_GROWTH else passed).append(text)
    elif resistance:
        passed.append(_("resistance {r:.0f} mΩ/cell on {date} (one measurement: no growth to judge yet)").format(
                r=resistance[-1].resistance_mohm_per_cell, date=resistance[-1].recorded[:10]))
    deviation = [p for p in points if p.cell_deviation_mv is not None]
    if deviation:
        last = deviation[-1]
        text = _("cells {mv:.0f} mV apart at the end of the charge on {date}").format(
                mv=last.cell_deviation_mv, date=last.recorded[:10])
        if last.cell_deviation_mv > CELL_DEVIATION_MAX_MV:
            failed.append(text + _(", more than {limit:.0f} mV: a cell is drifting").format(
                    limit=CELL_DEVIATION_MAX_MV))
        else:
            passed.append(text)
    read = [s for s in sessions if s.passport_errors is not None or s.passport_critical is not None]
    if read:
        # docs/zuml-2.0.md §4: CRIT > 0 is a battery not fit for use (the charger refuses it); ERR > 0 a warning.
        last = read[-1]
        if last.passport_critical:
            failed.append(_("the passport counts {n} critical errors on {date}: not fit for use").format(
                    n=last.passport_critical, date=last.recorded[:10]))
        else:
            passed.append(_("the passport counts {n} errors, no critical one, on {date}").format(
                    n=last.passport_errors or 0, date=last.recorded[:10]))
    if failed:
        return Health("poor", tuple(failed + unsure))
    if unsure:
        return Health("unknown", tuple(unsure + passed))
    if passed:
        return Health("good", tuple(passed))
    if not sessions:
        return Health("unknown", (_("no session yet: import a log or attach a run"),))
    return Health("unknown", (_("no session measures the capacity (a discharge from full to the cut-off), the "
                                "resistance (a rest after a current) or the cells"),))
