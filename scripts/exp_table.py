#!/usr/bin/env python3
"""Prints the table of 2^(j/64), j = 0..63, correctly rounded to f64, as the Rust array in
crates/bearing-core/src/physics/exp.rs (EXP2_TABLE). Standard library only: each entry is
computed with 50 significant digits by the decimal module, then rounded once."""
from decimal import Decimal, getcontext
import struct

getcontext().prec = 50
ln2 = Decimal(2).ln()
print("const EXP2_TABLE: [u64; 64] = [")
for j in range(64):
    v = (ln2 * j / 64).exp()
    bits = struct.unpack("<Q", struct.pack("<d", float(v)))[0]
    print(f"    0x{bits:016x}, // 2^({j}/64)")
print("];")
