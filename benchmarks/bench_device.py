"""Device link speed. Run: python benchmarks/bench_device.py

1. A 1 KB EEPROM image written and verified at 115200 baud through a virtual charger on a
   pty that paces both directions at the baud rate (10 bit times per byte), no modelled
   EEPROM write time. The client reads the present image (to send only changed bytes),
   stages every byte (each differs), commits, and reads back: 3 x 1024 data bytes must
   cross the wire, so the limit is 3072 x 10 / 115200 = 0.267 s. Target: within 1.5x.
   Also with the present image already known (2 x 1024 bytes must cross).
2. Telemetry frames parsed per second by ``FrameParser`` (4 KB chunks). Target: > 100 000.
"""
from __future__ import annotations

import os
import random
import statistics
import sys
import time

from zuml_studio.protocol import messages as m
from zuml_studio.device.zuml.client import ChargerClient
from zuml_studio.protocol.frames import FrameParser, encode_frame
from zuml_studio.virtual.transport import serve_pty
from zuml_studio.virtual.virtual_charger import VirtualCharger

BAUD = 115200
SIZE = 1024


def images(n: int) -> list[bytes]:
    rng = random.Random(1)
    out = []
    prev = b"\xff" * SIZE
    for _ in range(n):
        img = bytes((p + rng.randrange(1, 255)) % 255 for p in prev)    # every byte differs, never 0xFF
        out.append(img)
        prev = img
    return out


def bench_write() -> None:
    device = VirtualCharger(speed=1)
    port, stop = serve_pty(device, baud=BAUD)
    try:
        client = ChargerClient(port, BAUD)
        client.set_telemetry_rate(1)
        walls, known, wire = [], [], []
        link = stop.link
        current = client.read_image()
        for img in images(8):
            rx, tx = link.received, link.sent
            t0 = time.perf_counter()
            client.write_image(img, validate=False)
            walls.append(time.perf_counter() - t0)
            wire.append((link.received - rx) + (link.sent - tx))
            current = img
        for img in images(16)[8:]:
            t0 = time.perf_counter()
            client.write_image(img, validate=False, current=current)
            known.append(time.perf_counter() - t0)
            current = img
        assert device.eeprom_image == current
        client.close()
    finally:
        stop()
        device.close()
    limit = 3 * SIZE * 10 / BAUD
    limit_known = 2 * SIZE * 10 / BAUD
    w, k = statistics.median(walls), statistics.median(known)
    print(f"write_verify_1k_s {w:.3f}")
    print(f"write_verify_1k_wire_limit_s {limit:.3f}")
    print(f"write_verify_1k_ratio {w / limit:.2f}")
    print(f"write_verify_1k_frame_bytes {statistics.median(wire):.0f}")
    print(f"write_verify_1k_known_image_s {k:.3f}")
    print(f"write_verify_1k_known_image_wire_limit_s {limit_known:.3f}")
    print(f"write_verify_1k_known_image_ratio {k / limit_known:.2f}")


def bench_parser() -> None:
    rng = random.Random(2)
    frames = []
    for n in range(20000):
        t = m.Telemetry(n * 0.2, "charge", "charge", 1, 0, 1, 1, True, False, True, 5.0 + rng.random(),
                        rng.uniform(-1, 2), 25 + rng.random(), 30.0, n * 0.1, 0.0)
        frames.append(encode_frame(m.TELEMETRY, n & 0xFF, t.encode()))
    data = b"".join(frames)
    chunks = [data[i:i + 4096] for i in range(0, len(data), 4096)]
    rates, decode_rates = [], []
    for _ in range(5):
        p = FrameParser(m.DEVICE_TYPES)
        t0 = time.perf_counter()
        got = 0
        for c in chunks:
            got += len(p.feed(c))
        rates.append(got / (time.perf_counter() - t0))
        p = FrameParser(m.DEVICE_TYPES)
        t0 = time.perf_counter()
        for c in chunks:
            for f in p.feed(c):
                m.Telemetry.decode(f.payload)
        decode_rates.append(got / (time.perf_counter() - t0))
        assert got == len(frames)
    print(f"telemetry_frames_parsed_per_s {max(rates):.0f}")
    print(f"telemetry_frames_parsed_and_decoded_per_s {max(decode_rates):.0f}")


def main() -> None:
    if os.name == "posix":
        bench_write()
    bench_parser()
    sys.stdout.flush()


if __name__ == "__main__":
    main()
