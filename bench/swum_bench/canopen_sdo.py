"""The bench's SDO client (CiA 301 7.2.4): expedited and segmented upload and download on one
SDO channel, written from the standard (not from the slave's C++), over any `bus` with
send(can_id, data) and receive(timeout_s) -> (can_id, data) or None.

Every frame is 8 bytes: byte 0 the command specifier, bytes 1-2 the index (little-endian),
byte 3 the sub-index, bytes 4-7 data (CiA 301 7.2.4.3). A server's abort is raised as SdoAbort
with its code's CiA 301 name; a protocol error of the server's (a wrong toggle bit, an unknown
command specifier, a size that does not add up) or a timeout makes the client abort the
transfer itself, as CiA 301 says, and raise the same way."""
import struct
import time

from .emulator import BenchError

# CiA 301 Table 22: SDO abort codes
ABORT_NAMES = {
    0x05030000: "toggle bit not alternated",
    0x05040000: "SDO protocol timed out",
    0x05040001: "client/server command specifier not valid or unknown",
    0x05040002: "invalid block size",
    0x05040003: "invalid sequence number",
    0x05040004: "CRC error",
    0x05040005: "out of memory",
    0x06010000: "unsupported access to an object",
    0x06010001: "attempt to read a write only object",
    0x06010002: "attempt to write a read only object",
    0x06020000: "object does not exist in the object dictionary",
    0x06040041: "object cannot be mapped to the PDO",
    0x06040042: "the number and length of the objects to be mapped would exceed PDO length",
    0x06040043: "general parameter incompatibility reason",
    0x06040047: "general internal incompatibility in the device",
    0x06060000: "access failed due to a hardware error",
    0x06070010: "data type does not match, length of service parameter does not match",
    0x06070012: "data type does not match, length of service parameter too high",
    0x06070013: "data type does not match, length of service parameter too low",
    0x06090011: "sub-index does not exist",
    0x06090030: "invalid value for parameter",
    0x06090031: "value of parameter written too high",
    0x06090032: "value of parameter written too low",
    0x06090036: "maximum value is less than minimum value",
    0x060A0023: "resource not available: SDO connection",
    0x08000000: "general error",
    0x08000020: "data cannot be transferred or stored to the application",
    0x08000021: "data cannot be transferred or stored to the application because of local control",
    0x08000022: "data cannot be transferred or stored to the application because of the present device state",
    0x08000023: "object dictionary dynamic generation fails or no object dictionary is present",
    0x08000024: "no data available",
}
TOGGLE, TIMEOUT, COMMAND, OUT_OF_MEMORY = 0x05030000, 0x05040000, 0x05040001, 0x05040005
LENGTH_MISMATCH, GENERAL = 0x06070010, 0x08000000
# Command specifiers (bits 5-7 of byte 0), CiA 301 7.2.4.3
CCS_DOWNLOAD_SEGMENT, CCS_INITIATE_DOWNLOAD, CCS_INITIATE_UPLOAD, CCS_UPLOAD_SEGMENT, CS_ABORT = 0, 1, 2, 3, 4
SCS_UPLOAD_SEGMENT, SCS_DOWNLOAD_SEGMENT, SCS_INITIATE_UPLOAD, SCS_INITIATE_DOWNLOAD = 0, 1, 2, 3
MAX_UPLOAD_BYTES = 1 << 16  # more than any object of swum.eds: a server that never ends is refused


def abort_name(code):
    return ABORT_NAMES.get(code, "not a CiA 301 abort code")


class SdoAbort(BenchError):
    """A transfer that ended in an abort: code, its CiA 301 name, the object, and who aborted."""

    def __init__(self, code, index, sub, node, by_server):
        self.code, self.index, self.sub, self.node, self.by_server = code, index, sub, node, by_server
        who = f"node {node} aborted" if by_server else f"the bench aborted (to node {node})"
        super().__init__(f"SDO 0x{index:04X} sub {sub}: {who} with 0x{code:08X} ({abort_name(code)})")


def _frame(specifier, index, sub, data=b""):
    return bytes([specifier, index & 0xFF, index >> 8, sub]) + bytes(data).ljust(4, b"\0")


class SdoClient:
    def __init__(self, bus, node, request_id, response_id, timeout_s=1.0):
        self.bus, self.node = bus, node
        self.request_id, self.response_id = request_id, response_id
        self.timeout_s = timeout_s

    # ---- the exchanges ------------------------------------------------------------------------
    def _abort(self, index, sub, code):
        """The client's own abort (CiA 301 7.2.4.3.17): sent, then raised."""
        self.bus.send(self.request_id, _frame(CS_ABORT << 5, index, sub, struct.pack("<I", code)))
        return SdoAbort(code, index, sub, self.node, by_server=False)

    def _exchange(self, request, index, sub):
        """Sends a request and returns the server's 8-byte answer (its abort raised)."""
        self.bus.send(self.request_id, request)
        deadline = time.monotonic() + self.timeout_s
        while True:
            left = deadline - time.monotonic()
            got = self.bus.receive(left) if left > 0 else None
            if got is None:
                raise self._abort(index, sub, TIMEOUT)
            can_id, data = got
            if can_id != self.response_id:
                continue  # not this channel's: the link's filter normally keeps these away
            if len(data) != 8:  # CiA 301: an SDO frame is 8 bytes
                raise self._abort(index, sub, GENERAL)
            if data[0] >> 5 == CS_ABORT:
                raise SdoAbort(struct.unpack_from("<I", data, 4)[0], index, sub, self.node, by_server=True)
            return bytes(data)

    def _initiate(self, request, index, sub, expected_scs):
        answer = self._exchange(request, index, sub)
        if answer[0] >> 5 != expected_scs:
            raise self._abort(index, sub, COMMAND)
        if answer[1] | answer[2] << 8 != index or answer[3] != sub:  # the multiplexer must be ours
            raise self._abort(index, sub, GENERAL)
        return answer

    def upload(self, index, sub=0):
        """The object's bytes (expedited or segmented, as the server chooses)."""
        answer = self._initiate(_frame(CCS_INITIATE_UPLOAD << 5, index, sub), index, sub, SCS_INITIATE_UPLOAD)
        expedited, size_indicated = answer[0] & 0x02, answer[0] & 0x01
        if expedited:
            unused = (answer[0] >> 2) & 0x03 if size_indicated else 0
            return answer[4:8 - unused]
        size = struct.unpack_from("<I", answer, 4)[0] if size_indicated else None
        if size is not None and size > MAX_UPLOAD_BYTES:
            raise self._abort(index, sub, OUT_OF_MEMORY)
        data, toggle = b"", 0
        while True:
            segment = self._exchange(bytes([CCS_UPLOAD_SEGMENT << 5 | toggle << 4]) + bytes(7), index, sub)
            if segment[0] >> 5 != SCS_UPLOAD_SEGMENT:
                raise self._abort(index, sub, COMMAND)
            if (segment[0] >> 4) & 1 != toggle:
                raise self._abort(index, sub, TOGGLE)
            data += segment[1:8 - ((segment[0] >> 1) & 0x07)]
            if len(data) > (size if size is not None else MAX_UPLOAD_BYTES):
                raise self._abort(index, sub, LENGTH_MISMATCH if size is not None else OUT_OF_MEMORY)
            if segment[0] & 0x01:  # c: no more segments
                break
            toggle ^= 1
        if size is not None and len(data) != size:
            raise self._abort(index, sub, LENGTH_MISMATCH)
        return data

    def download(self, index, sub, data):
        """Writes the bytes: expedited up to 4, segmented above."""
        data = bytes(data)
        if 0 < len(data) <= 4:  # e = 1, s = 1, n = 4 - length (CiA 301 7.2.4.3.3)
            specifier = CCS_INITIATE_DOWNLOAD << 5 | (4 - len(data)) << 2 | 0x02 | 0x01
            self._initiate(_frame(specifier, index, sub, data), index, sub, SCS_INITIATE_DOWNLOAD)
            return
        self._initiate(_frame(CCS_INITIATE_DOWNLOAD << 5 | 0x01, index, sub, struct.pack("<I", len(data))),
                       index, sub, SCS_INITIATE_DOWNLOAD)
        toggle = 0
        for start in range(0, max(len(data), 1), 7):  # an empty value: one empty last segment
            chunk = data[start:start + 7]
            last = start + 7 >= len(data)
            specifier = CCS_DOWNLOAD_SEGMENT << 5 | toggle << 4 | (7 - len(chunk)) << 1 | int(last)
            answer = self._exchange(bytes([specifier]) + chunk.ljust(7, b"\0"), index, sub)
            if answer[0] >> 5 != SCS_DOWNLOAD_SEGMENT:
                raise self._abort(index, sub, COMMAND)
            if (answer[0] >> 4) & 1 != toggle:
                raise self._abort(index, sub, TOGGLE)
            toggle ^= 1

    # ---- typed, through the EDS ---------------------------------------------------------------
    def read(self, entry):
        """The value of an EDS entry (canopen_eds.Entry), decoded by its type."""
        data = self.upload(entry.index, entry.sub)
        try:
            return entry.decode(data)
        except ValueError as e:
            raise BenchError(f"SDO upload from node {self.node}: {e}") from None

    def write(self, entry, value):
        """Writes a value to an EDS entry, encoded by its type (a value it cannot hold is a
        ValueError before anything is sent)."""
        self.download(entry.index, entry.sub, entry.encode(value))
