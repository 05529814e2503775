"""The few nlsoft wire-protocol messages the M4 tools need (protocol/PROTOCOL.md):
COBS framing, CRC-16/CCITT-FALSE with the per-type seed, and a blocking
request/reply peer over a tty file descriptor. Standard library only."""
import os
import random
import re
import select
import struct
import termios
import time
import tty

# Type ids (PROTOCOL.md section 6).
PING, INFO_GET, PARAM_GET, PARAM_SET = 0x01, 0x02, 0x04, 0x05
RUN_START, RUN_STOP, TELEMETRY_CONFIG, STATUS_GET = 0x0B, 0x0C, 0x0E, 0x0F
ACK, NACK, PONG, INFO, PARAM_VALUE, STATUS, TELEMETRY, LOG = 0x40, 0x41, 0x42, 0x43, 0x45, 0x47, 0x48, 0x49
INFO_EX = 0x4A
SPEC = os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "..", "protocol", "PROTOCOL.md")


def read_seeds(path=SPEC):
    """The CRC seed of every type, computed from the layout signatures in the
    spec as check_vectors.py does, so a layout change there cannot leave a
    stale copy here. The catalogue table gives each name its type id."""
    text = open(path, encoding="utf-8").read()
    ids = {m.group(2): int(m.group(1), 16)
           for m in re.finditer(r"^\| 0x([0-9A-F]{2}) \| ([A-Z_]+) \|", text, re.M)}
    block = text.split("Layout signatures", 1)[1].split("```", 2)[1]
    seeds = {}
    for line in block.strip().splitlines():
        c = crc16(line.encode())
        seeds[ids[line.split(":", 1)[0]]] = (c & 0xFF) ^ (c >> 8)
    return seeds


REPLY_FLAG = 0x01

# TELEMETRY mask bits (PROTOCOL.md section 7)
T_STEP, T_TIME, T_YREF, T_YHAT, T_YTRUE, T_U, T_COST, T_SOLVER = 1, 2, 4, 8, 16, 32, 64, 128

# shared/params.hpp ParamId
PARAM_MODE = 13


def crc16(data, crc=0xFFFF):
    for b in data:
        crc ^= b << 8
        for _ in range(8):
            crc = ((crc << 1) ^ 0x1021) & 0xFFFF if crc & 0x8000 else (crc << 1) & 0xFFFF
    return crc


SEED = read_seeds()


def cobs_encode(raw):
    out, block = bytearray(), bytearray()
    for b in raw:
        if b == 0:
            out += bytes([len(block) + 1]) + block
            block = bytearray()
        else:
            block.append(b)
            if len(block) == 254:
                out += b"\xff" + block
                block = bytearray()
    out += bytes([len(block) + 1]) + block
    return bytes(out)


def cobs_decode(enc):
    out, i = bytearray(), 0
    while i < len(enc):
        code = enc[i]
        if code == 0 or i + code > len(enc):
            return None  # a block that promises more bytes than arrived
        out += enc[i + 1:i + code]
        i += code
        if code < 255 and i < len(enc):
            out.append(0)
    return bytes(out)


def encode(msg_type, seq, payload=b"", flags=0):
    raw = bytes([1, msg_type, seq, flags, len(payload)]) + payload
    crc = crc16(bytes([SEED[msg_type]]), crc16(raw))
    return b"\x00" + cobs_encode(raw + struct.pack("<H", crc)) + b"\x00"


def decode(wire):
    """(type, seq, flags, payload) of one wire frame without its delimiter, or None."""
    raw = cobs_decode(wire)
    if raw is None or len(raw) < 7 or raw[0] != 1 or len(raw) != 7 + raw[4] or raw[1] not in SEED:
        return None
    if crc16(bytes([SEED[raw[1]]]), crc16(raw[:-2])) != struct.unpack("<H", raw[-2:])[0]:
        return None
    return raw[1], raw[2], raw[3], raw[5:-2]


def parse_telemetry(p):
    tseq, mask, dims = struct.unpack_from("<HBB", p)
    n, m = dims >> 4, dims & 15
    t, off = {"tseq": tseq, "mask": mask}, 4
    if mask & T_STEP:
        t["step"] = struct.unpack_from("<I", p, off)[0]; off += 4
    if mask & T_TIME:
        t["time_us"] = struct.unpack_from("<I", p, off)[0]; off += 4
    for bit, name, count in ((T_YREF, "y_ref", n), (T_YHAT, "y_hat", n), (T_YTRUE, "y_true", n), (T_U, "u", m)):
        if mask & bit:
            t[name] = list(struct.unpack_from("<%df" % count, p, off)); off += 4 * count
    if mask & T_COST:
        t["cost"] = struct.unpack_from("<f", p, off)[0]; off += 4
    if mask & T_SOLVER:
        t["iterations"], t["compute_ticks"] = struct.unpack_from("<BI", p, off); off += 5
    return t


def parse_info(p, msg_type=INFO_EX):
    """INFO_EX (protocol 1.1) or INFO (1.0): the same first 28 bytes."""
    f = struct.unpack_from("<12B4I", p)
    keys = ("protocol_version", "platform", "m", "n", "w", "nd", "dd", "max_n", "max_nc", "fw_major",
            "fw_minor", "fw_patch", "loop_rate_hz", "model_hash", "param_hash", "capabilities")
    d = dict(zip(keys, f))
    if msg_type == INFO_EX:
        d["table_max"], d["model_max"], d["protocol_minor"] = struct.unpack_from("<IIB", p, 28)
        d["firmware"] = p[37:].decode("ascii", "replace")
    else:
        d["table_max"] = d["model_max"] = d["protocol_minor"] = 0
        d["firmware"] = p[28:].decode("ascii", "replace")
    return d


def parse_status(p):
    keys = ("uptime_ms", "run_id", "step", "run_state", "watchdog", "telemetry_mask", "ref_id", "frames_in",
            "crc_errors", "frame_errors", "tx_dropped", "loop_overruns", "compute_min", "compute_mean",
            "compute_max", "tick_rate_hz")
    return dict(zip(keys, struct.unpack("<3I4B9I", p)))


class Peer:
    """The console side over a tty: requests with retries, unsolicited frames queued."""

    def __init__(self, path):
        self.fd = os.open(path, os.O_RDWR | os.O_NOCTTY | os.O_NONBLOCK)
        tty.setraw(self.fd, termios.TCSANOW)
        # A random first seq (PROTOCOL.md section 3): a restarted tool must not
        # meet the firmware's memory of its previous last request.
        self.seq, self.buf, self.unsolicited = random.randrange(256), bytearray(), []

    def close(self):
        os.close(self.fd)

    def _send(self, wire):
        while wire:
            select.select([], [self.fd], [], 0.1)
            try:
                wire = wire[os.write(self.fd, wire):]
            except BlockingIOError:
                pass

    def frames(self, until):
        """Yields decoded frames until the deadline."""
        while True:
            while b"\x00" in self.buf:
                i = self.buf.index(b"\x00")
                chunk, self.buf = bytes(self.buf[:i]), self.buf[i + 1:]
                if chunk:
                    f = decode(chunk)
                    if f:
                        yield f
            left = until - time.monotonic()
            if left <= 0:
                return
            if select.select([self.fd], [], [], min(left, 0.05))[0]:
                try:
                    self.buf += os.read(self.fd, 4096)
                except (BlockingIOError, OSError):
                    pass

    def request(self, msg_type, payload=b"", timeout=1.0, retries=5):
        """Sends a request (the same seq on every retry: PROTOCOL.md section 10)."""
        seq = self.seq
        self.seq = (self.seq + 1) & 0xFF
        for _ in range(retries):
            self._send(encode(msg_type, seq, payload))
            for f_type, f_seq, flags, p in self.frames(time.monotonic() + timeout):
                if flags & REPLY_FLAG and f_seq == seq:
                    return f_type, p
                self.unsolicited.append((f_type, p))
        return None

    def set_param(self, pid, words):
        return self.request(PARAM_SET, struct.pack("<H%dI" % len(words), pid, *words))


def self_test(golden):
    """Decodes every golden vector that is one good frame with these seeds and
    re-encodes it byte for byte: proof that the seeds read from the spec are
    the ones the library uses."""
    checked, types, blocks = 0, set(), []
    for line in open(golden, encoding="utf-8"):
        if line.startswith("vector:"):
            blocks.append([bytearray(), []])
        elif line.startswith("wire:"):
            blocks[-1][0] += bytes(int(x, 16) for x in line.split(":", 1)[1].split())
        elif line.startswith("expect:"):
            blocks[-1][1].append(line.split(":", 1)[1].strip())
    for wire, expect in blocks:
        if len(expect) != 1 or not expect[0].startswith("frame ") or wire.count(0) != 1 or wire[-1] != 0:
            continue
        f = decode(bytes(wire[:-1]))
        if f is None:
            raise SystemExit("golden frame not decoded: %s" % expect[0])
        f_type, f_seq, flags, payload = f
        if encode(f_type, f_seq, payload, flags)[1:] != bytes(wire):  # without the leading 0x00
            raise SystemExit("golden frame not re-encoded byte for byte: %s" % expect[0])
        checked += 1
        types.add(f_type)
    missing = sorted(set(SEED) - types)
    print("%d golden frames decoded and re-encoded, %d seeds from the spec, types without a frame: %s"
          % (checked, len(SEED), " ".join("0x%02X" % t for t in missing) or "none"))
    return 0 if checked and not missing else 1


if __name__ == "__main__":
    import sys
    sys.exit(self_test(sys.argv[1]))
