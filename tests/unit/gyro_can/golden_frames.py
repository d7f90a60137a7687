# Independent golden-frame generator for HRG CAN protocol v2: CRC-8 SAE J1850 (poly 0x1D, init
# 0xFF, xorout 0xFF) over id (2 bytes LE) + payload, appended as the last byte.
def crc8(data):
    crc = 0xFF
    for b in data:
        crc ^= b
        for _ in range(8):
            crc = ((crc << 1) ^ 0x1D) & 0xFF if crc & 0x80 else (crc << 1) & 0xFF
    return crc ^ 0xFF
assert crc8(b"123456789") == 0x4B
def frame(id_, payload, fd=False):
    body = bytes(payload)
    c = crc8(bytes([id_ & 0xFF, id_ >> 8]) + body)
    sep = "##1" if fd else "#"
    return "%03X%s%s" % (id_, sep, (body + bytes([c])).hex().upper())
def le(v, n): return list((v & ((1 << 8*n) - 1)).to_bytes(n, "little"))
# Configure node 0 and node 5
print("cfg0", frame(0x040, [0x07] + le(1000,2) + [0, 10, 0, 0]))
print("cfg0fd", frame(0x040, [0x21] + le(5000,2) + [1, 0, 0, 0]))
print("cfg5", frame(0x045, [0x07] + le(1000,2) + [0, 10, 0, 0]))
print("exc3", frame(0x053, [0x08] + le(10000,2) + le(-4000,2) + le(4488,2)))
print("exc0", frame(0x050, [0x08] + le(10000,2) + le(-4000,2) + le(4488,2)))
print("rel0", frame(0x060, [0x09]))
print("stop15", frame(0x02F, [0x0A]))
print("stop0", frame(0x020, [0x0A]))
print("sreq0", frame(0x070, [0x0B]))
print("ack_rel5", frame(0x085, [0x42, 0x09, 0, 4] + le(0,3)))
print("ack_cfg0", frame(0x080, [0x40, 0x07, 0, 1] + le(1000,3)))
print("ack_exc0", frame(0x080, [0x41, 0x08, 1, 0] + le(0,3)))
st0 = 3 | 0x10 | 0x20
print("status0", frame(0x090, [st0, 0] + le(5123456,3) + le(2537,2)))
print("status7", frame(0x097, [6, 0x05] + le(4999000,3) + le(-1250,2)))
def q(y): return round(y * 4194304)
print("halfA0", frame(0x100, [0x2A] + le(q(1.0),3) + le(q(-0.5),3)))
print("halfB0", frame(0x110, [0x2A] + le(q(0.25),3) + le(-1,3)))
print("halfA2", frame(0x102, [0x2A] + le(q(1.0),3) + le(q(-0.5),3)))
print("sat0", frame(0x100, [0xFF] + le((1<<23)-1,3) + le(-(1<<23),3)))
print("ref0", frame(0x130, le(0x1234,2) + le(0x28BE60DC,4) + [0]))
print("refF", frame(0x13F, le(0xFFFF,2) + le(0xEBA0CF92,4) + [0]))
print("ref0b", frame(0x130, le(0xFFFF,2) + le(0xEBA0CF92,4) + [0]))
def pattern(seq, count):
    ys = []
    for s in range(5):
        for c in range(4):
            ys.append((s*4+c+1)*1000*(-1 if c % 2 == 1 else 1) if s < count else 0)
    p = le(seq,2) + [count]
    for y in ys: p += le(y,3)
    return p
print("fd_full0", frame(0x120, pattern(0x1234,5), fd=True))
print("fd_part9", frame(0x129, pattern(0xFFFF,2), fd=True))
# Configure in the whole-angle run mode (byte 5), and an operating sample: seq, the angle output
# int32 of 2^-21 rad (-3 rad), the wave angle uint16 of pi/2^16 (pi/2).
print("cfg0wa", frame(0x040, [0x10] + le(1000,2) + [0, 10, 1, 0]))
print("op4", frame(0x144, [0x2A] + le(-3 * 2**21, 4) + le(32768, 2)))
# The operating loops' report of sample 0x2A, node 3, in two frames of seq + two int24: A (0x15n)
# the energy error (S - S*)/S* = 2e-4 in 2^-28 and K/S = -3e-7 in 2^-34; B (0x16n) the efforts
# g = 1e-3 1/s and q = -1.5e-4 rad/s in 2^-26. And an A whose values saturate at the int24 bounds.
print("loopsA3", frame(0x153, [0x2A] + le(round(2e-4 * 2**28), 3) + le(round(-3e-7 * 2**34), 3)))
print("loopsB3", frame(0x163, [0x2A] + le(round(1e-3 * 2**26), 3) + le(round(-1.5e-4 * 2**26), 3)))
print("loopsA0sat", frame(0x150, [0xFF] + le((1 << 23) - 1, 3) + le(-(1 << 23), 3)))
# Parameter (0x03n): token, op, word index, value u16, two reserved zero bytes.
print("par_begin0", frame(0x030, [0x0C, 1, 0] + le(48,2) + [0, 0]))
print("par_write6", frame(0x036, [0x0D, 2, 17] + le(0xBEEF,2) + [0, 0]))
print("par_commit0", frame(0x030, [0x0E, 5, 0] + le(0,2) + [0, 0]))
print("ack_par_read0", frame(0x080, [0x45, 0x0F, 0, 1] + le((17 << 16) | 0xBEEF,3)))
# The parameter block: layout 1, count 11, eleven binary64 little-endian as 16-bit words, CRC-32
# (zlib's, IEEE 802.3) of the 92 bytes before it, low word first.
import struct, zlib
values = [-1e-3, 0.29, 3e-5, -2e-5, 2e-4, -1e-4, 0.01, 0.002, -0.003, 0.004, 1.5e-6]
body = struct.pack("<HH", 1, 11) + b"".join(struct.pack("<d", v) for v in values)
crc = zlib.crc32(body)
print("block_crc %08X" % crc)
words = struct.unpack("<46H", body) + (crc & 0xFFFF, crc >> 16)
print("block_words", " ".join("%04X" % w for w in words))
