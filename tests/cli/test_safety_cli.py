"""Every command that puts bytes on a charger runs the safety check and refuses with the
diagnostics unless --force-unsafe (issue 12, point 1)."""
import os

import pytest

from helpers import HOT_LIION, compiled, unsafe_record
from zuml_studio.lang.eeprom import pack, slots

pytestmark = pytest.mark.skipif(os.name != "posix", reason="ptys need POSIX")


@pytest.fixture
def liion(make_charger):
    """A 1-cell LiIon virtual charger: its passport's V_LIMIT is a whole 5 V."""
    return make_charger(battery="LiIon:2000:1", speed=20000)


@pytest.fixture
def hot_files(tmp_path):
    zuml_path = tmp_path / "hot.zuml"
    zuml_path.write_text(HOT_LIION)
    bin_path = tmp_path / "hot.bin"
    bin_path.write_bytes(unsafe_record())
    image_path = tmp_path / "image.bin"
    image_path.write_bytes(pack([compiled("LiIon"), unsafe_record()], 1024))
    return zuml_path, bin_path, image_path


def refused(code, err):
    assert code == 1 and "Traceback" not in err
    assert "E303" in err and "4.96 V per cell" in err
    assert "--force-unsafe" in err.splitlines()[-1]


def test_flash_of_an_unsafe_bin_is_refused_and_nothing_is_written(liion, zuml, hot_files):
    device, port = liion
    before = bytes(device.eeprom)
    code, out, err = zuml("flash", "--port", port, str(hot_files[1]))
    refused(code, err)
    assert bytes(device.eeprom) == before and device.commits == 0


def test_flash_of_an_unsafe_zuml_is_refused(liion, zuml, hot_files):
    device, port = liion
    code, out, err = zuml("flash", "--port", port, str(hot_files[0]))
    refused(code, err)
    assert device.commits == 0


@pytest.mark.parametrize("which", [0, 1])
def test_force_unsafe_flashes_with_a_warning(liion, zuml, hot_files, which):
    device, port = liion
    code, out, err = zuml("flash", "--port", port, "--force-unsafe", str(hot_files[which]))
    assert code == 0, err
    assert "E303" in err and "--force-unsafe" in err
    assert [s.name for s in slots(bytes(device.eeprom))] == ["Hot"]


def test_restore_of_an_image_with_an_unsafe_record_is_refused(liion, zuml, hot_files):
    device, port = liion
    code, out, err = zuml("restore", "--port", port, str(hot_files[2]))
    refused(code, err)
    assert "slot 1 (Hot)" in err and device.commits == 0
    code, out, err = zuml("restore", "--port", port, "--force-unsafe", str(hot_files[2]))
    assert code == 0, err


def test_image_packing_an_unsafe_record_is_refused(zuml, hot_files, tmp_path):
    out_path = tmp_path / "out.bin"
    code, out, err = zuml("image", "-o", str(out_path), str(hot_files[1]))
    refused(code, err)
    assert not out_path.exists()
    assert zuml("image", "-o", str(out_path), "--force-unsafe", str(hot_files[1]))[0] == 0


def test_run_is_refused_by_the_host_and_then_by_the_charger(liion, zuml, hot_files):
    device, port = liion
    assert zuml("flash", "--port", port, "--force-unsafe", str(hot_files[1]))[0] == 0
    code, out, err = zuml("run", "--port", port, "--slot", "0")
    refused(code, err)
    # Forced past the host's check, the charger itself refuses: the last line of defence.
    code, out, err = zuml("run", "--port", port, "--slot", "0", "--force-unsafe")
    assert code == 1 and "Traceback" not in err
    assert "refused to start slot 0 (PASSPORT_CONFLICT)" in err and "E303" in err
    from zuml_studio.device.zuml.client import ChargerClient
    with ChargerClient(port) as client:
        assert client.status().state == "idle"
