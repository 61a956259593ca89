"""The serial monitor's lines: timestamps at each line's start (also when a line arrives in pieces),
and in hex a new line after each pause between bursts."""
import re

from zuml_studio.device.links.serial_lines import BURST_GAP_S, MonitorLines, stamp

STAMP = r"\d\d:\d\d:\d\d\.\d\d\d → "


def test_text_without_timestamps_is_the_bytes_as_text():
    lines = MonitorLines()
    assert lines.render(0.0, b"V=12.6\r\nI=") + lines.render(0.01, b"2.0\n") == "V=12.6\nI=2.0\n"


def test_each_text_line_gets_the_time_it_began_even_when_split_across_reads():
    lines = MonitorLines(timestamps=True)
    out = lines.render(100.0, b"V=12.6\nI=") + lines.render(100.5, b"2.0\nT=25")
    first, second, third = out.split("\n")
    assert re.fullmatch(STAMP + "V=12.6", first)
    assert re.fullmatch(STAMP + "I=2.0", second) and second.startswith(stamp(100.0))   # the line began at 100.0
    assert re.fullmatch(STAMP + "T=25", third) and third.startswith(stamp(100.5))


def test_hex_breaks_the_line_at_a_pause_and_keeps_a_burst_together():
    lines = MonitorLines(hex_mode=True)
    out = (lines.render(1.0, b"\x55\xaa") + lines.render(1.0 + BURST_GAP_S / 2, b"\x01")
           + lines.render(2.0, b"\x55\xaa\x02"))
    assert out == "55 aa 01 \n55 aa 02 "
    stamped = MonitorLines(hex_mode=True, timestamps=True).render_all([(1.0, b"\x55"), (2.0, b"\xaa")])
    assert re.fullmatch(f"{STAMP}55 \n{STAMP}aa ", stamped)


def test_render_all_starts_afresh():
    lines = MonitorLines(timestamps=True)
    lines.render(1.0, b"half a line")
    assert re.fullmatch(STAMP + "x\n", lines.render_all([(3.0, b"x\n")]))
