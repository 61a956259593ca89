"""The pack's own battery model: the chemistry's model fitted (``sim.fit``) to the pack's latest charge
and saved as a named battery, which the simulator then offers like any other ("simulate this macro on
pack 'Turnigy 4S #2'")."""
from __future__ import annotations

import re

from ..logs import LogFormatError, read_log_file
from .text import path_of
from ..sim.batteries import battery_names, save_battery
from ..sim.curve import CurveError, charge_from_log
from ..sim.fit import FitResult, fit
from ..sim.fit_predict import predict_own
from .db import Logbook
from .register import Pack, PackError
from .sessions import pack_sessions
from ..i18n import _


def model_name(pack: Pack) -> str:
    """The named battery of a pack (a battery name takes letters, digits, spaces and . , + ( ) -)."""
    return ("pack " + re.sub(r"[^\w .,+()-]", "", pack.name).strip())[:80]


def has_model(pack: Pack) -> bool:
    return model_name(pack) in battery_names()


def fit_quality(result: FitResult) -> dict:
    """What a pack's fitted model is to be read with: ``{"quality": {quantity: {"rmse", "unit", "window_s"}},
    "own_program": {...} | None}``, the RMSE per quantity over its window (``FitResult.figures["quality"]``) and
    what the model predicts on its own log's program against the log (``sim.fit_predict.predict_own``: its
    ``trusted`` is False where the charge is more than 15 % off). Runs a simulation: off the GUI thread."""
    return {"quality": result.figures["quality"], "own_program": predict_own(result)}


def fit_pack_model(book: Logbook, pack: Pack) -> tuple[str, FitResult]:
    """Fit the model to the newest session whose file is still there and holds a charge; save it under
    ``model_name(pack)``. Takes seconds to minutes (call it off the GUI thread)."""
    failed = ""
    for session in reversed(pack_sessions(book, pack)):
        if session.figures.charge_in_mah is None or not path_of(session.file).is_file():
            continue
        try:
            curve = charge_from_log(read_log_file(path_of(session.file)), session.file)
            result = fit(curve, pack.chemistry, pack.cells)
        except (LogFormatError, CurveError) as exc:
            failed = str(exc)
            continue
        except (ValueError, ArithmeticError) as exc:      # a charge the model cannot follow: try an older one
            failed = _("{file}: the fit failed: {error}").format(file=session.file, error=exc)
            continue
        name = model_name(pack)
        save_battery(name, result.battery, source=session.file)
        return name, result
    raise PackError(_("pack {name!r}: no session with a charge whose file is still there to fit a model "
                      "to").format(name=pack.name) + (f" ({failed})" if failed else ""))
