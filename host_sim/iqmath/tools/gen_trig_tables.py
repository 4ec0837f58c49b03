#!/usr/bin/env python3
"""Print the constant tables of iqmath_trig.c (needs mpmath; 50 digits).

  SIN_Q31[k]      = round(sin(k * pi/128) * 2^31),          k = 0..64
  ATAN_REV_Q34[k] = round(atan(k/64) / (2 pi) * 2^34),      k = 0..64
and the scalar constants.
"""
import mpmath as mp

mp.mp.dps = 50


def rnd(x):
    return int(mp.nint(x))


def table(name, ctype, vals):
    print("static const %s %s[%d] = {" % (ctype, name, len(vals)))
    for i in range(0, len(vals), 6):
        print("    " + ", ".join("%du" % v if ctype.startswith("uint") else "%d" % v
                                 for v in vals[i:i + 6]) + ",")
    print("};")


table("SIN_Q31", "uint32_t", [rnd(mp.sin(k * mp.pi / 128) * 2**31) for k in range(65)])
table("ATAN_REV_Q34", "uint32_t",
      [rnd(mp.atan(mp.mpf(k) / 64) / (2 * mp.pi) * 2**34) for k in range(65)])
k64 = rnd(2**65 / (2 * mp.pi))
print("K64 = 2^65/(2 pi): hi %d lo %du" % (k64 >> 32, k64 & 0xFFFFFFFF))
print("TWO_PI_Q28 %d" % rnd(2 * mp.pi * 2**28))
print("TWO_PI_Q29 %du" % rnd(2 * mp.pi * 2**29))
print("INV_2PI_Q34 %du" % rnd(2**34 / (2 * mp.pi)))
