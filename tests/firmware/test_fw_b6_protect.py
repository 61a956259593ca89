"""The iMAX B6 board's calibration and protections (firmware/boards/imaxb6/calib.c, protect.c) built for the
PC and driven through ctypes: the decisions the ADC interrupt takes, reading by reading."""
import ctypes
import subprocess
import tomllib

import pytest

from host_core import FIRMWARE, ROOT
from tools import HOST, needs

pytestmark = needs(HOST)

(VOUT, VOUT_MINUS, IDIS, ISMPS, VIN, VB0, VB1, VB2, VB3, VB4, VB5, VB6, TEXTERN) = range(13)
BLOCK = 54
AKK = {"Undef": 0, "Pb": 1, "NiCd": 2, "NiMh": 3, "LiPo": 4, "LiIon": 5, "LiS": 6, "LiFe": 7, "New": 8}


@pytest.fixture(scope="module")
def lib():
    done = subprocess.run(["make", "-s", "-C", str(FIRMWARE), "build/host/libzuml_b6_logic.so"],
                          capture_output=True, text=True)
    assert done.returncode == 0, done.stdout + done.stderr
    so = ctypes.CDLL(str(FIRMWARE / "build" / "host" / "libzuml_b6_logic.so"))
    so.cal_value.restype = ctypes.c_int32
    so.cal_value.argtypes = [ctypes.c_uint8, ctypes.c_uint16]
    so.cal_adc16.restype = ctypes.c_uint16
    so.cal_adc16.argtypes = [ctypes.c_uint8, ctypes.c_int32]
    so.protect_arm.restype = ctypes.c_char_p
    so.protect_arm.argtypes = [ctypes.c_uint8, ctypes.c_int16, ctypes.POINTER(ctypes.c_uint8), ctypes.c_char_p]
    so.protect_reading.argtypes = [ctypes.c_uint8, ctypes.c_int16]
    so.protect_text.restype = ctypes.c_char_p
    so.protect_cell_max_mv.restype = ctypes.c_uint16
    return so


def sealed(pairs, version=1):
    block = bytearray([version])
    for zero, full in pairs:
        block += zero.to_bytes(2, "little") + full.to_bytes(2, "little")
    check = 0
    for b in block:
        check ^= b
    return bytes(block + bytes([check]))


def nominal(lib):
    lib.cal_use(bytes(BLOCK))                       # not a calibration: the nominal one is used
    block = ctypes.create_string_buffer(BLOCK)
    lib.cal_block(block)
    return block.raw


def test_the_nominal_calibration_is_cheali_s_default_points(lib):
    block = nominal(lib)
    assert lib.cal_block_valid(block) == 1 and block[0] == 1
    # targets/imaxB6-original/defaultCalibration.cpp: Vout {55102, 25141 mV}, Ismps {775, 50} {11080, 1000 mA},
    # Idischarge {2017, 50} {11971, 300 mA}, Vb1 {55048, 4187 mV}, Textern {5884, 22.80 C}
    assert abs(lib.cal_value(VOUT, 55102) - 25141) <= 1
    assert abs(lib.cal_value(ISMPS, 775) - 50) <= 1 and abs(lib.cal_value(ISMPS, 11080) - 1000) <= 1
    assert abs(lib.cal_value(IDIS, 2017) - 50) <= 1 and abs(lib.cal_value(IDIS, 11971) - 300) <= 1
    assert abs(lib.cal_value(VB1, 55048) - 4187) <= 1 and abs(lib.cal_value(TEXTERN, 5884) - 2280) <= 1
    for k, value in ((VOUT, 12600), (ISMPS, 2000), (VB3, 4200), (VIN, 11000)):
        assert abs(lib.cal_value(k, lib.cal_adc16(k, value)) - value) <= 1


def test_a_calibration_block_is_used_only_whole(lib):
    pairs = [(0, 30000), (0, 30826), (26, 1646), (233, 6042), (0, 19154), (0, 5022), (0, 4985), (0, 9761),
             (0, 4899), (0, 5016), (0, 4993), (0, 4924), (0, 25395)]      # nominal, Vout+ 0.3 % off
    good = sealed(pairs)
    assert lib.cal_use(good) == 1 and lib.cal_value(VOUT, 32768) == 15000
    torn = bytearray(good)
    torn[5] ^= 0x40                                 # a byte a power cut left half written
    for bad in (bytes(torn), sealed(pairs, version=2), sealed(pairs[:12] + [(0, 0)]),
                b"\xff" * BLOCK):
        assert lib.cal_block_valid(bad) == 0
        assert lib.cal_use(bad) == 0                # falls back to the nominal calibration
        assert abs(lib.cal_value(VOUT, 55102) - 25141) <= 1


def test_the_ceiling_per_cell_is_the_spec_s_absolute_maximum_for_every_chemistry(lib):
    for name, code in AKK.items():
        path = ROOT / "resources" / "chemistries" / f"{name}.toml"
        if path.exists():
            max_v = tomllib.loads(path.read_text())["limits"]["max_v"]
            assert lib.protect_cell_max_mv(code) == round(max_v * 1000), name
    # the firmware's decisions where the spec gives none (docs/firmware.md)
    assert [lib.protect_cell_max_mv(AKK[n]) for n in ("LiS", "Undef", "New")] == [2800, 4350, 4350]


def feed(lib, readings, times=1):
    trip = 0
    for _ in range(times):
        for k, value in readings.items():
            trip = lib.protect_reading(k, value) or trip
    return trip


def pack(lib, cells_mv, vout=None, vin=12000, vminus=0, probe=2500):
    """A pack on the output and its balance lead: taps 1, 2 to ground, cells 3..6 alone."""
    taps = {VB0: 0, VB1: 0, VB2: 0, VB3: 0, VB4: 0, VB5: 0, VB6: 0}
    if cells_mv:
        taps[VB1] = cells_mv[0]
    if len(cells_mv) > 1:
        taps[VB2] = cells_mv[0] + cells_mv[1]
    for k, mv in enumerate(cells_mv[2:]):
        taps[VB3 + k] = mv
    return {VOUT: sum(cells_mv) if vout is None else vout, VOUT_MINUS: vminus, VIN: vin, TEXTERN: probe,
            ISMPS: 0, IDIS: 0, **taps}


def arm(lib, akk, cells, sentence=None):
    """protect_arm's answer (its text, its trip); the sentence the PC would get into `sentence` when given."""
    trip = ctypes.c_uint8()
    why = lib.protect_arm(AKK[akk], cells, ctypes.byref(trip), sentence)
    return (why.decode() if why else None), trip.value


def text(lib, trip):
    return lib.protect_text(trip).decode()


@pytest.mark.parametrize("readings, cells, why", [
    (dict(cells_mv=[3800] * 3, vout=0, vminus=3000), 3, "battery reversed"),
    (dict(cells_mv=[], vout=100), 3, "no battery"),
    (dict(cells_mv=[3800] * 3, vin=10500), 3, "input below 11V"),
    (dict(cells_mv=[3800] * 3), 4, "balance lead 3 cells"),
    (dict(cells_mv=[3800, 3800, 4320]), 3, "cell 3 over max"),
    (dict(cells_mv=[], vout=13500), 3, "pack over max"),
])
def test_a_start_the_inputs_forbid_is_refused_with_its_reason(lib, readings, cells, why):
    lib.protect_disarm()
    feed(lib, pack(lib, **readings))
    assert arm(lib, "LiPo", cells)[0] == why


def test_a_limit_trips_after_four_readings_in_a_row_not_on_one(lib):
    lib.protect_disarm()
    ok = pack(lib, [3900] * 3)
    feed(lib, ok)
    assert arm(lib, "LiPo", 3) == (None, 0)
    assert feed(lib, {ISMPS: 5300}) == 0 and feed(lib, {ISMPS: 2000}) == 0     # one noisy reading
    for n in range(3):
        assert feed(lib, {ISMPS: 5300}) == 0
    assert text(lib, feed(lib, {ISMPS: 5300})) == "over current"
    assert text(lib, feed(lib, ok)) == "over current"                          # the first trip stays


@pytest.mark.parametrize("akk, cells, reading, times, why", [
    ("LiPo", 3, dict(cells_mv=[4000, 4000, 4350]), 4, "cell 3 over max"),       # the fault's 4.35 V tap
    ("LiFe", 3, dict(cells_mv=[3400, 3660, 3400]), 4, "cell 2 over max"),
    ("NiMh", 8, dict(cells_mv=[], vout=8 * 1810), 4, "pack over max"),
    ("Pb", 6, dict(cells_mv=[], vout=6 * 2510), 4, "pack over max"),
    ("LiPo", 3, dict(cells_mv=[3900] * 3, vout=0), 16, "battery disconnected"),
    ("LiPo", 3, dict(cells_mv=[3900] * 3, vout=13000), 16, "battery disconnected"),  # main lead off: V rises
    ("LiPo", 3, dict(cells_mv=[3900, 3900, 0]), 4, "balance lead 2 cells"),
    ("LiPo", 3, dict(cells_mv=[3900] * 3, vout=0, vminus=11000), 4, "battery reversed"),
    ("LiPo", 3, dict(cells_mv=[3900] * 3, vin=10000), 4, "input below 11V"),
    ("LiPo", 3, dict(cells_mv=[3900] * 3, probe=6100), 4, "probe over 60C"),
    ("LiPo", 3, dict(cells_mv=[3900] * 3, probe=0), 4, "probe open"),
])
def test_each_limit_ends_the_run_with_its_reason(lib, akk, cells, reading, times, why):
    lib.protect_disarm()
    li_start = [3300 if akk == "LiFe" else 3900] * 3
    start = pack(lib, li_start) if akk.startswith("Li") else pack(lib, [], vout=cells * 1200)
    feed(lib, start)
    assert arm(lib, akk, cells) == (None, 0)
    assert text(lib, feed(lib, pack(lib, **reading), times)) == why


def test_below_the_limits_nothing_trips_and_disarming_clears_a_trip(lib):
    lib.protect_disarm()
    feed(lib, pack(lib, [4150, 4190, 4200]))
    assert arm(lib, "LiPo", 3) == (None, 0)
    assert feed(lib, {**pack(lib, [4150, 4190, 4290]), ISMPS: 5000, IDIS: 0, TEXTERN: 5900}, 20) == 0
    feed(lib, {ISMPS: 6000}, 4)
    lib.protect_disarm()
    assert feed(lib, pack(lib, [3900] * 3), 4) == 0


def test_without_a_probe_at_the_start_its_input_is_not_judged(lib):
    lib.protect_disarm()
    feed(lib, pack(lib, [3900] * 3, probe=0))
    assert arm(lib, "LiPo", 3) == (None, 0)
    assert feed(lib, pack(lib, [3900] * 3, probe=0), 10) == 0
