#!/usr/bin/env python3
"""Instructions per pixel by function, from QEMU's execution trace of the firmware.

    E=target/thumbv7em-none-eabihf/release/firmware
    qemu-system-arm -M mps2-an386 -cpu cortex-m4 -nographic -monitor none -serial none \\
        -semihosting-config enable=on,target=native -icount shift=0 -kernel $E \\
        -d in_asm,exec,nochain -D /dev/stderr 2>&1 >/dev/null | python3 tools/profile.py $E

With `--lines [N]` after the ELF it prints the N (default 60) costliest source lines instead:
each instruction is charged to the innermost inlined frame in microray's or the firmware's
source (`llvm-addr2line -i`, or binutils' `addr2line` for a toolchain that knows Arm), with
the line's text. Optimised code's line tables are approximate: a line is where to look, and
`:0` is code the compiler made (spills, moves) that no line owns.

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
lines_mode = len(sys.argv) > 2 and sys.argv[2] == "--lines"
top = int(sys.argv[3]) if lines_mode and len(sys.argv) > 3 else 60
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
if lines_mode:
    per_address = collections.Counter()
    for pc, n in runs.items():
        for a in blocks.get(pc, [pc]):
            per_address[a] += n
    addresses = sorted(per_address)
    tool = next((c for c in ("llvm-addr2line", "arm-none-eabi-addr2line", "addr2line")
                 if shutil.which(c)), None)
    out = subprocess.run([tool, "-f", "-i", "-a", "-e", elf] + [hex(a) for a in addresses],
                         capture_output=True, text=True).stdout.splitlines()
    # Per address: a line "0x…", then (function, file:line) pairs, innermost first.
    per_line, chain, address = collections.Counter(), [], None

    def charge():
        if address is None:
            return
        places = chain[1::2]
        own = [p for p in places if "/src/" in p and "/rustc/" not in p and "/.cargo/" not in p]
        place = (own or places or ["?"])[0]
        per_line[re.sub(r" \(discriminator \d+\)", "", place)] += per_address[address]

    for line in out:
        if re.match(r"0x[0-9a-f]+$", line):
            charge()
            address, chain = int(line, 16), []
        else:
            chain.append(line)
    charge()
    texts = {}
    for place, n in per_line.most_common(top):
        path, _, number = place.rpartition(":")
        text = ""
        if number.isdigit():
            try:
                text = texts.setdefault(path, open(path).read().split("\n"))[int(number) - 1]
            except (OSError, IndexError):
                pass
        short = re.sub(r"^.*?/(src|examples)/", r"\1/", place)
        print(f"{n / pixels:7.1f}/px  {short:40s} {text.strip()[:70]}")
    sys.exit(0)
per_function, total = collections.Counter(), 0
for pc, n in runs.items():
    for a in blocks.get(pc, [pc]):
        per_function[function(a)] += n
        total += n
for name, n in per_function.most_common(25):
    print(f"{100 * n / total:6.2f}% {n / pixels:8.1f}/px  {re.sub(r'::h[0-9a-f]{16}$', '', name)}")
print(f"total {total} instructions, {total / pixels:.1f}/px")
