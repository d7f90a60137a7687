# Independent reference: classic CAN frame bit stuffing (ISO 11898-1), written from the standard.
def crc15(bits):
    crc = 0
    for b in bits:
        nxt = b ^ ((crc >> 14) & 1)
        crc = (crc << 1) & 0x7FFF
        if nxt: crc ^= 0x4599
    return crc
def frame_bits(id_, data, ext=False, rtr=False):
    bits = [0]
    def put(v, w):
        for i in range(w-1, -1, -1): bits.append((v >> i) & 1)
    if ext:
        put(id_ >> 18, 11); put(1,1); put(1,1); put(id_ & 0x3FFFF, 18); put(1 if rtr else 0,1); put(0,2)
    else:
        put(id_, 11); put(1 if rtr else 0, 1); put(0, 2)
    put(len(data), 4)
    if not rtr:
        for d in data: put(d, 8)
    c = crc15(bits); put(c, 15)
    return bits
def stuff(bits):
    out = []; cnt = 0; prev = None; n = 0
    for b in bits:
        out.append(b)
        if b == prev: cnt += 1
        else: prev = b; cnt = 1
        if cnt == 5:
            n += 1; s = 1 - b; out.append(s); prev = s; cnt = 1
    return n
for name, id_, data, ext in [("zeros", 0x000, [0]*8, False), ("ones", 0x7FF, [0xFF]*8, False),
                             ("sample", 0x100, [0x2A,0,0,0x40,0,0,0xE0,0x02], False),
                             ("ext", 0x1ABCDEF0, [0xDE,0xAD,0xBE,0xEF], True), ("empty", 0x123, [], False)]:
    print(name, stuff(frame_bits(id_, data, ext)))
