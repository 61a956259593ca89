"""zuml flash / slots / backup / restore --programmer: macros into an iMAX B6's EEPROM through its ISP
programmer, with the real avrdude against the emulated STK500v1 programmer (tests/stk500_chip.py), and end to
end: the EEPROM written that way runs on the simulated B6 (`zuml firmware-sim --board imaxb6`)."""
import subprocess
import sys
from pathlib import Path

import pytest

from b6_eeprom import ZUML_FLASH, b6_eeprom
from chargers import NEEDS_FIRMWARE_SIM
from helpers import HOT_LIION, compiled
from stk500_chip import Atmega32, Stk500Programmer
from tools import AVRDUDE, needs
from zuml_studio.device.avr_install import FLASH_SIZE, IMAGE, ihex_bytes
from zuml_studio.device.client import ChargerClient
from zuml_studio.device.isp_store import IMAGE_SIZE, TEMPLATES_AT
from zuml_studio.lang.eeprom import slots
from zuml_studio.sim.start_templates import StartTemplate, factory_templates

pytestmark = needs(AVRDUDE)
MACROS = Path(__file__).resolve().parents[2] / "macros"


@pytest.fixture
def b6():
    """A B6 with the ZUML image in its flash and an empty store, behind the emulated programmer."""
    chip = Atmega32(flash=bytearray(ZUML_FLASH), eeprom=bytearray(b6_eeprom()), lfuse=0x3F, hfuse=0xC9)
    with Stk500Programmer(chip) as programmer:
        yield chip, ("--programmer", "stk500v1", "--port", programmer.port)


@pytest.fixture
def hot(tmp_path):
    path = tmp_path / "hot.zuml"
    path.write_text(HOT_LIION)
    return str(path)


def test_flash_writes_two_macros_leaves_templates_and_calibration_alone_and_says_what_changed(zuml, b6):
    chip, link = b6
    before = bytes(chip.eeprom)
    code, out, err = zuml("flash", *link, str(MACROS / "LiPo.zuml"), str(MACROS / "NiMh.zuml"))
    assert code == 0, err
    lines = out.splitlines()
    assert lines[0] == "LiPo: appended as slot 0"
    assert lines[1].startswith("NiMh: appended as slot 1; ") and lines[1].endswith(" bytes written, verified")
    assert "Disconnect the battery first" in err
    image = bytes(chip.eeprom[:IMAGE_SIZE])
    assert [s.name for s in slots(image)] == ["LiPo", "NiMh"]
    assert chip.eeprom[IMAGE_SIZE:TEMPLATES_AT] == image                    # the staging copy: the same bytes
    assert chip.eeprom[TEMPLATES_AT:] == before[TEMPLATES_AT:]              # templates, flag, journal, calibration
    assert chip.erases == 0 and chip.flash == ZUML_FLASH
    code, out, err = zuml("flash", *link, str(MACROS / "LiPo.zuml"))          # again: replaced by its name
    assert code == 0 and out == "LiPo: replaced slot 0 (LiPo); 0 bytes written, verified\n", err


def test_an_e303_macro_is_refused_and_nothing_is_written(zuml, b6, hot):
    chip, link = b6
    before = bytes(chip.eeprom)
    code, out, err = zuml("flash", *link, str(MACROS / "LiPo.zuml"), hot)
    assert code == 1 and "E303" in err and "4.96 V per cell" in err
    assert err.splitlines()[-1].endswith("nothing written (safety errors only: --force-unsafe writes it anyway)")
    assert bytes(chip.eeprom) == before


def test_the_check_judges_with_the_chip_s_own_templates(zuml, b6, tmp_path):
    # template 5, stored on this chip only, says 2 cells: the macro naming it charges to 6.30 V per cell (E303)
    chip, link = b6
    named = tmp_path / "named.zuml"
    named.write_text("MACRO Tpl-LiPo\n  AKK_TYPE=LiPo\n  START_SHABLON=5\n  CHARGE_SECTION\n    FAZE\n"
                     "    CONSTANT_I=1A\n    IF(V>12.6V) STOP_FAZE()\n    END_FAZE\n  END_SECTION\nEND_MACRO\n")
    assert zuml("flash", *link, str(named))[0] == 0          # the factory table has no template 5
    chip.eeprom[:] = b6_eeprom(templates={**factory_templates(), 5: StartTemplate(series=2, capacity_mah=2000,
                                                                                  current_a=1.0)})
    code, out, err = zuml("flash", *link, str(named))
    assert code == 1 and "E303" in err and "6.30 V per cell" in err and "[start template 5: " in err, err


def test_slots_lists_what_the_chip_holds_with_the_check_s_marks(zuml, b6, hot):
    chip, link = b6
    assert zuml("flash", *link, "--force-unsafe", str(MACROS / "LiPo.zuml"), hot)[0] == 0
    code, out, err = zuml("slots", *link)
    assert code == 0, err
    lines = out.splitlines()
    assert lines[1].split()[3] == "LiPo" and lines[1].endswith("ok")
    assert lines[2].split()[3] == "Hot" and lines[2].endswith("UNSAFE (E303)")
    assert lines[3].startswith("2 macros; free ") and lines[3].endswith(f" of {IMAGE_SIZE} bytes")
    assert lines[4:] == ["start templates: 1, 2, 3", "calibration: valid"]


def test_backup_and_restore_of_the_store_through_the_programmer(zuml, b6, tmp_path):
    chip, link = b6
    assert zuml("flash", *link, str(MACROS / "LiPo.zuml"), str(MACROS / "NiMh.zuml"))[0] == 0
    saved = bytes(chip.eeprom)
    code, out, err = zuml("backup", *link, "-o", str(tmp_path / "store.bin"))
    assert code == 0 and "(2 macros)" in out, err
    assert (tmp_path / "store.bin").read_bytes() == saved[:IMAGE_SIZE]         # as a serial backup: the image
    chip.eeprom[:2 * IMAGE_SIZE] = b"\xff" * (2 * IMAGE_SIZE)
    code, out, err = zuml("restore", *link, str(tmp_path / "store.bin"))
    assert code == 0 and out.endswith("bytes written, verified\n"), err
    assert bytes(chip.eeprom) == saved


def test_a_chip_without_the_zuml_firmware_is_left_alone(zuml, b6):
    chip, link = b6
    chip.flash[:] = b"ORIGINAL-IMAX-B6-FIRMWARE" * 1310 + b"\xff" * (FLASH_SIZE - 32750)
    before = bytes(chip.eeprom)
    code, out, err = zuml("flash", *link, str(MACROS / "LiPo.zuml"))
    assert code == 1 and err.splitlines()[-1] == (
        "zuml: error: the charger does not run the ZUML firmware (its flash holds no ZUML imaxb6 image): its EEPROM "
        "is another firmware's; install ZUML first (zuml firmware install); nothing was written")
    assert bytes(chip.eeprom) == before


def test_without_a_programmer_or_a_port_it_says_what_to_give(zuml, monkeypatch):
    monkeypatch.delenv("ZUML_PORT", raising=False)
    code, out, err = zuml("slots")
    assert code == 2 and err == "zuml: error: give the port: --port /dev/ttyUSB0 (see `zuml ports`)\n"


def firmware_sim(eeprom: Path, *more: str) -> tuple[subprocess.Popen, str]:
    proc = subprocess.Popen([sys.executable, "-m", "zuml_studio.cli.main", "firmware-sim", "--board", "imaxb6",
                             "--eeprom", str(eeprom), "--speed", "0", *more], stdout=subprocess.PIPE,
                            stderr=subprocess.DEVNULL, text=True)
    return proc, proc.stdout.readline().strip()


def stop(proc: subprocess.Popen) -> None:
    proc.terminate()
    proc.wait(timeout=60)
    proc.stdout.close()


@NEEDS_FIRMWARE_SIM
def test_end_to_end_the_eeprom_written_through_the_programmer_runs_on_the_simulated_b6(zuml, tmp_path, hot):
    subprocess.run(["make", "-s", "-C", str(IMAGE.parents[2]), "imaxb6", "simavr-imaxb6"], check=True)
    # 1. the EEPROM as the firmware leaves it: the simulated B6's first start stores the templates and its
    #    calibration (as after `zuml firmware install` and `zuml calibrate`)
    first = tmp_path / "first.bin"
    proc, port = firmware_sim(first)
    with ChargerClient(port, timeout=10) as client:
        assert client.list_templates() == [1, 2, 3]
    stop(proc)
    as_left = first.read_bytes()
    # 2. the real image in the flash, that EEPROM, behind the programmer; two macros written, an E303 one refused
    chip = Atmega32(flash=bytearray(ihex_bytes(IMAGE.with_suffix(".hex").read_text(), FLASH_SIZE)),
                    eeprom=bytearray(as_left), lfuse=0x3F, hfuse=0xC9)
    with Stk500Programmer(chip) as programmer:
        link = ("--programmer", "stk500v1", "--port", programmer.port)
        code, out, err = zuml("flash", *link, str(MACROS / "LiPo.zuml"), str(MACROS / "NiMh.zuml"))
        assert code == 0, err
        assert zuml("flash", *link, hot)[0] == 1
    assert chip.eeprom[TEMPLATES_AT:] == as_left[TEMPLATES_AT:]
    # 3. the simulated B6 on that EEPROM lists the macros and starts the first by its request protocol
    written = tmp_path / "written.bin"
    written.write_bytes(bytes(chip.eeprom))
    proc, port = firmware_sim(written, "--cells", "3")
    try:
        with ChargerClient(port, timeout=10) as client:
            assert [s.name for s in client.slots()] == ["LiPo", "NiMh"]
            assert client.start(0, "charge", current_a=1.0, series=3) == "LiPo"
            assert client.status().state == "running"
            client.stop()
    finally:
        stop(proc)
