#!/usr/bin/env python3
"""Proves from the disassembly that the render path of a firmware ELF cannot reach a panic.

Usage: panic_check.py FIRMWARE.elf [OBJDUMP [ROOT,ROOT...]]

Builds the static call graph (bl/b/b.w/cbz... targets that are other functions: calls and tail
calls) from `objdump -d`, walks it from the render-path roots (by default `crc_rgb888` and
`crc_rgb565_dithered` of scene.rs, both `#[inline(never)]`; another firmware names its own),
and fails if the walk reaches
`core::panicking::*`, `rust_begin_unwind` or the panic handler, or meets an indirect call
(`blx rN`, `bx rN` other than `bx lr`, or a load into pc), which it could not follow.

Prints key=value lines: render_path_functions, render_path_flash_bytes (everything the render
path can execute: microray, libm, compiler-builtins, embedded-graphics glue and the firmware's
CRC code), render_path_indirect_calls, render_path_panics,
and panic_callers (every function in the ELF that calls a panic entry directly: these must be
firmware set-up code, never microray's). Exit status 0 only when the render path is panic-free.
"""
import re
import subprocess
import sys

ROOTS = ("crc_rgb888", "crc_rgb565_dithered")
PANIC = re.compile(r"core::panicking::|rust_begin_unwind|^panic$|::panic::h[0-9a-f]+$")
HEAD = re.compile(r"^([0-9a-f]+) <(.+)>:$")
# An instruction line with its raw bytes: address, bytes, then the instruction after a tab.
RAW = re.compile(r"^(\s*[0-9a-f]+:)\s+((?:[0-9a-f]{2,8} ?)+)\s*\t(.*)$")
BRANCH = re.compile(r"^\s*[0-9a-f]+:\s+(bl|blx|b|b\.w|b\.n|b[a-z]{2}(?:\.w|\.n)?|cbn?z)\s+.*<(.+?)(\+0x[0-9a-f]+)?>")
INDIRECT = re.compile(r"^\s*[0-9a-f]+:\s+(blx\s+(r\d+|ip|lr)|bx\s+(?!lr)\w+|mov\s+pc,|ldr\S*\s+pc,)")


def main():
    elf = sys.argv[1]
    objdump = sys.argv[2] if len(sys.argv) > 2 else "llvm-objdump"
    roots_wanted = tuple(sys.argv[3].split(",")) if len(sys.argv) > 3 else ROOTS
    text = subprocess.run([objdump, "-d", "--demangle", elf],
                          check=True, capture_output=True, text=True).stdout
    calls, indirect, func, start = {}, {}, None, {}

    def body(lines):
        # lld fills the gap after a function with 0xd4d4 halfwords (a trap), which disassemble
        # as `bmi` into whatever precedes: the trailing ones are padding, not code.
        while lines and lines[-1][0] == "d4d4":
            lines.pop()
        for _, line in lines:
            m = BRANCH.match(line)
            if m and m.group(2) != func and not m.group(2).startswith("$"):
                calls[func].add(m.group(2))
            elif INDIRECT.match(line):
                indirect[func].append(line.strip())

    pending = []
    for line in text.splitlines():
        m = HEAD.match(line)
        if m:
            name = m.group(2)
            if not name.startswith("$"):  # $t/$d are mapping symbols inside a function
                if func is not None:
                    body(pending)
                pending = []
                func = name
                start[func] = int(m.group(1), 16)
                calls.setdefault(func, set())
                indirect.setdefault(func, [])
            continue
        if func is None:
            continue
        r = RAW.match(line)
        if r:
            pending.append((r.group(2).replace(" ", ""), r.group(1) + "\t" + r.group(3)))
    if func is not None:
        body(pending)
    # `pop {..., pc}` and `bx lr` are returns; a `blx`/`bx` through another register or a load
    # into pc is an indirect branch that the walk cannot follow, so it counts as a failure.
    roots = [f for f in calls if any(r in f for r in roots_wanted)]
    if len(roots) != len(roots_wanted):
        print(f"error=render-path roots not found (found {roots})")
        return 2
    seen, todo = set(), list(roots)
    while todo:
        f = todo.pop()
        if f in seen:
            continue
        seen.add(f)
        todo.extend(calls.get(f, ()))
    panics = sorted(f for f in seen if PANIC.search(f))
    ind = [(f, i) for f in sorted(seen) for i in indirect.get(f, [])]
    callers = sorted({f for f, cs in calls.items() for c in cs if PANIC.search(c) and not PANIC.search(f)})
    # Function sizes from consecutive start addresses (literal pools included; the last function
    # of the text has no successor and is left out, it is never on the render path).
    addrs = sorted(start.values())
    nxt = {a: b for a, b in zip(addrs, addrs[1:])}
    size = {f: nxt.get(a, a) - a for f, a in start.items()}
    print(f"render_path_functions={len(seen)}")
    print(f"render_path_flash_bytes={sum(size.get(f, 0) for f in seen)}")
    print(f"render_path_indirect_calls={len(ind)}")
    print(f"render_path_panics={len(panics)}")
    print("panic_callers=" + ";".join(callers))
    for f in panics:
        print(f"render_path_panic={f}")
    for f, i in ind:
        print(f"render_path_indirect={f}: {i}")
    return 0 if not panics and not ind else 1


if __name__ == "__main__":
    sys.exit(main())
