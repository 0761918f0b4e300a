#!/usr/bin/env python3
"""Writes tests/data/edid/*.bin: an EDID 1.4 base block per known Looking Glass model, for the
monitor-detection unit tests (src/output/monitor/tests.rs). Built, not recorded: the monitor
name is the model's serial prefix (presets/devices/*.toml, from LKG-Toolkit's device
templates) followed by a placeholder serial number, the native size is the preset's screen.
Re-run after changing a preset: python3 scripts/make-edid.py"""
import pathlib, re, struct

ROOT = pathlib.Path(__file__).resolve().parent.parent
OUT = ROOT / "tests/data/edid"


def pnp(code):
    a, b, c = (ord(ch) - 64 for ch in code)
    return struct.pack(">H", (a << 10) | (b << 5) | c)


def text_descriptor(tag, text):
    body = text.encode("ascii")[:13]
    if len(body) < 13:
        body += b"\n" + b" " * (12 - len(body))
    return bytes([0, 0, 0, tag, 0]) + body


def timing(w, h):
    if w > 4095 or h > 4095:  # needs a DisplayID extension: a dummy descriptor instead
        return bytes([0, 0, 0, 0x10, 0]) + bytes(13)
    hb, vb = 160, 60
    clock = (w + hb) * (h + vb) * 60 // 10000
    return struct.pack("<H", clock) + bytes([
        w & 0xFF, hb & 0xFF, ((w >> 8) << 4) | (hb >> 8),
        h & 0xFF, vb & 0xFF, ((h >> 8) << 4) | (vb >> 8),
        48, 32, (3 << 4) | 5, 0, 0, 0, 0, 0, 0, 0x1E])


def edid(name, w, h):
    b = bytearray(b"\x00\xff\xff\xff\xff\xff\xff\x00")
    b += pnp("LKG") + struct.pack("<HI", 1, 0) + bytes([1, 30, 1, 4])
    b += bytes([0xA5, 0, 0, 0x78, 0x3A])  # digital, size unknown, gamma 2.2, features
    b += bytes(10) + bytes(3) + bytes([1, 1] * 8)  # chromaticity, established, standard timings
    b += timing(w, h) + text_descriptor(0xFC, name) + text_descriptor(0xFF, "0000000")
    b += bytes([0, 0, 0, 0x10, 0]) + bytes(13)
    b += bytes([0])  # no extensions
    b.append((-sum(b)) & 0xFF)
    assert len(b) == 128
    return bytes(b)


for preset in sorted((ROOT / "presets/devices").glob("*.toml")):
    t = preset.read_text()
    prefix = re.search(r'^serial_prefix = "(.+)"', t, re.M).group(1)
    w = int(re.search(r"^screenW = (\d+)", t, re.M).group(1))
    h = int(re.search(r"^screenH = (\d+)", t, re.M).group(1))
    (OUT / f"{preset.stem}.bin").write_bytes(edid(f"{prefix}00123", w, h))
# An ordinary monitor, to tell apart.
(OUT / "ordinary-1920x1080.bin").write_bytes(edid("DELL U2415", 1920, 1080))
