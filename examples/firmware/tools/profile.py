#!/usr/bin/env python3
"""Instructions per pixel by function, from QEMU's execution trace of the firmware.

    E=target/thumbv7em-none-eabihf/release/firmware
    qemu-system-arm -M mps2-an386 -cpu cortex-m4 -nographic -monitor none -serial none \\
        -semihosting-config enable=on,target=native -icount shift=0 -kernel $E \\
        -d in_asm,exec,nochain -D /dev/stderr 2>&1 >/dev/null | python3 tools/profile.py $E

QEMU logs each translated block once (`in_asm`: its instructions) and every execution of a block
(`exec`, with `nochain` so that chained blocks are logged too); each execution is charged to the
functions of the block's instructions. The figures cover the whole run (both render passes, the
set-up and the calibration loop), divided by 2 x 320 x 240 pixels: instructions, not cycles.
"""
import bisect
import collections
import re
import shutil
import subprocess
import sys

elf = sys.argv[1]
pixels = 2 * 320 * 240
nm = next((c for c in ("llvm-nm", "arm-none-eabi-nm", "nm") if shutil.which(c)), None)
syms = []
for line in subprocess.run([nm, "-C", "--defined-only", "-n", elf],
                           capture_output=True, text=True).stdout.splitlines():
    p = line.split(" ", 2)
    if len(p) == 3 and p[1] in "tTwW":
        syms.append((int(p[0], 16) & ~1, p[2]))
syms.sort()
addrs = [a for a, _ in syms]


def function(a):
    i = bisect.bisect_right(addrs, a) - 1
    return syms[i][1] if i >= 0 else "?"


blocks, current, runs = {}, None, collections.Counter()
for line in sys.stdin:
    if line.startswith("IN:"):
        current = []
        continue
    if current is not None:
        m = re.match(r"0x([0-9a-f]+):", line)
        if m:
            current.append(int(m.group(1), 16))
            continue
        if current:
            blocks[current[0]] = current
        current = None
    if line.startswith("Trace"):
        m = re.search(r"/([0-9a-f]{8})/", line)
        if m:
            runs[int(m.group(1), 16)] += 1
per_function, total = collections.Counter(), 0
for pc, n in runs.items():
    for a in blocks.get(pc, [pc]):
        per_function[function(a)] += n
        total += n
for name, n in per_function.most_common(25):
    print(f"{100 * n / total:6.2f}% {n / pixels:8.1f}/px  {re.sub(r'::h[0-9a-f]{16}$', '', name)}")
print(f"total {total} instructions, {total / pixels:.1f}/px")
