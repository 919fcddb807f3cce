"""The gate between an external controller process and swum-emu in lockstep (Modbus TCP).

The controller connects to the gate as it would to the emulator; every request is passed on
unchanged, except that a write covering the `advance` holding register (the request that moves
emulated time) waits until the bench lets one cycle through. After the emulator's reply the
bench reads the state (its own FC04) and records it with the set-points the controller has
written, then the reply goes back to the controller. So the bench owns emulated time: a test
steps an external controller exactly as it steps one written in Python.

MBAP framing (docs/protocols.md): transaction id, protocol id 0, length (unit id + PDU), unit
id, then the PDU; the gate reads whole frames and keeps a copy of the holding registers."""
import queue
import socket
import struct
import threading

from .emulator import BenchError

ADVANCE = 10


def _recv_exact(sock, n):
    data = b""
    while len(data) < n:
        chunk = sock.recv(n - len(data))
        if not chunk:
            return None
        data += chunk
    return data


def read_frame(sock):
    """One MBAP frame (header + PDU) or None at end of stream; a frame with a protocol id other
    than 0 or a length outside 2..254 is a BenchError."""
    head = _recv_exact(sock, 7)
    if head is None:
        return None
    _, protocol, length, _ = struct.unpack(">HHHB", head)
    if protocol != 0 or not 2 <= length <= 254:
        raise BenchError(f"Modbus gate: bad MBAP header {head.hex()} (protocol {protocol}, length {length})")
    body = _recv_exact(sock, length - 1)
    if body is None:
        return None
    return head + body


def written_registers(pdu):
    """{address: value} a write request sets (FC06, FC16), else {}."""
    if not pdu:
        return {}
    fc = pdu[0]
    if fc == 0x06 and len(pdu) == 5:
        address, value = struct.unpack(">HH", pdu[1:5])
        return {address: value}
    if fc == 0x10 and len(pdu) >= 6:
        start, count, nbytes = struct.unpack(">HHB", pdu[1:6])
        if nbytes != 2 * count or len(pdu) != 6 + nbytes:
            return {}
        values = struct.unpack(f">{count}H", pdu[6:6 + nbytes])
        return {start + i: v for i, v in enumerate(values)}
    return {}


class ModbusGate:
    def __init__(self, upstream, on_cycle):
        """upstream: (host, port) of swum-emu; on_cycle(holding_words) is called on the gate's
        thread after each advance the emulator answered, before the controller sees the reply."""
        self.upstream = upstream
        self.on_cycle = on_cycle
        self.holding = {}
        self.events = queue.Queue()
        self._permits = threading.Semaphore(0)
        self._stop = threading.Event()
        self._opened = threading.Event()  # closing: cycles pass unheld and unrecorded
        self._open_connections = 0
        self._count_lock = threading.Lock()
        self._listener = socket.create_server(("127.0.0.1", 0))
        self._listener.settimeout(0.2)
        self.port = self._listener.getsockname()[1]
        self._threads = [threading.Thread(target=self._accept, daemon=True)]
        self._connections = []
        self._threads[0].start()

    @property
    def endpoint(self):
        return f"tcp://127.0.0.1:{self.port}"

    def release(self):
        """Lets one more advance through."""
        self._permits.release()

    def open(self):
        """From now on advances pass without waiting and without being recorded (the bench is
        closing: a controller's last cycles, e.g. its drive-off, must not hang)."""
        self._opened.set()

    def quiet_after_exit(self):
        """After the controller exited: True once none of its connections is still being
        served (their end of stream comes after every request they carried)."""
        with self._count_lock:
            return self._open_connections == 0

    def close(self):
        self._stop.set()
        self._listener.close()
        for s in list(self._connections):
            try:
                s.shutdown(socket.SHUT_RDWR)
            except OSError:
                pass
            s.close()
        for t in self._threads:
            t.join(5)

    def _accept(self):
        while not self._stop.is_set():
            try:
                client, _ = self._listener.accept()
            except socket.timeout:
                continue
            except OSError:
                return
            with self._count_lock:  # counted from the accept on: quiet_after_exit sees it at once
                self._open_connections += 1
            t = threading.Thread(target=self._serve, args=(client,), daemon=True)
            self._threads.append(t)
            t.start()

    def _wait_permit(self):
        while not self._stop.is_set():
            if self._opened.is_set() or self._permits.acquire(timeout=0.2):
                return True
        return False

    @staticmethod
    def _peer_closed(sock):
        try:
            return sock.recv(1, socket.MSG_PEEK | socket.MSG_DONTWAIT) == b""
        except BlockingIOError:
            return False
        except OSError:
            return True

    def _serve(self, client):
        try:
            self._serve_connection(client)
        finally:
            with self._count_lock:
                self._open_connections -= 1

    def _serve_connection(self, client):
        self._connections.append(client)
        try:
            upstream = socket.create_connection(self.upstream, timeout=None)
        except OSError as e:
            self.events.put(("error", f"Modbus gate: cannot reach swum-emu at {self.upstream}: {e}"))
            client.close()
            return
        self._connections.append(upstream)
        try:
            upstream.setsockopt(socket.IPPROTO_TCP, socket.TCP_NODELAY, 1)
            client.setsockopt(socket.IPPROTO_TCP, socket.TCP_NODELAY, 1)
            while not self._stop.is_set():
                request = read_frame(client)
                if request is None:
                    self.events.put(("closed", "the controller closed its Modbus connection"))
                    return
                writes = written_registers(request[7:])
                advance = writes.get(ADVANCE, 0)
                if advance and not self._wait_permit():
                    return
                if advance and self._peer_closed(client):  # held while its controller exited: void
                    self.events.put(("closed", "the controller closed its Modbus connection"))
                    return
                upstream.sendall(request)
                reply = read_frame(upstream)
                if reply is None:
                    self.events.put(("error", "swum-emu closed the connection: it exited, or the controller's "
                                              "request was malformed or incomplete (see swum-emu.log)"))
                    return
                if len(reply) > 7 and reply[7] & 0x80:
                    if advance and not self._opened.is_set():  # no tick ran: the bench is told
                        self.events.put(("refused", f"its write with an advance of {advance} ticks got exception "
                                                    f"{reply[8] if len(reply) > 8 else '?'}"))
                else:
                    self.holding.update(writes)
                    if advance and not self._opened.is_set():
                        self.on_cycle(dict(self.holding))
                client.sendall(reply)
        except BenchError as e:
            self.events.put(("error", str(e)))
        except OSError as e:
            if not self._stop.is_set():
                self.events.put(("error", f"Modbus gate: {e}"))
        finally:
            upstream.close()
            client.close()
