"""Put a ``VirtualCharger`` behind a real port: a pty (POSIX) or a TCP listener (pyserial
``socket://HOST:PORT``, any OS).

A link has two threads: the reader takes the host's bytes, injects the device's faults
(bit errors, lost bytes, a disconnect after N bytes), paces them as they would arrive on
a wire at the baud rate, and feeds the device; the writer takes the device's output and
sends it no faster than the baud rate (10 bit times per byte, 8N1), with bit errors.
``baud=None`` (or 0) sends and receives as fast as the port allows.

``serve_pty(device) -> (port_path, stop)`` and ``serve_tcp(device, host, port) -> (url, stop)``
return at once; ``stop()`` ends the threads, closes every descriptor and detaches the
device (its thread stops with the last link).
"""
from __future__ import annotations

import errno
import math
import os
import select
import socket
import threading
import time
from typing import Callable

from .virtual_charger import VirtualCharger
from ..i18n import _

BITS_PER_BYTE = 10          # start + 8 data + stop
READ_SIZE = 4096


class _Link:
    """Moves bytes between one device and one byte stream."""

    name = "link"

    def __init__(self, device: VirtualCharger, baud: int | None):
        self.device = device
        self.byte_s = BITS_PER_BYTE / baud if baud else 0.0
        self.faults = device.faults
        self.rng = device.rng
        self._stop = threading.Event()
        # A socket pair, not a pipe: select() takes only sockets on Windows.
        self._wake_r, self._wake_w = socket.socketpair()
        # When the last byte in each direction leaves the wire (pacing at the baud rate). Bytes that
        # follow back to back continue the schedule, so a late thread wake-up does not stretch it.
        self._in_clock = 0.0
        self._out_clock = 0.0
        self._in_burst = False
        self.received = 0
        self.sent = 0
        self.closed = threading.Event()       # set once the link is down (fault or peer gone)
        self._threads: list[threading.Thread] = []
        # The disconnect fault fires once per device (a TCP listener then serves the next host).
        self._disconnect_at = None if device._disconnect_spent else device.faults.disconnect_after

    # -- the byte stream (subclasses) --
    def _fileno(self) -> int:
        raise NotImplementedError

    def _recv(self) -> bytes | None:
        """Bytes read; b"" for nothing now; None when the peer is gone."""
        raise NotImplementedError

    def _send(self, data) -> int | None:
        """Bytes written; 0 when it would block; None when the peer is gone."""
        raise NotImplementedError

    def _hangup(self) -> None:
        """The disconnect fault: the host sees the line go away."""
        raise NotImplementedError

    def _close_stream(self) -> None:
        raise NotImplementedError

    def start(self) -> None:
        for target, name in ((self._reader, "reader"), (self._writer, "writer")):
            t = threading.Thread(target=target, name=f"{self.name}-{name}", daemon=True)
            self._threads.append(t)
            t.start()

    def stop(self) -> None:
        self._wake()
        for t in self._threads:
            if t is not threading.current_thread():
                t.join(timeout=5)
        self._close_stream()
        for sock in (self._wake_r, self._wake_w):
            sock.close()
        self.closed.set()

    def _wake(self) -> None:
        self._stop.set()
        try:
            self._wake_w.send(b"x")
        except OSError:
            pass
        with self.device._out:
            self.device._out.notify_all()

    def _down(self) -> None:
        """The link is gone (fault or peer): both threads end."""
        self.closed.set()
        self._wake()

    def _flip(self, data: bytes) -> bytes:
        ber = self.faults.ber
        if not ber or not data:
            return data
        rng = self.rng
        out = bytearray(data)
        # Number of flipped bits ~ Binomial(8n, ber): walk with geometric gaps.
        bits = 8 * len(out)
        pos = -1
        log_q = math.log1p(-ber)
        while True:
            u = 1.0 - rng.random()            # (0, 1]
            pos += 1 + int(math.log(u) / log_q)
            if pos >= bits:
                break
            out[pos >> 3] ^= 1 << (pos & 7)
        return bytes(out)

    def _reader(self) -> None:
        fd = self._fileno()
        try:
            # A frame whose bytes stop coming for this long will not complete (inter-byte timeout).
            idle_s = max(0.005, 20 * self.byte_s)
            while not self._stop.is_set():
                pending = self.device.rx_pending
                try:
                    # Bytes already waiting arrived while the last ones were still on the wire:
                    # they follow back to back (the line's clock continues).
                    ready, _, _ = select.select([fd], [], [], 0)
                    self._in_burst = bool(ready)
                    if not ready:
                        ready, _, _ = select.select([fd, self._wake_r], [], [], idle_s if pending else 0.25)
                except (OSError, ValueError):
                    break
                if self._stop.is_set():
                    break
                if fd not in ready:
                    if pending:
                        self.device.line_idle()
                    continue
                data = self._recv()
                if data is None:
                    self._down()
                    break
                if not data:
                    continue
                if self._disconnect_at is not None:
                    left = self._disconnect_at - self.received
                    if len(data) >= left:
                        self._feed(data[:max(0, left)])
                        self.device._disconnect_spent = True
                        self._down()
                        for t in self._threads:       # the writer must be off the stream first
                            if t is not threading.current_thread():
                                t.join(timeout=5)
                        self._hangup()
                        break
                self._feed(data)
        except Exception:       # noqa: BLE001 - a broken stream ends the link, never the process
            self._down()

    def _feed(self, data: bytes) -> None:
        self.received += len(data)
        if self.faults.drop:
            rng = self.rng
            p = self.faults.drop
            data = bytes(b for b in data if rng.random() >= p)
        data = self._flip(data)
        if self.byte_s and data:
            now = time.monotonic()
            self._in_clock = (self._in_clock if self._in_burst else now) + len(data) * self.byte_s
            delay = self._in_clock - now
            if delay > 0:
                self._stop.wait(delay)
        if data:
            self.device.receive(data)

    def _writer(self) -> None:
        # A chunk is about 5 ms of wire time, so pacing stays smooth.
        chunk = max(16, int(0.005 / self.byte_s)) if self.byte_s else READ_SIZE
        try:
            burst = False
            while not self._stop.is_set():
                # Output ready at once after a chunk went out follows it back to back on the wire.
                data = self.device.read_output(chunk, timeout=0 if burst else 0.1)
                if not data:
                    burst = False
                    continue
                data = self._flip(data)
                if self.byte_s:
                    now = time.monotonic()
                    self._out_clock = (self._out_clock if burst else now) + len(data) * self.byte_s
                    burst = True
                    delay = self._out_clock - now
                    if delay > 0 and self._stop.wait(delay):
                        break
                view = memoryview(data)
                while view and not self._stop.is_set():
                    n = self._send(view)
                    if n is None:
                        self._down()
                        return
                    if n == 0:
                        select.select([], [self._fileno()], [], 0.05)
                        continue
                    self.sent += n
                    view = view[n:]
        except Exception:       # noqa: BLE001
            self._down()


# -- pty ---------------------------------------------------------------------------------------

class _PtyLink(_Link):
    name = "pty"

    def __init__(self, device: VirtualCharger, baud: int | None):
        super().__init__(device, baud)
        import tty
        self.master, self.slave = os.openpty()
        tty.setraw(self.slave)
        os.set_blocking(self.master, False)
        self.port = os.ttyname(self.slave)
        self._closed_fds = False

    def _fileno(self) -> int:
        return self.master

    def _recv(self) -> bytes | None:
        try:
            return os.read(self.master, READ_SIZE)
        except BlockingIOError:
            return b""
        except OSError as exc:
            if exc.errno == errno.EIO:      # no slave open right now (we keep one, so rare)
                time.sleep(0.01)
                return b""
            return None

    def _send(self, data) -> int | None:
        try:
            return os.write(self.master, data)
        except BlockingIOError:
            return 0
        except OSError as exc:
            if exc.errno in (errno.EAGAIN, errno.EIO):
                time.sleep(0.005)
                return 0
            return None

    def _hangup(self) -> None:
        self._close_stream()

    def _close_stream(self) -> None:
        if not self._closed_fds:
            self._closed_fds = True
            for fd in (self.master, self.slave):
                try:
                    os.close(fd)
                except OSError:
                    pass


def serve_pty(device: VirtualCharger, baud: int | None = 115200) -> tuple[str, Callable[[], None]]:
    """Serve the device on a new pty; returns the port path (``/dev/pts/N``) and a stop function."""
    if os.name != "posix":
        raise OSError(_("ptys need a POSIX system; use serve_tcp (socket://) instead"))
    device.attach()
    try:
        link = _PtyLink(device, baud)
    except BaseException:
        device.detach()
        raise
    link.start()
    stopped = threading.Lock()
    done = []

    def stop() -> None:
        with stopped:
            if done:
                return
            done.append(True)
            link.stop()
            device.detach()

    stop.link = link        # type: ignore[attr-defined]  # tests look at the link's counters
    return link.port, stop


# -- TCP ---------------------------------------------------------------------------------------

class _SocketLink(_Link):
    name = "tcp"

    def __init__(self, device: VirtualCharger, baud: int | None, conn: socket.socket):
        super().__init__(device, baud)
        self.conn = conn
        conn.setblocking(False)
        conn.setsockopt(socket.IPPROTO_TCP, socket.TCP_NODELAY, 1)
        self._closed_sock = False

    def _fileno(self) -> int:
        return self.conn.fileno()

    def _recv(self) -> bytes | None:
        try:
            data = self.conn.recv(READ_SIZE)
        except (BlockingIOError, InterruptedError):
            return b""
        except OSError:
            return None
        return data if data else None

    def _send(self, data) -> int | None:
        try:
            return self.conn.send(data)
        except (BlockingIOError, InterruptedError):
            return 0
        except OSError:
            return None

    def peer_gone(self) -> bool:
        """The host has hung up: its end of stream is queued (or was already read)."""
        if self.closed.is_set():
            return True
        try:
            return self.conn.recv(1, socket.MSG_PEEK) == b""
        except (BlockingIOError, InterruptedError):
            return False
        except OSError:
            return True

    def _hangup(self) -> None:
        try:
            self.conn.shutdown(socket.SHUT_RDWR)
        except OSError:
            pass

    def _close_stream(self) -> None:
        if not self._closed_sock:
            self._closed_sock = True
            try:
                self.conn.close()
            except OSError:
                pass


class _TcpServer:
    def __init__(self, device: VirtualCharger, host: str, port: int, baud: int | None):
        self.device = device
        self.baud = baud
        self.sock = socket.socket(socket.AF_INET6 if ":" in host else socket.AF_INET, socket.SOCK_STREAM)
        try:
            self.sock.setsockopt(socket.SOL_SOCKET, socket.SO_REUSEADDR, 1)
            self.sock.bind((host, port))
            self.sock.listen(2)
        except BaseException:
            self.sock.close()
            raise
        self.sock.settimeout(0.2)
        self.host, self.port = host, self.sock.getsockname()[1]
        self.link: _SocketLink | None = None
        self.connections = 0
        self._stop = threading.Event()
        self._thread = threading.Thread(target=self._accept, name="tcp-accept", daemon=True)

    def start(self) -> None:
        self._thread.start()

    def _accept(self) -> None:
        while not self._stop.is_set():
            try:
                conn, _ = self.sock.accept()
            except socket.timeout:
                self._reap()
                continue
            except OSError:
                break
            self._reap()
            if self.link is not None and self.link.peer_gone():
                # The host before hung up but its link has not seen it yet (a loaded machine):
                # its EOF is already queued, so the next host is not turned away.
                self.link.stop()
                self.link = None
            if self.link is not None:
                conn.close()                 # one host at a time, like a serial port
                continue
            self.connections += 1
            self.device.reset_link()
            self.link = _SocketLink(self.device, self.baud, conn)
            self.link.start()

    def _reap(self) -> None:
        if self.link is not None and self.link.closed.is_set():
            self.link.stop()
            self.link = None

    def stop(self) -> None:
        self._stop.set()
        try:
            self.sock.close()
        except OSError:
            pass
        self._thread.join(timeout=5)
        if self.link is not None:
            self.link.stop()
            self.link = None


def serve_tcp(device: VirtualCharger, host: str = "127.0.0.1", port: int = 0,
              baud: int | None = 115200) -> tuple[str, Callable[[], None]]:
    """Serve the device on a TCP port (0: any free one); returns ``socket://HOST:PORT`` and a stop function."""
    device.attach()
    try:
        server = _TcpServer(device, host, port, baud)
    except BaseException:
        device.detach()
        raise
    server.start()
    done = []

    def stop() -> None:
        if done:
            return
        done.append(True)
        server.stop()
        device.detach()

    stop.server = server    # type: ignore[attr-defined]
    shown = f"[{host}]" if ":" in host else host
    return f"socket://{shown}:{server.port}", stop


def serve(device: VirtualCharger, baud: int | None = None) -> tuple[str, Callable[[], None]]:
    """The built-in virtual charger's port: a pty on POSIX, else ``socket://127.0.0.1:<free port>``."""
    if os.name == "posix":
        return serve_pty(device, baud)
    return serve_tcp(device, "127.0.0.1", 0, baud)
