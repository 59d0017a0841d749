#!/usr/bin/python3
"""Generates the split constants of plume's argument reductions (exact, mpmath at 400 digits).

  /usr/bin/python3 tools/gen_constants.py
Output is pasted into include/plume/numerics/detail/coefficients.hpp and
numerics/trig_reduction.cpp; rerunning it must reproduce them bit for bit.
"""
import mpmath as mp

mp.mp.dps = 400


def chop(v, bits):
    """v rounded to a binary number with `bits` significant bits (round to nearest)."""
    if v == 0:
        return mp.mpf(0)
    e = mp.floor(mp.log(abs(v), 2)) + 1 - bits
    return mp.nint(v / mp.mpf(2) ** e) * mp.mpf(2) ** e


def split(v, part_bits, parts, last_bits):
    out = []
    rest = v
    for _ in range(parts):
        p = chop(rest, part_bits)
        out.append(p)
        rest -= p
    out.append(chop(rest, last_bits))
    return out


def lit(v, kind):
    if kind == "f":
        return mp.nstr(v, 12, strip_zeros=False, min_fixed=1, max_fixed=0) + "f"
    return float(v).hex()


def emit(name, vals, kind):
    print(f"// {name}")
    for i, v in enumerate(vals):
        print(f"  {lit(v, kind)},   // {mp.nstr(v, 25)}")


pio2 = mp.pi / 2
emit("pi/2 in 4 x 11-bit parts + 24-bit tail (float Cody-Waite, exact q*part for |q| < 2^13)",
     split(pio2, 11, 4, 24), "f")
emit("pi/2 in 4 x 26-bit parts + 53-bit tail (double Cody-Waite, exact q*part for |q| < 2^27)",
     split(pio2, 26, 4, 53), "d")
ln2 = mp.log(2)
emit("ln2 as 16-bit hi + 24-bit lo (float; n*hi exact for |n| < 2^8)", split(ln2, 16, 1, 24), "f")
emit("ln2 as 42-bit hi + 53-bit lo (double; n*hi exact for |n| < 2^11)", split(ln2, 42, 1, 53), "d")
il2 = 1 / ln2
emit("1/ln2 as 12-bit hi + 24-bit lo (float)", split(il2, 12, 1, 24), "f")
emit("1/ln2 as 21-bit hi + 53-bit lo (double)", split(il2, 21, 1, 53), "d")
for kind, bits in (("f", 24), ("d", 53)):
    for nm, v in (("pi/2", pio2), ("pi/4", mp.pi / 4), ("pi", mp.pi), ("1/ln2 (log2 e)", il2), ("2/3", mp.mpf(2) / 3)):
        emit(f"{nm} hi + lo ({'float' if kind == 'f' else 'double'})", split(v, bits, 1, bits), kind)

# 2/pi, bits b1 b2 ... after the binary point, preceded by 64 zero bits (see trig_reduction.cpp)
nbits = 64 * 22
v = mp.mpf(2) / mp.pi
words = []
acc = mp.floor(v * mp.mpf(2) ** (nbits - 64))  # drop the 64 leading zero bits
acc = int(acc)
total = nbits
full = acc  # integer holding bits 1 .. nbits-64
bits = "0" * 64 + bin(full)[2:].zfill(nbits - 64)
print("// 2/pi: 64 zero bits, then its binary digits after the point")
for i in range(0, nbits, 64):
    print(f"    0x{int(bits[i:i + 64], 2):016x}ULL,")
