"""zuml calibrate: an iMAX B6 running the ZUML firmware against the user's multimeter
(docs/firmware.md, *Calibration*): the voltages from the options or asked, the currents asked while
the charger holds them."""
from __future__ import annotations

import argparse

from ..i18n import _
from .common import CliError, out
from .device_commands import _connect, _device_errors, _with_port


def register(sub: argparse._SubParsersAction) -> None:
    p = _with_port(sub.add_parser("calibrate", help=_("calibrate an iMAX B6 running the ZUML firmware against "
                                                      "your multimeter")))
    p.add_argument("--pack-v", type=float, metavar="V", help=_("the pack's voltage at the output, as the meter "
                                                              "reads it (default: asked)"))
    p.add_argument("--supply-v", type=float, metavar="V", help=_("the supply's voltage (default: asked; 0: keep)"))
    p.add_argument("--cells-v", metavar="V,V,...", help=_("each cell's voltage at the balance port, cell 1 first "
                                                          "(default: asked; none: keep)"))
    p.set_defaults(run=cmd_calibrate)


def volts(text: str, what: str) -> float:
    try:
        value = float(text.replace(",", "."))
    except ValueError:
        raise CliError(_("{what}: {text!r} is not a number of volts").format(what=what, text=text)) from None
    if not 0 <= value <= 60:
        raise CliError(_("{what}: {value:g} V is outside 0..60 V").format(what=what, value=value))
    return value


def cells(text: str, what: str = "--cells-v") -> list[float] | None:
    """The cells in mV (None: keep)."""
    from ..device.zuml.calibration import CalibrationError, parse_cells
    try:
        return parse_cells(text)
    except CalibrationError as exc:
        raise CliError(f"{what}: {exc}") from None


def ask(prompt: str) -> str:
    try:
        return input(prompt).strip()
    except EOFError:
        raise CliError(_("no answer on the input: give the meter's readings")) from None


class PromptMeter:
    """The user's multimeter: the options' values, else asked on the terminal."""

    def __init__(self, args: argparse.Namespace):
        self.args = args

    def pack_mv(self) -> float:
        v = self.args.pack_v
        if v is None:
            v = volts(ask(_("Measure the pack at the charger's output: volts? ")), _("the pack"))
        return v * 1000

    def supply_mv(self) -> float | None:
        v = self.args.supply_v
        if v is None:
            v = volts(ask(_("Measure the supply at the charger's input: volts? ")) or "0", _("the supply"))
        return v * 1000 or None

    def cells_mv(self) -> list[float] | None:
        if self.args.cells_v is not None:
            return cells(self.args.cells_v)
        return cells(ask(_("Each cell at the balance port, cell 1 first (e.g. 3.91,3.92,3.90; empty: keep): ")),
                     _("the cells"))

    def current_ma(self, mode: int, asked_ma: int) -> float:
        from ..device.zuml.calibration import CHARGE
        what = _("charging") if mode == CHARGE else _("discharging")
        text = ask(_("The charger is {what} at about {ma} mA: what does the ammeter in series read (mA)? ").format(
            what=what, ma=asked_ma))
        try:
            value = float(text.replace(",", "."))
        except ValueError:
            raise CliError(_("{text!r} is not a number of mA").format(text=text)) from None
        if not 0 < value <= 5000:
            raise CliError(_("{value:g} mA is outside 0..5000 mA").format(value=value))
        return value


@_device_errors
def cmd_calibrate(args: argparse.Namespace) -> int:
    from ..device.zuml.calibration import INPUTS, CalibrationError, Calibrator
    if args.pack_v is not None:
        volts(str(args.pack_v), "--pack-v")
    if args.cells_v is not None:
        cells(args.cells_v)
    with _connect(args) as client:
        calibrator = Calibrator(client, out)
        try:
            block = calibrator.run(PromptMeter(args))
            readings = calibrator.measure()
        except CalibrationError as exc:
            raise CliError(str(exc), 1) from None
    out(_("Calibrated and stored. The charger now reads:"))
    for name, reading, (zero, full) in zip(INPUTS, readings, block.pairs):
        out(f"  {name:<12} {reading.value:>7}   zero {zero:>5}  full {full:>5}")
    return 0
