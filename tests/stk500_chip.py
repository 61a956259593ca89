"""An STK500v1 programmer with an ATmega32 on its ISP lead, emulated on a pty, for running the real
avrdude (``-c stk500v1 -P /dev/pts/N -p m32``) in tests.

The programmer answers each command as its last byte arrives, so nothing here depends on timing. The
chip is held as its memories; what the SPI programming interface does to them follows the ATmega32
datasheet (*Memory Programming*, *Serial Programming Instruction Set*): a flash page write can only
clear bits (so a write without a chip erase shows in the verify), chip erase blanks the flash and the
lock bits and the EEPROM unless EESAVE is programmed, EEPROM bytes are erased and written one by one,
the fuses are written whole. Command codes and framing: Atmel AVR061 (STK500 communication protocol)."""
from __future__ import annotations

import os
import select
import termios
import threading
import tty
from dataclasses import dataclass, field

SIGNATURE = bytes((0x1E, 0x95, 0x02))       # ATmega32
FLASH_SIZE, FLASH_PAGE = 32 * 1024, 128
EEPROM_SIZE = 1024
LFUSE_SHIPPED, HFUSE_SHIPPED = 0xE1, 0x99   # datasheet defaults: 1 MHz RC, BOD off
EESAVE = 0x08                                # high fuse bit 3, programmed = 0

INSYNC, OK, NOSYNC, FAILED, EOP = 0x14, 0x10, 0x15, 0x11, 0x20
# command byte -> number of argument bytes before the EOP (PROG_PAGE and SET_DEVICE_EXT carry their own)
FIXED_ARGS = {0x30: 0, 0x31: 0, 0x40: 2, 0x41: 1, 0x42: 20, 0x50: 0, 0x51: 0, 0x52: 0, 0x55: 2, 0x56: 4,
              0x74: 3, 0x75: 0, 0x76: 0}
PARAMETERS = {0x80: 2, 0x81: 1, 0x82: 18, 0x84: 50, 0x85: 50, 0x86: 0, 0x87: 0, 0x89: 2, 0x98: 0xFF}


@dataclass
class Atmega32:
    flash: bytearray = field(default_factory=lambda: bytearray(b"\xff" * FLASH_SIZE))
    eeprom: bytearray = field(default_factory=lambda: bytearray(b"\xff" * EEPROM_SIZE))
    lfuse: int = LFUSE_SHIPPED
    hfuse: int = HFUSE_SHIPPED
    lock: int = 0xFF
    signature: bytes = SIGNATURE
    erases: int = 0

    def chip_erase(self) -> None:
        self.flash[:] = b"\xff" * FLASH_SIZE
        if self.hfuse & EESAVE:
            self.eeprom[:] = b"\xff" * EEPROM_SIZE
        self.lock = 0xFF
        self.erases += 1

    def program_flash_page(self, address: int, data: bytes) -> None:
        for i, byte in enumerate(data):
            self.flash[address + i] &= byte

    def universal(self, a: int, b: int, c: int, d: int) -> int:
        """One 4-byte serial programming instruction; the byte the chip shifts out last."""
        if a == 0x30:
            return self.signature[c & 3] if c & 3 < 3 else 0xFF
        if (a, b) == (0x50, 0x00):
            return self.lfuse
        if (a, b) == (0x58, 0x08):
            return self.hfuse
        if (a, b) == (0x58, 0x00):
            return self.lock
        if a == 0x38:
            return 0xA5                 # the RC oscillator's calibration byte
        if a in (0x20, 0x28):
            return self.flash[(((b << 8) | c) & 0x3FFF) * 2 + (a == 0x28)]
        if a == 0xA0:
            return self.eeprom[((b << 8) | c) & 0x3FF]
        if a == 0xC0:
            self.eeprom[((b << 8) | c) & 0x3FF] = d
        elif (a, b) == (0xAC, 0x80):
            self.chip_erase()
        elif (a, b) == (0xAC, 0xA0):
            self.lfuse = d
        elif (a, b) == (0xAC, 0xA8):
            self.hfuse = d
        elif a == 0xAC and b & 0xE0 == 0xE0:
            self.lock &= d | 0xC0       # lock bits can only be programmed, until a chip erase
        return d


class Stk500Programmer:
    """The programmer on a pty; ``port`` is the path avrdude opens. It outlives avrdude's runs (the pty
    stays open on this side) until ``close()``."""

    def __init__(self, chip: Atmega32 | None = None):
        self.chip = chip or Atmega32()
        self.commands: list[int] = []
        self._master, self._slave = os.openpty()
        tty.setraw(self._slave)
        self.port = os.ttyname(self._slave)
        self._stop_r, self._stop_w = os.pipe()
        self._pending = bytearray()
        self._address = 0
        self._thread = threading.Thread(target=self._serve, name="stk500-programmer", daemon=True)
        self._thread.start()

    def close(self) -> None:
        os.write(self._stop_w, b"x")
        self._thread.join()
        for fd in (self._master, self._slave, self._stop_r, self._stop_w):
            os.close(fd)

    def __enter__(self) -> Stk500Programmer:
        return self

    def __exit__(self, *exc: object) -> None:
        self.close()

    def _serve(self) -> None:
        while True:
            ready, _, _ = select.select([self._master, self._stop_r], [], [])
            if self._stop_r in ready:
                return
            try:
                self._pending += os.read(self._master, 4096)
            except OSError:             # no reader on the other side between avrdude runs
                continue
            while (length := self._command_length()) is not None and len(self._pending) >= length:
                command = bytes(self._pending[:length])
                del self._pending[:length]
                # avrdude reads each answer before its next command, except the answers to the GET_SYNCs it
                # sends and drains at the start: one answered after its drain would be read as the answer to
                # a later command (on a loaded machine). A new command makes whatever is unread stale.
                termios.tcflush(self._slave, termios.TCIFLUSH)
                if command == b"\x30\x20" and self._pending.startswith(b"\x30\x20"):
                    continue            # GET_SYNCs that came together: only the last one is waited for
                os.write(self._master, self._answer(command))

    def _command_length(self) -> int | None:
        """Bytes of the command at the head of the buffer, EOP included; None until that is known."""
        if not self._pending:
            return None
        code = self._pending[0]
        if code in FIXED_ARGS:
            return FIXED_ARGS[code] + 2
        if code == 0x45:                # SET_DEVICE_EXT: its second byte counts itself and what follows
            return self._pending[1] + 2 if len(self._pending) >= 2 else None
        if code == 0x64:                # PROG_PAGE: size (big endian), memory type, data
            return (self._pending[1] << 8 | self._pending[2]) + 5 if len(self._pending) >= 3 else None
        return 2 if code != EOP else 1  # unknown: answered as not in sync, as the real one does

    def _answer(self, command: bytes) -> bytes:
        code, args = command[0], command[1:-1]
        self.commands.append(code)
        if command[-1] != EOP:
            return bytes((NOSYNC,))
        if code == 0x41:
            return bytes((INSYNC, PARAMETERS.get(args[0], 0), OK))
        if code == 0x55:
            self._address = args[0] | args[1] << 8
            return bytes((INSYNC, OK))
        if code == 0x56:
            return bytes((INSYNC, self.chip.universal(*args), OK))
        if code == 0x52:
            self.chip.chip_erase()
            return bytes((INSYNC, OK))
        if code == 0x75:
            return bytes((INSYNC, *self.chip.signature, OK))
        if code == 0x74:
            return bytes((INSYNC, *self._read_page(args[2], args[0] << 8 | args[1]), OK))
        if code == 0x64:
            self._write_page(args[2], bytes(args[3:]))
            return bytes((INSYNC, OK))
        if code in FIXED_ARGS or code == 0x45:
            return bytes((INSYNC, OK))
        return bytes((NOSYNC,))

    def _read_page(self, memory: int, size: int) -> bytes:
        source = self.chip.flash if memory == ord("F") else self.chip.eeprom
        start = self._byte_address(memory)
        return bytes(source[start:start + size]).ljust(size, b"\xff")

    def _write_page(self, memory: int, data: bytes) -> None:
        start = self._byte_address(memory)
        if memory == ord("F"):
            self.chip.program_flash_page(start, data)
        else:
            self.chip.eeprom[start:start + len(data)] = data

    def _byte_address(self, memory: int) -> int:
        # LOAD_ADDRESS takes a word address for the flash and a byte address for the EEPROM (AVR061).
        return self._address * 2 if memory == ord("F") else self._address


def main(argv: list[str] | None = None) -> int:
    """``python tests/stk500_chip.py [--flash IMAGE.hex] [--eeprom FILE]``: the emulated programmer on a pty for
    trying ``zuml flash --programmer stk500v1 --port PTY`` by hand; prints the pty, serves until Ctrl+C, then
    saves the EEPROM back to FILE (docs/firmware.md, *Macros through the programmer*)."""
    import argparse
    import signal
    import sys
    from pathlib import Path

    sys.path.insert(0, str(Path(__file__).resolve().parents[1]))
    from zuml_studio.device.install.avr_install import ihex_bytes

    parser = argparse.ArgumentParser(description="an emulated STK500v1 programmer holding an iMAX B6's ATmega32")
    parser.add_argument("--flash", type=Path, help="an Intel HEX image in the flash (firmware/build/imaxb6/zuml.hex)")
    parser.add_argument("--eeprom", type=Path, help="the EEPROM, 1024 raw bytes, read at start and saved at the end")
    args = parser.parse_args(argv)
    chip = Atmega32(lfuse=0x3F, hfuse=0xC9)
    if args.flash:
        chip.flash[:] = ihex_bytes(args.flash.read_text(), FLASH_SIZE)
    if args.eeprom and args.eeprom.exists():
        chip.eeprom[:] = args.eeprom.read_bytes().ljust(EEPROM_SIZE, b"\xff")[:EEPROM_SIZE]
    stop = threading.Event()
    signal.signal(signal.SIGTERM, lambda *_: stop.set())
    signal.signal(signal.SIGINT, lambda *_: stop.set())
    with Stk500Programmer(chip) as programmer:
        print(programmer.port, flush=True)
        while not stop.wait(0.5):
            pass
    if args.eeprom:
        args.eeprom.write_bytes(bytes(chip.eeprom))
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
