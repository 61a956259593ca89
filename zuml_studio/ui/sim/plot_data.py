"""A finished (or cancelled) simulation made ready to draw, off the GUI thread: the sample
log's columns as float64 arrays and their min/max envelopes at every zoom level, so that the
GUI thread draws any view of a run, a day of ticks or more, from about two points per pixel
without scanning the samples (``ChargePlot``). No Qt here."""
from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from ..device.envelope import Envelope

CLOCK = "time_s"
CURVES = {"voltage": "voltage_v", "current": "current_a", "temp": "temp_c", "heatsink": "heatsink_c"}


@dataclass(frozen=True)
class PlotData:
    result: object                      # the SimResult
    data: dict[str, np.ndarray]         # the log's columns (sim.samples.COLUMNS)
    envelope: Envelope                  # over CURVES' columns, clock CLOCK

    def __len__(self) -> int:
        return len(self.data[CLOCK])


def prepare_plot(result) -> PlotData:
    """Costs about as much as a tenth of the simulation: run it where the simulation ran."""
    data = result.log.arrays()
    envelope = Envelope(tuple(CURVES.values()), clock=CLOCK)
    envelope.update(len(data[CLOCK]), data)
    return PlotData(result, data, envelope)
