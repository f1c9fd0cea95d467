#!/usr/bin/env python3
"""Flash bytes of microray's code that LLVM inlined into the firmware's own functions.

Usage: inlined.py FIRMWARE.elf OBJDUMP MICRORAY_SRC_DIR [SUFFIX]

`elfsize.py` counts microray's flash by symbol: code inlined into a firmware function (typically
`Frame::new` inside the firmware's set-up) counts as firmware there. This adds it back from the
line table (`objdump -d -l`): inside every function that is not microray's, an instruction
belongs to microray when its source line is in MICRORAY_SRC_DIR, or when it is library code
(core, heapless, libm, ...: generics instantiated for the caller) whose nearest preceding
crate line was microray's. Prints `microray_inlined_flash_bytes` (instruction bytes, literal
pools not included, so a slight undercount). Pure Python apart from objdump.
"""
import os
import re
import subprocess
import sys

HEAD = re.compile(r"^([0-9a-f]+) <(.+)>:$")
INSN = re.compile(r"^\s*([0-9a-f]+):")
LINE = re.compile(r"^; (/\S+?)(:\d+)?$")


def main():
    elf, objdump, src = sys.argv[1], sys.argv[2], os.path.realpath(sys.argv[3])
    suffix = sys.argv[4] if len(sys.argv) > 4 else ""
    firmware_src = os.path.realpath(os.path.join(os.path.dirname(elf), "..", "..", "..", "src"))
    text = subprocess.run([objdump, "-d", "-l", "--demangle", "--no-show-raw-insn", elf],
                          check=True, capture_output=True, text=True).stdout
    total = 0
    theirs = False  # inside a function that is not microray's
    owner = "firmware"  # the crate of the last line seen that was not library code
    prev = None  # (address, owner) of the previous instruction of this function
    for line in text.splitlines():
        m = HEAD.match(line)
        if m:
            name = m.group(2)
            if name.startswith("$"):  # mapping symbols: $d starts a literal pool
                if name.startswith("$d"):
                    prev = None
                continue
            theirs = "microray::" not in name and "microray.." not in name
            owner, prev = "firmware", None
            continue
        m = LINE.match(line)
        if m:
            path = os.path.realpath(m.group(1))
            if path.startswith(src + os.sep):
                owner = "microray"
            elif path.startswith(firmware_src + os.sep) or "/examples/firmware/" in path:
                owner = "firmware"
            continue
        m = INSN.match(line)
        if m and theirs:
            addr = int(m.group(1), 16)
            if prev is not None and prev[1] == "microray":
                total += addr - prev[0]
            prev = (addr, owner)
    print(f"microray_inlined_flash_bytes{suffix}={total}")


if __name__ == "__main__":
    main()
