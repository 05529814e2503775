#!/usr/bin/env python3
"""Independent check of the spec against the golden vectors.

Implements a receiver from PROTOCOL.md alone: it reads the catalogue table
and the layout signatures out of PROTOCOL.md (recomputing every CRC seed),
then decodes every vector in golden.txt with its own COBS, CRC and
signature-driven field decoder, and compares with the expected events.
Shares no code with the C++ library, so agreement means the document is
enough to build a compatible peer.

usage: check_vectors.py PROTOCOL.md golden.txt [model_file.txt [corpus_dir]]

With a golden model file it also checks that file against the model file
layout of PROTOCOL.md 9.4: sizes, layer chain, parameter count and CRC-32;
and the example rig file beside it (rig_hash_example.toml) against the
canonical content and rig_hash of PROTOCOL.md 7.
With the fuzzer's seed corpus it checks that every vector is there, as its
wire bytes after one chunk-size byte (PROTOCOL.md 14), so the fuzzer starts
from the frames of today's layouts.
"""
import math
import re
import struct
import sys


def crc16(data, crc=0xFFFF):
    for b in data:
        crc ^= b << 8
        for _ in range(8):
            crc = ((crc << 1) ^ 0x1021) if crc & 0x8000 else (crc << 1)
            crc &= 0xFFFF
    return crc


def read_spec(path):
    text = open(path, encoding="utf-8").read()
    table = {}
    row = re.compile(r"^\| 0x([0-9A-F]{2}) \| ([A-Z_]+) \| (?:C→F|F→C) \| 0x([0-9A-F]{2}) \| "
                     r"([^|]+)\|", re.M)
    for m in row.finditer(text):
        rule = m.group(4).strip()
        if "computed" in rule:
            r = re.match(r"(\d+)\.\.(\d+), computed$", rule)
            lo, hi, step = int(r.group(1)), int(r.group(2)), 0
        else:
            r = re.match(r"(\d+)(?:\.\.(\d+), (\d+))?$", rule)
            lo = int(r.group(1))
            hi = int(r.group(2) or lo)
            step = int(r.group(3) or 1)
        table[int(m.group(1), 16)] = dict(name=m.group(2), seed=int(m.group(3), 16),
                                          lo=lo, hi=hi, step=step)
    block = text.split("Layout signatures", 1)[1].split("```", 2)[1]
    sigs = {}
    for line in block.strip().splitlines():
        name, fields = line.split(":", 1)
        sigs[name] = (line, [f.split(" ", 1) for f in fields.split(",")] if fields else [])
    for t, info in table.items():
        line, fields = sigs[info["name"]]
        c = crc16(line.encode())
        seed = (c & 0xFF) ^ (c >> 8)
        if seed != info["seed"]:
            sys.exit(f"{info['name']}: seed in table 0x{info['seed']:02X}, signature gives 0x{seed:02X}")
        info["fields"] = fields
    if len(table) != len(sigs):
        sys.exit("catalogue table and signature list differ")
    return table


def cobs_decode(enc):
    """Returns (bytes decoded so far, whether the COBS blocks were complete)."""
    out = bytearray()
    i = 0
    while i < len(enc):
        code = enc[i]
        i += 1
        out += enc[i:i + code - 1]
        if i + code - 1 > len(enc):
            return bytes(out), False
        i += code - 1
        if code != 0xFF and i < len(enc):
            out.append(0)
    return bytes(out), True


def fmt_float(x_bits):
    x = struct.unpack("<f", struct.pack("<I", x_bits))[0]
    return ("%.9g" % x) if math.isfinite(x) else "0x%08x" % x_bits


def fmt_word(w, as_float):
    if not as_float:
        return str(w)
    exp = (w >> 23) & 0xFF
    if (w & 0x7FFFFFFF) == 0 or exp not in (0, 0xFF):
        return fmt_float(w)
    return "0x%08x" % w


def quote(raw):
    s = '"'
    for b in raw:
        c = chr(b)
        if c in '"\\':
            s += "\\" + c
        elif b < 0x20 or b >= 0x7F:
            s += "\\x%02x" % b
        else:
            s += c
    return s + '"'


TELEMETRY_BITS = {"step": 0x01, "time_us": 0x02, "y_ref": 0x04, "y_hat": 0x08,
                  "y_true": 0x10, "u": 0x20, "cost": 0x40, "iterations": 0x80,
                  "compute_ticks": 0x80}


def decode_fields(name, fields, p):
    out = []
    pos = 0
    vals = {}

    def take(n):
        nonlocal pos
        b = p[pos:pos + n]
        if len(b) != n:
            raise ValueError("short")
        pos += n
        return b

    for ftype, fname in fields:
        if ftype.startswith("?"):
            if not vals["mask"] & TELEMETRY_BITS[fname]:
                continue
            ftype = ftype[1:]
        if ftype == "u4":
            if fname == "n":
                b = take(1)[0]
                vals["n"], vals["m"] = b >> 4, b & 15
            out.append(f"{fname}={vals[fname]}")
            continue
        m = re.match(r"(u8|u16|u32|f32|char)(?:\[(\w*)\])?$", ftype)
        base, count = m.group(1), m.group(2)
        size = {"u8": 1, "u16": 2, "u32": 4, "f32": 4, "char": 1}[base]
        if count is None:
            raw = take(size)
            v = int.from_bytes(raw, "little")
            vals[fname] = v
            out.append(f"{fname}={fmt_float(v) if base == 'f32' else v}")
            continue
        if count == "":
            n = (len(p) - pos) // size
        elif count.isdigit():
            n = int(count)
        else:
            n = vals[count]
        raw = take(n * size)
        if base == "char":
            if count == "":
                raw = raw.replace(b"\0", b"?")
            else:
                raw = raw.split(b"\0", 1)[0]
            out.append(f"{fname}={quote(raw)}")
        elif base == "u8":
            out.append(f"{fname}={raw.hex()}")
        else:
            words = [int.from_bytes(raw[i:i + 4], "little") for i in range(0, len(raw), 4)]
            if base == "f32":
                s = ",".join(fmt_float(w) for w in words)
            else:  # PARAM words: PARAM_SET has no type field and prints as f32
                s = ",".join(fmt_word(w, vals.get("type", 0) == 0) for w in words)
            out.append(f"{fname}={s}")
    if pos != len(p):
        raise ValueError("trailing")
    return out


def check_shapes(fields):
    """RIG_INFO's shape list as section 7 lays it out: entries of L >= 1 and
    L layers of kind 1|2 and u16 units >= 1 that fill the tail exactly; empty
    with accept 1; the last layer's units are n."""
    vals = dict(f.split("=", 1) for f in fields)
    raw = bytes.fromhex(vals["shapes"])
    if vals["accept"] == "1":
        return None if not raw else "accept 1 with a shape list"
    pos = 0
    while pos < len(raw):
        layers = raw[pos]
        end = pos + 1 + 3 * layers
        if layers == 0 or end > len(raw):
            return f"shape entry at byte {pos} malformed"
        units = []
        for at in range(pos + 1, end, 3):
            if raw[at] not in (1, 2) or int.from_bytes(raw[at + 1:at + 3], "little") == 0:
                return f"layer at byte {at}: unknown kind or no units"
            units.append(int.from_bytes(raw[at + 1:at + 3], "little"))
        if units[-1] != int(vals["n"]):
            return f"shape at byte {pos} ends in {units[-1]} units, n is {vals['n']}"
        pos = end
    return None


def telemetry_len(p):
    mask, n, m = p[2], p[3] >> 4, p[3] & 15
    size = 4
    for bit, sz in ((1, 4), (2, 4), (4, 4 * n), (8, 4 * n), (16, 4 * n), (32, 4 * m),
                    (64, 4), (128, 5)):
        if mask & bit:
            size += sz
    return size


def ident_sample_len(p):
    if len(p) < 5:
        return -1
    return 13 + 4 * (p[2] + p[3] + p[4])


def computed_len(name, p):
    return ident_sample_len(p) if name == "IDENT_SAMPLE" else telemetry_len(p)


def receive(frame, table):
    raw, complete = cobs_decode(frame)
    if len(raw) > 253:
        return "error oversize"
    if not complete:
        return "error cobs_error"
    if not raw:
        return "error truncated"
    if raw[0] != 1:
        return "error wrong_version"
    if len(raw) < 7 or len(raw) < 7 + raw[4]:
        return "error truncated"
    if len(raw) > 7 + raw[4]:
        return "error length_mismatch"
    info = table.get(raw[1])
    if info is None:
        return "error unknown_type"
    body = raw[:5 + raw[4]]
    if crc16(bytes([info["seed"]]), crc16(body)) != int.from_bytes(raw[-2:], "little"):
        return "error bad_crc"
    p = body[5:]
    lo, hi, step = info["lo"], info["hi"], info["step"]
    if not lo <= len(p) <= hi or (step and (len(p) - lo) % step) or \
            (step == 0 and len(p) != computed_len(info["name"], p)):
        return "error bad_length"
    head = f"frame {info['name']} seq={raw[2]} flags={raw[3]}"
    return " ".join([head] + decode_fields(info["name"], info["fields"], p))


def crc32(data):
    crc = 0xFFFFFFFF
    for b in data:
        crc ^= b
        for _ in range(8):
            crc = (crc >> 1) ^ (0xEDB88320 if crc & 1 else 0)
    return crc ^ 0xFFFFFFFF


def check_model(path):
    """The golden model file read by the layout table of PROTOCOL.md 9.4."""
    size = crc = None
    data = bytearray()
    for line in open(path, encoding="utf-8"):
        if line.startswith("size:"):
            size = int(line.split(":", 1)[1])
        elif line.startswith("crc32:"):
            crc = int(line.split(":", 1)[1], 16)
        elif line.startswith("file:"):
            data += bytes(int(x, 16) for x in line.split(":", 1)[1].split())
    problems = []
    if len(data) != size:
        problems.append(f"{len(data)} bytes, size says {size}")
    if data[0:4] != b"NLSM" or data[4] != 1:
        problems.append("magic or format")
    m, n, w, nd, dd, layers = data[6:12]
    (params,) = struct.unpack_from("<I", data, 12)
    if any(data[17:24]):
        problems.append("reserved bytes not 0")
    if len(data) != 24 + 8 * layers + 4 * params + 4:
        problems.append("size is not 24 + 8L + 4P + 4")
    p = nd * m + dd * n + w
    width, count = p, 2 * p + 2 * n
    for i in range(layers):
        kind, act, rec_act, reset_after, lin, lout = struct.unpack_from("<4BHH", data, 24 + 8 * i)
        if lin != width or act > 4 or rec_act > 4 or kind not in (1, 2):
            problems.append(f"layer {i}")
        count += lin * lout + lout if kind == 1 else 3 * lout * (lin + lout) + (6 if reset_after else 3) * lout
        width = lout
    if width != n or count != params:
        problems.append(f"layer chain ends at {width} (n {n}), {count} parameters (header {params})")
    values = struct.unpack_from(f"<{params}f", data, 24 + 8 * layers)
    if not all(math.isfinite(v) for v in values):
        problems.append("a parameter is not finite")
    (trailer,) = struct.unpack_from("<I", data, len(data) - 4)
    if crc32(bytes(data[:-4])) != trailer or trailer != crc:
        problems.append(f"CRC-32 0x{crc32(bytes(data[:-4])):08x}, trailer 0x{trailer:08x}, crc32 line 0x{crc:08x}")
    for p_ in problems:
        print(f"MODEL {path}: {p_}")
    print(f"model file: {len(data)} bytes, {layers} layer(s), {params} parameters, {len(problems)} problems")
    return len(problems)


def check_rig_hash(path):
    """rig_hash of PROTOCOL.md 7 (canonical content of a rig file), recomputed
    for the example rig file, which names its own hash on a comment line."""
    data = open(path, "rb").read()
    canonical = b""
    for line in data.replace(b"\r", b"").split(b"\n"):
        line = line.rstrip(b" \t")
        if line.strip(b" \t") and not line.lstrip(b" \t").startswith(b"#"):
            canonical += line + b"\n"
    named = re.search(rb"^# rig_hash 0x([0-9a-f]{8})\r?$", data, re.M)
    got = crc32(canonical)
    ok = named is not None and int(named.group(1), 16) == got
    print(f"rig hash: {len(canonical)} canonical bytes of {len(data)}, 0x{got:08x}"
          + ("" if ok else f", the file names {named.group(1).decode() if named else 'none'}"))
    return 0 if ok else 1


def main():
    table = read_spec(sys.argv[1])
    vectors = []
    for line in open(sys.argv[2], encoding="utf-8"):
        line = line.rstrip("\n")
        if line.startswith("vector:"):
            vectors.append([line.split(":", 1)[1].strip(), bytearray(), []])
        elif line.startswith("wire:"):
            vectors[-1][1] += bytes(int(x, 16) for x in line.split(":", 1)[1].split())
        elif line.startswith("expect:"):
            vectors[-1][2].append(line.split(":", 1)[1].strip())
    failures = 0
    for name, wire, expect in vectors:
        events = [receive(bytes(f), table) for f in bytes(wire).split(b"\0")[:-1] if f]
        for e in events:
            if e.startswith("frame RIG_INFO "):
                bad = check_shapes(e.split()[4:])
                if bad:
                    events.append("shape list: " + bad)
        if events != expect:
            failures += 1
            print(f"MISMATCH {name}\n  got:  {events}\n  want: {expect}")
    print(f"{len(vectors)} vectors, {len(table)} message types, {failures} mismatches")
    if len(sys.argv) > 3:
        failures += check_model(sys.argv[3])
        import os
        failures += check_rig_hash(os.path.join(os.path.dirname(sys.argv[3]), "rig_hash_example.toml"))
    if len(sys.argv) > 4:
        import os
        stale = [name for name, wire, _ in vectors
                 if not os.path.exists(os.path.join(sys.argv[4], name)) or
                 open(os.path.join(sys.argv[4], name), "rb").read()[1:] != bytes(wire)]
        print(f"seed corpus: {len(vectors) - len(stale)} of {len(vectors)} vectors current"
              + (f"; stale or missing: {' '.join(stale)}" if stale else ""))
        failures += len(stale)
    return 1 if failures else 0


if __name__ == "__main__":
    sys.exit(main())
