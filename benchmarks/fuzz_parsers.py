"""Fuzz every parser of outside input; any exception other than the parser's own precise error
is a crash. Run: python benchmarks/fuzz_parsers.py [N] [SEED]   (N inputs per parser, default 100000)

Parsers: macro text (compile_source: never raises), a record's bytes (decode_record:
DecodeError only), an EEPROM image (slots: ImageError only), a passport answer and request
(PassportError only) and what the safety check makes of it, serial bytes (FrameParser: never
raises), message payloads (PayloadError only), port URLs (BadPortUrl only), the CLI's start
values are in fuzz_cli.py, files in fuzz_files.py). Inputs are the project's macros, records
and frames mutated (bit flips, splices, repeats, huge numbers, control bytes) and random bytes.
Each input runs under a time limit (fuzz_common.LIMIT_S: slower is a hang). Prints per parser:
inputs, crashes, hangs, the first of each kind, the time taken, and a summary table.
"""
from __future__ import annotations

import random
import sys
from pathlib import Path

from zuml_studio.protocol import messages as m
from zuml_studio.protocol import passport as pp
from zuml_studio.protocol.frames import FrameParser, encode_frame
from zuml_studio.device.links.port_url import BadPortUrl, check_port_url
from zuml_studio.lang.compiler import compile_source
from zuml_studio.lang.decoder import decode_record
from zuml_studio.lang.eeprom import ImageError, pack, slots
from zuml_studio.lang.record import DecodeError
from zuml_studio.safety import judge
from zuml_studio.virtual.passport_chip import default_passport

sys.path.insert(0, str(Path(__file__).resolve().parent))
from fuzz_common import Campaign, mutate_bytes

ROOT = Path(__file__).resolve().parent.parent
TEXTS = [p.read_text("utf-8-sig") for p in sorted([*(ROOT / "macros").glob("*.zuml"),
                                                  *(ROOT / "tests" / "data").glob("*.zuml")])]
assert TEXTS, "no macros to mutate: the fuzzer's seeds moved"
RECORDS = [compile_source(t).record for t in TEXTS if compile_source(t).ok]
NASTY = ["9" * 30, "1e999", "-0", "0x1F", "INPUT", "\x1b[2J", "\0", "(", ")", "//", "\r\n", "ā", "  ", ",,",
         "99999999999999999999999999999.99999", "0." + "0" * 40 + "1", "IF(", "FAZE", "END_MACRO"]


def mutate_text(rng: random.Random, text: str) -> str:
    for _ in range(rng.randint(1, 4)):
        at = rng.randrange(len(text) + 1)
        kind = rng.random()
        if kind < 0.35:
            text = text[:at] + rng.choice(NASTY) + text[at:]
        elif kind < 0.6:
            text = text[:at] + text[at + rng.randint(1, 12):]
        elif kind < 0.8:
            other = rng.choice(TEXTS)
            b = rng.randrange(len(other))
            text = text[:at] + other[b:b + rng.randint(1, 60)] + text[at:]
        else:
            text = text[:at] + chr(rng.randrange(1, 0x3000)) + text[at:]
    return text


def fix_check(record: bytes) -> bytes:
    """Half the mutated records get a correct check byte, so the decoder looks past it."""
    from zuml_studio.lang.record import check_byte
    if not record:
        return record
    body = bytearray(record)
    body[0] = len(body) & 0xFF
    body[-1] = check_byte(bytes(body[:-1]))
    return bytes(body)


def main() -> int:
    n = int(sys.argv[1]) if len(sys.argv) > 1 else 100_000
    passport = default_passport("LiPo", 2000, 3)
    frames = [encode_frame(code, seq, m.encode_response("STATUS", state=1, slot=0, task=0, uptime_ms=5, run_ms=5,
                                                          events=0, speed=1, name="x", end_reason=""))
              for code, seq in ((0x80 | m.BY_NAME["STATUS"].code, 3),)]
    telemetry = frames[0]

    def text(rng):
        return mutate_text(rng, rng.choice(TEXTS))

    def record(rng):
        r = mutate_bytes(rng, rng.choice(RECORDS))
        return fix_check(r) if rng.random() < 0.5 else r

    def decode_and_check(data):
        decode_record(data)
        judge(data, passport)          # a record that decodes must also pass through the safety check

    def image(rng):
        return mutate_bytes(rng, pack(rng.sample(RECORDS, 2), 256))

    def passport_answer(rng):
        data = mutate_bytes(rng, passport.to_bytes())
        if rng.random() < 0.5 and len(data) == 32:
            data = data[:0x1E] + pp.check_word(data).to_bytes(2, "little")
        return data

    def passport_show(data):
        p = pp.Passport.from_bytes(data)
        assert all(" " <= c <= "~" for c in pp.printable(p.serial) + pp.printable(p.vendor)), "unescaped"

    def serial_stream(rng):
        return mutate_bytes(rng, telemetry * rng.randint(1, 4)) if rng.random() < 0.8 else \
            bytes(rng.randrange(256) for _ in range(rng.randint(0, 200)))

    def feed(data):
        parser = FrameParser(m.DEVICE_TYPES)
        parser.feed(data)
        parser.flush_stale()

    def payload(rng):
        code = rng.choice([t.code for t in m.BY_NAME.values()])
        return code, bytes(rng.randrange(256) for _ in range(rng.randint(0, 60)))

    def decode_payload(item):
        code, data = item
        m.decode_response(code, data)

    def url(rng):
        base = rng.choice(["socket://127.0.0.1:7777", "rfc2217://host:2217?timeout=3", "/dev/ttyUSB0",
                           "socket://[::1]:7777?logging=debug", "loop://"])
        return mutate_text(rng, base)

    from zuml_studio.virtual.virtual_charger import VirtualCharger
    charger = [VirtualCharger(), 0]
    requests = sorted(m.HOST_TYPES)
    good = [encode_frame(m.BY_NAME[name].code, 1, m.encode_request(name, **fields)) for name, fields in (
        ("IDENTIFY", {}), ("STATUS", {}), ("READ_EEPROM", {"offset": 0, "length": 64}),
        ("GET_TEMPLATE", {"number": 1}), ("LIST_TEMPLATES", {}), ("SET_TELEMETRY_RATE", {"hz": 5}),
        ("PASSPORT", {"request": pp.read_all_request()}))]

    def host_bytes(rng):
        """What a host (or a line's noise) sends the charger: frames of every request type with
        random payloads and correct checks, real requests mutated, and random bytes."""
        out = b""
        for _ in range(rng.randint(1, 5)):
            kind = rng.random()
            if kind < 0.5:
                out += encode_frame(rng.choice(requests), rng.randrange(256), rng.randbytes(rng.randint(0, 40)))
            elif kind < 0.85:
                out += mutate_bytes(rng, rng.choice(good))
            else:
                out += rng.randbytes(rng.randint(1, 60))
        return out

    def charger_answers(data):
        charger[1] += 1
        if charger[1] % 1000 == 0:                        # a fresh charger now and then: state differs
            charger[0] = VirtualCharger()
        charger[0].receive(data)
        charger[0].line_idle()
        charger[0].read_output(1 << 20)

    c = Campaign(SEED)
    failures = 0
    failures += c.run("macro text", n, text, compile_source, ())
    failures += c.run("record bytes", n, record, decode_and_check, (DecodeError,))
    failures += c.run("EEPROM image", n, image, slots, (ImageError,))
    failures += c.run("passport answer", n, passport_answer, passport_show, (pp.PassportError,))
    failures += c.run("passport request", n, lambda rng: mutate_bytes(rng, pp.read_all_request()),
                      pp.parse_request, (pp.PassportError,))
    failures += c.run("serial stream", n, serial_stream, feed, ())
    failures += c.run("message payload", n, payload, decode_payload, (m.PayloadError,))
    failures += c.run("port URL", n, url, check_port_url, (BadPortUrl,))
    failures += c.run("virtual charger rx", n, host_bytes, charger_answers, ())
    c.table()
    print(f"total findings: {failures}")
    return 1 if failures else 0


SEED = int(sys.argv[2]) if len(sys.argv) > 2 else 12
if __name__ == "__main__":
    sys.exit(main())
