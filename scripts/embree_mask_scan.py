#!/usr/bin/env python3
"""Lists the places in an Embree library where an AVX-512 mask stored to the stack as 8 or 16
bits (kmovw/kmovb %kN,OFF(%rsp)) is read back as 64 bits from the same slot (cmpq, tzcnt, bsf,
test or mov into a 64-bit register) before the slot is written again: the bits above the mask are
then whatever the slot held before. This is the miscompile behind EmbreeBackend's guard
(include/igi/backends/embree/embree_backend.hpp, embree_coherent_occlusion16_may_loop); for each
place it names the Embree function whose assertion strings lie closest to it.

    python3 scripts/embree_mask_scan.py [/usr/lib/x86_64-linux-gnu/libembree3.so.3]

Needs objdump (binutils); takes about a minute. Debian 12's libembree3 3.13.5+dfsg-2 has four
such places, all in the 16-wide occlusion kernels (BVHNIntersectorKHybrid<N, 16>::occluded with
occludedCoherent inlined, for BVH4 and BVH8, robust or not), and none anywhere else: not in the
closest-hit kernels, not at 4 or 8 lanes.
"""
import re
import subprocess
import sys

library = sys.argv[1] if len(sys.argv) > 1 else "/usr/lib/x86_64-linux-gnu/libembree3.so.3"
# How far after the store the reload is looked for: the loop's store and its reload are a few
# instructions apart; 40 covers the compiler's scheduling without running into other functions.
WINDOW = 40
# How far around a place its function's assertion strings are looked for (in instructions).
NEARBY = 3000

listing = subprocess.run(["objdump", "-d", "--no-show-raw-insn", library], check=True, capture_output=True,
                         text=True).stdout.split("\n")
data = open(library, "rb").read()
store = re.compile(r"^\s*([0-9a-f]+):\s+kmov[wb]\s+%k\d,(-?0x[0-9a-f]+)\(%rsp\)")
string_address = re.compile(r"lea\s+0x[0-9a-f]+\(%rip\),%r[a-z0-9]+\s+#\s+([0-9a-f]+)")


def reads_wide(instruction):
    """True if the instruction reads its stack operand as 64 bits."""
    op = instruction.split()[0]
    if op in ("cmpq", "testq", "andq", "orq"):
        return True
    registers = re.findall(r"%(r[a-z0-9]+)", instruction)
    return op in ("tzcnt", "bsf", "mov", "popcnt") and any(not r.endswith(("d", "w", "b", "sp")) for r in registers)


def function_near(line):
    """The Embree function named by the assertion strings closest to line `line`, if any."""
    best = None
    for distance in range(NEARBY):
        for i in (line - distance, line + distance):
            if 0 <= i < len(listing) and "__assert_fail" in listing[i]:
                for j in range(i - 6, i):
                    m = string_address.search(listing[j])
                    if not m:
                        continue
                    start = int(m.group(1), 16)
                    text = data[start:data.index(b"\0", start)].decode(errors="replace")
                    if "Coherent" in text or "Hybrid" in text:
                        best = text
                if best:
                    return best
    return "(no assertion string nearby)"


places = 0
for i, line in enumerate(listing):
    m = store.match(line)
    if not m:
        continue
    address, offset = m.groups()
    slot = offset + "(%rsp)"
    for j in range(i + 1, min(i + WINDOW, len(listing))):
        if slot in listing[j]:
            instruction = listing[j].split(":", 1)[1].strip()
            if reads_wide(instruction):
                places += 1
                name = function_near(i)
                print(f"{address}: {line.split(':', 1)[1].strip()}  ->  {instruction}\n    in {name}")
            break
print(f"{places} places where a narrow mask store is read back as 64 bits in {library}")
