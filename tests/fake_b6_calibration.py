"""A stand-in for the iMAX B6's calibration requests (CAL_READ, CAL_OUTPUT; CAL_MEASURE's readings given
directly) for tests of the host's checks without the simulated board: a 3S pack at rest at 11.4 V."""
from zuml_studio.device.zuml.calibration import OFF, Block, Reading

NOMINAL = Block(((0, 29902), (0, 30826), (26, 1646), (233, 6042), (0, 19154), (0, 5022), (0, 4985), (0, 9761),
                 (0, 4899), (0, 5016), (0, 4993), (0, 4924), (0, 25395)))


def readings(vout=11400, vin=12000, cells=(3800, 3800, 3800)) -> list[Reading]:
    """CAL_MEASURE's readings (values in mV through the nominal calibration) of a pack at rest on the balance
    port (cells 1, 2 as taps to ground, 3..6 alone)."""
    taps = [0, cells[0] if cells else 0, sum(cells[:2]) if len(cells) > 1 else 0] + list(cells[2:]) + \
        [0] * (6 - max(len(cells), 2))
    values = [vout, 0, 0, 0, vin] + taps + [2500]
    return [Reading(adc16=round(zero + v * 65536 / full), value=v) for v, (zero, full) in zip(values, NOMINAL.pairs)]


class FakeB6:
    """Answers CAL_READ (uncalibrated: the nominal block) and CAL_OUTPUT, holding every current exactly as
    asked; what was asked is kept."""

    def __init__(self):
        self.asked: list[tuple[str, bytes]] = []
        self.mode = OFF
        self.ma = 0

    def request(self, name, payload=b"", response_len=64, extra_s=0.0):
        self.asked.append((name, payload))
        if name == "CAL_READ":
            return b"\x00" + NOMINAL.encode()
        if name == "CAL_OUTPUT":
            self.mode, self.ma = payload[0], int.from_bytes(payload[1:3], "little")
            return payload
        raise AssertionError(f"FakeB6 does not serve {name}")

    def settled(self, input_no: int) -> Reading:
        zero, full = NOMINAL.pairs[input_no]
        return Reading(adc16=round(zero + self.ma * 65536 / full), value=self.ma)


def patch_calibrator(monkeypatch) -> None:
    """Calibrator's timed reads answered at once: the pack's readings, the current FakeB6 holds."""
    from zuml_studio.device.zuml.calibration import Calibrator
    monkeypatch.setattr(Calibrator, "after_next_second", lambda self: readings())
    monkeypatch.setattr(Calibrator, "settled", lambda self, input_no: self.client.settled(input_no))
