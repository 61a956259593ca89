"""The command line against hostile bytes and failing disks (issue 12, points 5, 6, 8)."""
import os

import pytest

from helpers import MACROS, ROOT, lose_link_after_commit

pytestmark = pytest.mark.skipif(os.name != "posix", reason="ptys need POSIX")


def test_passport_control_bytes_are_printed_escaped_and_flagged(make_charger, zuml):
    device, port = make_charger(speed=20000)
    device.chip._image[0x04:0x0C] = b"\x1b[2J\r\nOK"      # what a damaged or forged chip may hold
    code, out, err = zuml("passport", "--port", port)
    assert code == 0, err
    assert "\x1b" not in out and "\r" not in out
    assert "serial   ZU\\x1b[2J\\x0d\\x0aOK0001" in out
    assert out.splitlines()[-1].startswith("warning: the passport's serial hold non-printable bytes")


@pytest.mark.skipif(not os.path.exists("/dev/full"), reason="needs /dev/full (a disk that is always full)")
def test_monitor_on_a_full_disk_says_so_once_and_keeps_streaming(any_charger, zuml):
    port = any_charger().port
    code, out, err = zuml("monitor", "--port", port, "--csv", "/dev/full", "--seconds", "1.5", "--rate", "20")
    assert code == 1
    assert "Traceback" not in err and len(err.strip().splitlines()) == 1, err
    assert err.startswith("zuml: error: /dev/full: cannot write: No space left on device")
    assert len([line for line in out.splitlines() if " V " in line]) >= 5     # the stream went on


def test_monitor_csv_that_cannot_be_opened_is_one_line(make_charger, zuml, tmp_path):
    code, out, err = zuml("monitor", "--port", "/dev/null", "--csv", str(tmp_path / "no" / "such" / "x.csv"))
    assert code == 2 and len(err.strip().splitlines()) == 1 and "cannot write" in err


def test_flash_lost_after_a_confirmed_commit_is_settled_on_reconnect(any_charger, zuml, monkeypatch):
    from zuml_studio.cli import device_commands
    monkeypatch.setattr(device_commands, "SETTLE_PAUSE_S", 0.01)
    port = any_charger().port
    lose_link_after_commit(monkeypatch)
    code, out, err = zuml("flash", "--port", port, str(MACROS / "NiMh-dV.zuml"))
    assert code == 0, err
    assert "confirmed the new image" in err and "Traceback" not in err
    assert out.strip() == "NiMh-dV: appended as slot 0; verified after reconnecting"


@pytest.mark.parametrize("commit_arrives", [True, False])
def test_another_charger_of_the_model_holding_the_image_is_not_verified_after_reconnecting(
        any_charger, zuml, monkeypatch, commit_arrives):
    """Issue 34: the cable moved to a second charger of the same model and firmware, which already holds the
    image, after a COMMIT lost on the line. IDENTIFY is equal; the write's token (the host's nonce) is not
    known there: "not verified", exit 1, whether or not the first charger committed."""
    from zuml_studio.cli import device_commands
    monkeypatch.setattr(device_commands, "SETTLE_PAUSE_S", 0.01)
    first, second = any_charger(), any_charger()
    macro = str(MACROS / "NiMh-dV.zuml")
    assert zuml("flash", "--port", second.port, macro)[0] == 0        # the second already holds the image
    real = device_commands._connect
    calls = []

    def connect(args):
        calls.append(args.port)
        if len(calls) > 1:                                             # the reconnect reaches the second charger
            args.port = second.port
        return real(args)
    monkeypatch.setattr(device_commands, "_connect", connect)
    lose_link_after_commit(monkeypatch, commit_arrives=commit_arrives, confirmed=False)
    code, out, err = zuml("flash", "--port", first.port, macro)
    assert code == 1 and out == "" and "Traceback" not in err, (out, err)
    assert "holds the new image, but it is not verified to be the one written to" in err.splitlines()[-1]
    if first.virtual:
        assert first.device.commits == int(commit_arrives)


def test_flash_whose_commit_never_arrived_says_so_after_reconnecting(any_charger, zuml, monkeypatch):
    from zuml_studio.cli import device_commands
    monkeypatch.setattr(device_commands, "SETTLE_PAUSE_S", 0.01)
    charger = any_charger()
    lose_link_after_commit(monkeypatch, commit_arrives=False, confirmed=False)
    code, out, err = zuml("flash", "--port", charger.port, str(MACROS / "NiMh-dV.zuml"))
    assert code == 1 and (not charger.virtual or charger.device.commits == 0)
    lines = err.strip().splitlines()
    assert "either the new image or its previous one" in lines[0]
    assert lines[-1] == ("zuml: error: reconnected and read back: the charger kept its previous image; "
                         "nothing was written, flash again")
    code, out, err = zuml("slots", "--port", charger.port)
    assert code == 0 and out.splitlines()[-1].startswith("0 macros"), out


class _FullDisk:
    """A standard output on a disk that fills after ``room`` writes (issue 27: `zuml monitor` ended in
    a traceback, OSError: [Errno 28] from cli/common.py)."""

    def __init__(self, room: int):
        self.room = room
        self.written = []

    def write(self, text):
        if self.room <= 0:
            raise OSError(28, "No space left on device")
        self.room -= 1
        self.written.append(text)
        return len(text)

    def flush(self):
        if self.room <= 0:
            raise OSError(28, "No space left on device")


def test_monitor_with_its_standard_output_on_a_full_disk_is_one_line(make_charger, capsys, monkeypatch):
    from zuml_studio.cli.main import main
    _device, port = make_charger(speed=20000)
    full = _FullDisk(room=3)
    monkeypatch.setattr("sys.stdout", full)
    code = main(["monitor", "--port", port, "--seconds", "5", "--rate", "20"])
    err = capsys.readouterr().err
    assert code == 1 and full.written
    assert err == "zuml: error: standard output: cannot write: No space left on device\n"


@pytest.mark.skipif(not os.path.exists("/dev/full"), reason="needs /dev/full (a disk that is always full)")
@pytest.mark.parametrize("args", [("check", str(MACROS / "LiPo.zuml")),
                                  ("log", "info", "--json", str(ROOT / "tests" / "data" / "logs" /
                                                                "308DUO_LiFe_2.3Ah_Laden_0_CH1.txt")),
                                  ("new", "--chemistry", "NiMh", "--series", "4", "--capacity", "2000")])
def test_standard_output_on_a_full_disk_is_one_line_as_a_user_runs_it(args):
    import subprocess
    import sys
    with open("/dev/full", "w") as full:
        proc = subprocess.run([sys.executable, "-m", "zuml_studio.cli.main", *args], stdout=full,
                              stderr=subprocess.PIPE, text=True, timeout=60)
    assert proc.returncode == 1
    assert proc.stderr == "zuml: error: standard output: cannot write: No space left on device\n"


def _disk_full_at_sync(monkeypatch):
    def full(fd):
        raise OSError(28, "No space left on device")
    monkeypatch.setattr("zuml_studio.recovery.os.fsync", full)


@pytest.mark.parametrize("command", ["log export", "new", "simulate --csv", "compile -o"])
def test_a_file_written_over_on_a_full_disk_stays_whole_and_no_temporary_file_is_left(zuml, tmp_path, monkeypatch,
                                                                                      command):
    # issue 27: `log export -o` over an old export left it cut mid-row; `new -o` left .NAME.PID.tmp files
    target = tmp_path / "out.file"
    target.write_text("the old file\n")
    args = {"log export": ("log", "export", str(ROOT / "tests" / "data" / "logs" /
                                                  "308DUO_LiFe_2.3Ah_Laden_0_CH1.txt"), "-o", str(target)),
            "new": ("new", "--chemistry", "NiMh", "--series", "4", "--capacity", "2000", "-o", str(target)),
            # a charge that ends in an hour (the seed's NiMh at 0.5C runs to the 1000 h guard: seconds of CPU)
            "simulate --csv": ("simulate", str(MACROS / "NiMh-dV.zuml"), "--series", "4", "--capacity", "2000",
                               "--current", "2", "--csv", str(target)),
            "compile -o": ("compile", str(MACROS / "NiMh.zuml"), "-o", str(target))}[command]
    _disk_full_at_sync(monkeypatch)
    code, out, err = zuml(*args)
    assert code == 2 and "Traceback" not in err      # compile's warnings come before the error line
    assert err.splitlines()[-1] == f"zuml: error: {target}: cannot write: No space left on device"
    assert target.read_text() == "the old file\n"
    assert sorted(p.name for p in tmp_path.iterdir()) == ["out.file"]


def test_a_flash_reconnect_that_finds_another_device_under_the_name_says_so(make_charger, zuml, monkeypatch):
    # issue 27: after the port vanished the reconnect reopened its name, by then another device, read its
    # EEPROM and gave a verdict about it
    from zuml_studio.cli import device_commands
    monkeypatch.setattr(device_commands, "SETTLE_PAUSE_S", 0.01)
    first, port = make_charger(speed=20000)
    other, other_port = make_charger(speed=20000, eeprom_size=512)
    real = device_commands.ChargerClient
    opened = []

    def connect(url, *args, **kw):            # the second opening of the name reaches the other charger
        opened.append(url)
        return real(other_port if len(opened) > 1 else url, *args, **kw)
    monkeypatch.setattr(device_commands, "ChargerClient", connect)
    lose_link_after_commit(monkeypatch, commit_arrives=False, confirmed=False)
    code, out, err = zuml("flash", "--port", port, str(MACROS / "NiMh-dV.zuml"))
    assert code == 1 and out == ""
    assert err.splitlines()[-1].startswith(f"zuml: error: {port}: after reconnecting, another device answers there (")
    assert "512 bytes of EEPROM, not the" in err and "nothing is known about the write" in err
    assert other.commits == 0
