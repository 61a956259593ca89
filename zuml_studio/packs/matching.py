"""Whether a log can be a session of a pack: a log whose chemistry or cell count contradicts the pack's is
another pack's (a folder of mixed logs imported into a NiMH 4S pack held LiPo 5S and LiFe 2S ones), and
is not filed unless the user says so (``--force``), marked then.

The chemistry is what the log says (a DUO/X log's battery type, an .osd's record-set names, a file name's
words); the cell count its balance taps, else its voltage: a charge's median voltage per cell within
``sim.fit.SERIES_TOLERANCE`` of the chemistry's ``charging_v``, a discharge's within
``DISCHARGE_SERIES_TOLERANCE`` of its ``nominal_v`` (the fit's rule for a log's cell count)."""
from __future__ import annotations

import re

import numpy as np

from ..logs.model import STATES, Log
from ..domain.chemistry import load_chemistry
from ..sim.fit import DISCHARGE_SERIES_TOLERANCE, SERIES_TOLERANCE
from .register import Pack
from ..i18n import _

# Words that name a chemistry (lower case, whole words) -> the chemistry's name in domain.chemistry.
_WORDS = {"lipo": "LiPo", "lipoly": "LiPo", "lihv": "LiPo", "liion": "LiIon", "li-ion": "LiIon", "liio": "LiIon",
          "life": "LiFe", "lifepo4": "LiFe", "lfp": "LiFe", "nimh": "NiMh", "nicd": "NiCd", "pb": "Pb",
          "lead": "Pb", "agm": "Pb"}
_WORD = re.compile(r"[a-z0-9-]+")
# Fewer samples in a direction than this do not say the pack's voltage.
MIN_SAMPLES = 20


def stated_chemistry(log: Log, file_name: str = "") -> str | None:
    """The chemistry the log names (its battery type, record sets, comment, or the file's name)."""
    texts = [str(log.meta.get("battery", ""))] + [str(n) for n in log.meta.get("record_sets", ())] + \
        [str(log.meta.get("comment", "")), file_name]
    for text in texts:
        for word in _WORD.findall(text.lower().replace("_", " ")):
            if word in _WORDS:
                return load_chemistry(_WORDS[word]).name
    return None


def mismatch(log: Log, pack: Pack, file_name: str = "") -> str | None:
    """Why the log is not this pack's, or None when nothing in it contradicts the pack."""
    chemistry = stated_chemistry(log, file_name)
    own = load_chemistry(pack.chemistry)
    if chemistry is not None and chemistry != own.name:
        return _("the log is of a {log} pack, this one is {pack}").format(log=chemistry, pack=own.name)
    if log.cells > 1 and log.cells != pack.cells:
        return _("the log's balance taps show {log} cells, the pack has {pack}").format(log=log.cells,
                                                                                     pack=pack.cells)
    for state, typical, tolerance in (("charge", own.charging_v, SERIES_TOLERANCE),
                                      ("discharge", own.nominal_v, DISCHARGE_SERIES_TOLERANCE)):
        c = log.columns
        volts = c.voltage[(c.state == STATES.index(state)) & (np.abs(c.current) > 0.05)]
        if len(volts) < MIN_SAMPLES:
            continue
        per_cell = float(np.median(volts)) / pack.cells
        if abs(per_cell / typical - 1.0) > tolerance:
            return _("its {state}'s median voltage, {v:.2f} V, is {cell:.2f} V per cell for {cells} cells; a "
                     "{chemistry} cell reads about {typical:.2f} V").format(
                    state=_(state), v=per_cell * pack.cells, cell=per_cell, cells=pack.cells,
                    chemistry=own.name, typical=typical)
    return None
