#!/usr/bin/env python3
"""A fake avrdude for the install's failure cases (after ../shared/repro/hostile-3/firmware/bin/avrdude): an
ATmega32 kept in $FAKE_AVR_STATE (flash.bin, eeprom.bin, fuses.json), -U operations as avrdude does them.
$FAKE_AVR_MODE: ok | fail | hang_silent | hang_chatty | garbage_exit0 | fail_on_write | fail_mid_flash_write |
fuse_write_ignored | lfuse_garbage | read_truncates. Each run is logged to $FAKE_AVR_STATE/calls.log."""
import json
import os
import sys
import time

S = os.environ["FAKE_AVR_STATE"]
MODE = os.environ.get("FAKE_AVR_MODE", "ok")


def load(name, size):
    path = os.path.join(S, name)
    return bytearray(open(path, "rb").read()) if os.path.exists(path) else bytearray(b"\xff" * size)


flash, eeprom = load("flash.bin", 32768), load("eeprom.bin", 1024)
FUSES = os.path.join(S, "fuses.json")
fuses = json.load(open(FUSES)) if os.path.exists(FUSES) else {"lfuse": 0x3F, "hfuse": 0xC9, "lock": 0xFF}


def save():
    open(os.path.join(S, "flash.bin"), "wb").write(flash)
    open(os.path.join(S, "eeprom.bin"), "wb").write(eeprom)
    json.dump(fuses, open(FUSES, "w"))


args = sys.argv[1:]
open(os.path.join(S, "calls.log"), "a").write(MODE + " " + " ".join(args) + "\n")
if MODE == "fail":
    print("avrdude: error: could not find USB device with vid=0x16c0 pid=0x5dc", file=sys.stderr)
    sys.exit(1)
if MODE == "hang_silent":
    time.sleep(3600)
if MODE == "hang_chatty":
    while True:
        print("avrdude: usbasp_transmit(): retrying ...", file=sys.stderr, flush=True)
        time.sleep(0.05)
if MODE == "garbage_exit0":
    print("\x00\xff@@@ garbage ###", file=sys.stderr)
    sys.exit(0)
operations = [args[i + 1] for i, a in enumerate(args) if a == "-U"]


def ihex(data):
    end = len(data.rstrip(b"\xff"))
    end = end // 2 if MODE == "read_truncates" else end
    out = []
    for a in range(0, end, 16):
        chunk = data[a:a + 16]
        rec = bytes([len(chunk), a >> 8 & 0xFF, a & 0xFF, 0]) + chunk
        out.append(":" + rec.hex().upper() + f"{(-sum(rec)) & 0xFF:02X}")
    return "\n".join(out + [":00000001FF"]) + "\n"


def unhex(text, size):
    d = bytearray(b"\xff" * size)
    for line in text.split():
        b = bytes.fromhex(line[1:])
        if b[3] == 0:
            d[b[1] << 8 | b[2]:(b[1] << 8 | b[2]) + b[0]] = b[4:4 + b[0]]
    return d


memories = {"flash": flash, "eeprom": eeprom}
if "-e" in args:
    flash[:] = b"\xff" * len(flash)
    save()
for op in operations:
    memory, kind, rest = op.split(":", 2)
    name, fmt = rest.rsplit(":", 1)
    if kind == "r":
        if memory in fuses:
            text = "zz\n" if MODE == "lfuse_garbage" and memory == "lfuse" else f"0x{fuses[memory]:02x}\n"
            open(name, "w").write(text)
        else:
            open(name, "w").write(ihex(memories[memory]))
        print(f"avrdude: reading {memory} memory: done", file=sys.stderr)
    elif kind in ("w", "v"):
        if kind == "w" and MODE in ("fail_on_write", "fail_mid_flash_write"):
            if MODE == "fail_mid_flash_write" and memory == "flash":
                flash[:16384] = b"\x00" * 16384
                save()
            print("avrdude: error: programmer is not responding", file=sys.stderr)
            sys.exit(1)
        if memory in fuses:
            value = int(name, 16) if fmt == "m" else int(open(name).read().split()[0], 16)
            if kind == "w" and MODE != "fuse_write_ignored":
                fuses[memory] = value
            continue
        raw = open(name, "rb").read()
        size = len(memories[memory])
        data = unhex(raw.decode(), size) if fmt == "i" else bytearray(raw.ljust(size, b"\xff"))
        if kind == "w":
            memories[memory][:] = data
        elif data != memories[memory]:
            print("avrdude: verification error, first mismatch at byte 0x0000", file=sys.stderr)
            sys.exit(1)
save()
sys.exit(0)
