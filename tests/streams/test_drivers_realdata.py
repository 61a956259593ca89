"""Every monitor-only driver on the real recordings: checksums verified, record counts and
decoded values as the notes (shared/realdata/*.md) give them."""
import csv

import pytest

from realdata_samples import (ICHARGER_HID_REPORT, IMAXB6_README_FRAME, dollar_lines, imaxb6_frames, isdt_frames, path,
                      raw, skyrc_reply, ultramat_sections)
from zuml_studio.streams import cheali, icharger_hid, icharger_logview, imaxb6_serial, isdt_hid, skyrc_hid, ultramat


# -- cheali ----------------------------------------------------------------------------------

def test_cheali_every_real_line_verifies_and_decodes():
    lines = dollar_lines("cheali_captured_lines_from_issues.txt")
    assert len(lines) == 13
    dec = cheali.decoder()
    got = dec.feed(b"".join(line + b"\r\n" for line in lines))
    assert (len(got), dec.good, dec.bad, dec.skipped) == (13, 13, 0, 0)
    first = got[0]                   # issue #71: 1.x layout, state 8 = discharge-charge cycle, 2 cells
    assert (first.time_s, first.voltage_v, first.current_a, first.heatsink_c, first.temp_c) == \
        (23433.4, 2.459, 0.25, 34.68, None)
    assert first.cells_v == (1.202, 1.257, 0.031, 0.019, 0.011, 0.007)
    assert first.task == "train" and first.section == "" and first.running
    assert first.state == "discharge-charge cycle"
    last = got[-1]                   # issue #4: 0.2x layout, state 7 = discharging, 3 cells
    assert (last.time_s, last.voltage_v, last.current_a, last.mah_out, last.section) == \
        (2789.9, 11.481, -0.395, 305.0, "discharge")
    assert last.state == "discharging"
    assert last.cells_v[:3] == (3.824, 3.944, 3.713)


def test_cheali_line_endings_nul_and_debug_channels():
    line = dollar_lines("cheali_captured_lines_from_issues.txt")[0]
    dec = cheali.decoder()
    # LogView showed CR LF NUL on a CP21xx adapter (issue #4); $2/$3 debug lines are skipped.
    debug = b"$3;8;23433.4;"
    debug += str(__import__("functools").reduce(lambda a, b: a ^ b, debug, 0)).encode()
    got = dec.feed(line + b"\r\n\x00" + debug + b"\r\n" + line + b"\n")
    assert len(got) == 2 and dec.skipped == 1 and dec.bad == 0


def test_cheali_8_cell_builds_and_v2_long_times():
    """No real 8-cell line exists: the issue #71 line with Vb7, Vb8 and their Rth added (the
    8-cell LogView ini's layout), and a 2.01+ int32 time, checksummed by the firmware's rule."""
    from zuml_studio.streams.stream_decoder import xor8
    fields = dollar_lines("cheali_captured_lines_from_issues.txt")[0].decode().split(";")[:-1]
    fields[2] = "123456.7"
    eight = fields[:17] + ["3001", "3002"] + fields[17:23] + ["5", "6"] + fields[23:]
    body = (";".join(eight) + ";").encode()
    (t,) = cheali.decoder().feed(body + str(xor8(body)).encode() + b"\r\n")
    assert len(t.cells_v) == 8 and t.cells_v[6:] == (3.001, 3.002) and t.time_s == 123456.7
    assert t.voltage_v == 2.459 and t.state == "discharge-charge cycle"


def test_cheali_a_changed_digit_fails_the_checksum():
    line = bytearray(dollar_lines("cheali_captured_lines_from_issues.txt")[0])
    line[8] ^= 0x01                  # 23433.4 -> 23432.4 would plot a wrong time
    dec = cheali.decoder()
    assert dec.feed(bytes(line) + b"\r\n") == [] and dec.bad == 1


# -- iCharger LogView lines -----------------------------------------------------------------

@pytest.mark.parametrize("name, count, cells", [
    ("icharger208B_Storage_lines.txt", 68, 8),
    ("icharger306B_RB_1000_lines_head300.txt", 300, 6),
    ("icharger106Bplus_Laden_lines_head300.txt", 300, 6),
    ("icharger3010B_2500NiMh_lines.txt", 4606, 10),
])
def test_icharger_legacy_recordings(name, count, cells):
    dec = icharger_logview.decoder()
    got = dec.feed(raw(name))
    assert (len(got), dec.bad, dec.skipped) == (count, 0, 0)
    assert all(len(t.cells_v) == cells for t in got)
    assert [t.time_s for t in got[:3]] == [0.0, 2.0, 4.0]      # no time on the line: the 2 s step


def test_icharger_306B_values():
    t = icharger_logview.decoder().feed(b"$1;1;;15564;12645;19;4203;4204;4192;0;0;0;354;0;1;26\r\n")[0]
    assert (t.voltage_v, t.current_a, t.heatsink_c, t.temp_c, t.mah_in, t.section) == \
        (12.645, 0.19, 35.4, None, 1.0, "charge")
    assert t.cells_v == (4.203, 4.204, 4.192, 0.0, 0.0, 0.0)


def test_icharger_306B_discharge_is_sent_unsigned():
    """The 306B recording discharges (state 2) with positive current fields: the state signs it."""
    got = icharger_logview.decoder().feed(raw("icharger306B_RB_1000_lines_head300.txt"))
    discharging = [t for t in got if t.state == "discharging"]
    assert len(discharging) == 235
    assert all(t.section == "discharge" and t.current_a <= 0 for t in discharging)
    assert min(t.current_a for t in discharging) < -2.0 and discharging[-1].mah_out > 0


def test_each_phase_count_is_banked_into_the_totals():
    """The charger counts each phase from 0: the driver banks each count (the log readers' rule,
    streams/charge_counter.py), so mAh in and out are totals."""
    from zuml_studio.streams.stream_decoder import xor8

    def line(state, mah):
        body = f"$1;{state};;15564;12645;19;4203;4204;4192;0;0;0;354;0;{mah};".encode()
        return body + str(xor8(body)).encode() + b"\r\n"
    got = icharger_logview.decoder().feed(b"".join(line(s, m) for s, m in ((1, 10), (1, 20), (2, 2), (2, 5), (1, 3))))
    assert [(t.mah_in, t.mah_out) for t in got] == [(10, 0), (20, 0), (20, 2), (20, 5), (23, 5)]


def test_icharger_3010B_nimh_charge_as_the_notes_describe_it():
    got = icharger_logview.decoder().feed(raw("icharger3010B_2500NiMh_lines.txt"))
    assert got[-1].time_s == 9210.0 and got[-1].mah_in == 684.0          # stopped at 684 mAh
    assert max(t.voltage_v for t in got) == 6.113                        # plateau ~6.10 V
    assert got[0].temp_c == 20.5 and {t.run for t in got} == {1}


@pytest.mark.parametrize("name, skipped", [
    ("308DUO_LiFe_2.3Ah_Laden_0_CH1_head120.txt", 0), ("4010DUO_LiFe_2S_3A_Charge_1_CH1_head120.txt", 0),
    ("406DUO_Turnigy_4S_1500_A_Charge_0_CH1_head120.txt", 1 + 1), ("X6_LiFe_10-3A_Cycle_2_head120.txt", 2 + 1),
    ("X6_LiPo_Cycle_1_head120.txt", 1), ("X8_LiPo_5S_2200mA_Charge_4_head120.txt", 2 + 1),
    ("codelever_4010DUO_LiPo_Storage_952_CH1_head120.txt", 0),
])
def test_icharger_duo_x_logs(name, skipped):
    """Every line verifies; IR records (state 128) and the '@Model' header are skipped."""
    dec = icharger_logview.decoder()
    got = dec.feed(raw(name))
    ir = sum(1 for line in dollar_lines(name) if line.startswith(b"$1;128;"))
    header = 1 if raw(name).startswith(b"@") else 0
    assert ir + header == skipped
    assert dec.bad == 0 and dec.skipped == skipped and len(got) == len(dollar_lines(name)) - ir
    assert [t.time_s for t in got[:2]] == [0.0, 1.0]             # 1 record per second, time in ms


def test_icharger_duo_values_from_the_notes():
    x6 = icharger_logview.decoder().feed(b"$1;1;0;1;1;0;12819;20341;0;282;0;4092;4090;3989;4082;4086;0;29\r\n")[0]
    assert (x6.voltage_v, x6.current_a, x6.heatsink_c, x6.temp_c) == (20.341, 0.0, 28.2, None)
    assert x6.cells_v == (4.092, 4.090, 3.989, 4.082, 4.086, 0.0)
    duo = icharger_logview.decoder().feed(
        b"$1;1;0;1;0;0;27175;14925;0;280;243;3725;3734;3729;3733;0;0;39\r\n")[0]
    assert (duo.voltage_v, duo.temp_c, duo.heatsink_c) == (14.925, 24.3, 28.0)
    neg = icharger_logview.decoder().feed(
        b"$1;1;18000;1;0;-53;23746;22752;1;380;0;3795;3793;3798;3795;3793;3789;0;0;0;0;50\n")[0]
    # the DUO/X capacity is signed (the notes): +1 is 1 mAh in, though the current says it discharges
    assert (neg.time_s, neg.current_a, neg.section, neg.mah_in, neg.mah_out) == (18.0, -0.53, "discharge", 1.0, 0.0)
    assert neg.state == "charge"                # the log state; the current says it discharges


# -- iCharger DUO/X USB HID -------------------------------------------------------------------

def test_icharger_hid_report_from_the_notes():
    dec = icharger_hid.decoder()
    (t,) = dec.feed(ICHARGER_HID_REPORT)
    assert (t.time_s, t.section, t.current_a, t.voltage_v, t.mah_out, t.heatsink_c, t.temp_c) == \
        (491.0, "discharge", -0.27, 15.403, 49.0, 35.6, None)
    assert t.cells_v[:4] == (3.842, 3.851, 3.854, 3.840) and len(t.cells_v) == 10
    assert dec.bad == 0


# -- original iMAX B6 -------------------------------------------------------------------------

def test_imaxb6_frames_match_the_decoded_csv():
    frames = imaxb6_frames()
    dec = imaxb6_serial.decoder()
    got = dec.feed(b"".join(frames))
    assert (len(got), dec.bad) == (300, 0)
    with path("imaxb6_Ladung3S450mAh_decoded_head300.csv").open() as fh:
        rows = list(csv.DictReader(fh))
    for t, row in zip(got, rows, strict=True):
        assert round(t.voltage_v * 1000) == int(row["V_mV"])
        assert round(t.current_a * 1000) == int(row["I_mA"])
        assert t.mah_in == float(row["C_mAh"])
        assert [round(c * 1000) for c in t.cells_v] == [int(row[f"c{k}_mV"]) for k in range(1, 7)]


def test_imaxb6_readme_frame():
    (t,) = imaxb6_serial.decoder().feed(IMAXB6_README_FRAME)
    assert (t.current_a, t.voltage_v, t.mah_in, t.section) == (2.21, 7.76, 58.0, "charge")
    assert t.cells_v[:2] == (3.88, 3.86)


def test_imaxb6_a_bad_checksum_is_counted():
    frame = bytearray(IMAXB6_README_FRAME)
    frame[36] ^= 0x01
    dec = imaxb6_serial.decoder()
    assert dec.feed(bytes(frame) + IMAXB6_README_FRAME) and dec.good == 1 and dec.bad == 1


# -- Ultramat -----------------------------------------------------------------------------------

def test_ultramat_frames_per_model_with_their_checksum_offsets():
    counts = {}
    for model, frames in ultramat_sections().items():
        dec = ultramat.decoder()
        got = dec.feed(b"".join(frames))
        counts[model] = (len(frames), len(got), dec.skipped, dec.bad)
    # every model's frames verify (Ultramat18 with +0x180, UltraDuoPlus45 with +0x480) and decode
    assert counts == {"UltraDuoPlus45": (157, 157, 0, 0), "Ultramat12": (50, 50, 0, 0),
                      "Ultramat16": (69, 69, 0, 0), "Ultramat18": (38, 38, 0, 0)}


def test_ultramat_worked_example():
    (t,) = ultramat.decoder().feed(b"\x0c823638010015410064000000000000000000000000000008D4\r")
    assert (t.voltage_v, t.current_a) == (5.441, 0.1)
    dec = ultramat.decoder()
    assert dec.feed(b"\x0c823638010015410064000000000000000000000000000008D5\r") == [] and dec.bad == 1


# -- ISDT ---------------------------------------------------------------------------------------

def test_isdt_real_frames():
    frames = isdt_frames()
    assert len(frames) == 5
    q8 = isdt_hid.IsdtDecoder(channel=4)
    (t,) = q8.feed(b"".join(frames[:3]))
    assert (t.section, t.voltage_v, t.current_a, t.temp_c, t.heatsink_c) == ("charge", 28.437, 1.0, 29.0, 10.0)
    assert q8.skipped == 2 and q8.bad == 0                   # channels 5 and 6
    c4 = isdt_hid.IsdtDecoder(channel=0)
    (done,) = c4.feed(frames[3])
    assert (done.running, done.time_s, done.temp_c, done.heatsink_c) == (False, 448.0, 34.0, 41.0)
    escaped = isdt_hid.IsdtDecoder()
    (t,) = escaped.feed(frames[4])                           # 0xAA inside is sent as AA AA
    assert (t.voltage_v, t.current_a, t.time_s, t.mah_in + t.mah_out) == (1.91, 0.663, 2169.0, 0.0)
    assert escaped.bad == 0


def test_isdt_poll_request_matches_the_real_one():
    assert isdt_hid.poll_request(4) == bytes.fromhex("0106aa1202de04f6")


# -- SkyRC --------------------------------------------------------------------------------------

def test_skyrc_real_reply_verifies_and_is_skipped():
    reply = bytes.fromhex("0F 0F 5F 00 02 00 00 00 3C 14 01 02 0E 07 FF FF C7 FF FF").ljust(64, b"\0")
    dec = skyrc_hid.decoder()
    assert dec.feed(reply) == [] and (dec.skipped, dec.bad) == (1, 0)
    broken = bytearray(reply)
    broken[16] ^= 1
    assert dec.feed(bytes(broken)) == [] and dec.bad == 1


def test_skyrc_every_captured_packet_verifies():
    """knifter's capture: the host's packets (start, stop, 0x5F) and the first, clean reply; the
    later replies are mis-aligned sniffer dumps (skyrc_hid.md) and are not frames."""
    import re
    text = path("skyrc_knifter_b6mini_usb_capture.txt").read_text()
    lines = [line for line in text.splitlines() if line.startswith("0F ")]
    lines[1] += " C7 FF FF"                    # the clean reply continues on the next line of the capture
    packets = [bytes.fromhex(" ".join(re.findall(r"\b[0-9A-F]{2}\b", line.split("    ")[0]))) for line in lines]
    packets = [p[:p[1] + 4] for p in packets]     # one line also holds the start of an answer
    assert len(packets) == 17               # 10 distinct (skyrc_hid.md), some sent more than once
    for p in packets:
        length = p[1]
        assert p[length + 1] == skyrc_hid.checksum(p, length) and p[length + 2:length + 4] == b"\xff\xff"
    dec = skyrc_hid.decoder()
    assert dec.feed(b"".join(p.ljust(64, b"\0") for p in packets)) == []
    assert (dec.skipped, dec.bad) == (17, 0)


def test_skyrc_poll_request_is_the_captured_one():
    assert skyrc_hid.POLL == bytes.fromhex("0F 03 55 00 55 FF FF")


@pytest.mark.parametrize("name", ["skyrc_B6ACv2_Charging_head100.csv", "skyrc_B6ACv2_Discharging_head100.csv"])
def test_skyrc_telemetry_layout_with_real_logged_values(name):
    """No raw 0x55 reply exists publicly (skyrc_hid.md): the values a B6AC v2 logged over it are
    put back into the documented layout and must come out unchanged."""
    with path(name).open() as fh:
        rows = list(csv.DictReader(fh))
    sign = -1 if "Discharging" in name else 1
    reports = b"".join(skyrc_reply(1, int(r["mAH"]), int(float(r["SN"])), round(float(r["Volatge"]) * 1000),
                                    sign * int(r["Current"]), 0, 30, [round(float(r["Volatge"]) * 1000)])
                       for r in rows)
    dec = skyrc_hid.decoder()
    got = dec.feed(reports)
    assert len(got) == len(rows) and dec.bad == 0
    for t, r in zip(got, rows):
        assert round(t.voltage_v * 1000) == round(float(r["Volatge"]) * 1000)
        assert round(t.current_a * 1000) == sign * int(r["Current"])
        assert t.heatsink_c == 30.0 and t.temp_c is None
