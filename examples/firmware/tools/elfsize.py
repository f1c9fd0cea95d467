#!/usr/bin/env python3
"""Flash and RAM use of a linked firmware ELF, whole and per crate, as key=value lines.

Usage: elfsize.py FIRMWARE.elf [SUFFIX]

Whole firmware (from the section headers):
  flash_bytes = every allocated section that is loaded from flash (.vector_table, .text,
                .rodata, and the initial values of .data)
  ram_bytes   = .data + .bss + .uninit (statics; the stack is measured at run time)
Per crate (from the symbol table, FUNC and OBJECT symbols with their sizes):
  microray_flash_bytes / microray_ram_bytes: symbols whose mangled path is in crate `microray`
  libm_flash_bytes: symbols of crate `libm` (microray's float functions)
Symbols are counted where the linker left them: code that LLVM inlined into a firmware function
counts as firmware here; tools/inlined.py measures that part of microray from the line table. Pure Python (no binutils needed); ELF32 little-endian only.
"""
import struct
import sys


def sections(data):
    shoff, = struct.unpack_from("<I", data, 0x20)
    shentsize, shnum, shstrndx = struct.unpack_from("<HHH", data, 0x2E)
    hdrs = [struct.unpack_from("<IIIIIIIIII", data, shoff + i * shentsize) for i in range(shnum)]
    strtab = hdrs[shstrndx]
    def name(off):
        start = strtab[4] + off
        return data[start:data.index(b"\0", start)].decode()
    return [(name(h[0]),) + h for h in hdrs]


def main():
    path = sys.argv[1]
    suffix = sys.argv[2] if len(sys.argv) > 2 else ""
    data = open(path, "rb").read()
    assert data[:4] == b"\x7fELF" and data[4] == 1 and data[5] == 1, "ELF32 LE expected"
    secs = sections(data)
    SHF_ALLOC, SHT_NOBITS, SHT_SYMTAB = 2, 8, 2
    flash = ram = 0
    kind = {}  # section index -> "flash" | "ram" | "both"
    for i, (name, _, stype, flags, addr, _, size, *_rest) in enumerate(secs):
        if not flags & SHF_ALLOC or size == 0:
            continue
        if stype == SHT_NOBITS:  # .bss, .uninit
            ram += size
            kind[i] = "ram"
        elif addr >= 0x2000_0000:  # .data: in RAM, initial values in flash
            ram += size
            flash += size
            kind[i] = "both"
        else:
            flash += size
            kind[i] = "flash"
    crate = {"microray": [0, 0], "libm": [0, 0]}
    for name, _, stype, _, _, off, size, link, _, _, entsize in secs:
        if stype != SHT_SYMTAB:
            continue
        strs = secs[link][5]
        for k in range(size // entsize):
            st_name, _, st_size, info, _, shndx = struct.unpack_from("<IIIBBH", data, off + k * entsize)
            if (info & 0xF) not in (1, 2) or st_size == 0 or shndx not in kind:  # OBJECT, FUNC
                continue
            sym = data[strs + st_name:data.index(b"\0", strs + st_name)].decode(errors="replace")
            for c in crate:
                # Legacy (_ZN8microray...) and v0 (...8microray...) mangling both hold len+name;
                # generic impls print the path as `microray..`.
                if f"{len(c)}{c}" in sym or f"$LT${c}.." in sym:
                    where = kind[shndx]
                    if where in ("flash", "both"):
                        crate[c][0] += st_size
                    if where in ("ram", "both"):
                        crate[c][1] += st_size
                    break
    print(f"flash_bytes{suffix}={flash}")
    print(f"ram_bytes{suffix}={ram}")
    print(f"microray_flash_bytes{suffix}={crate['microray'][0]}")
    print(f"microray_ram_bytes{suffix}={crate['microray'][1]}")
    print(f"libm_flash_bytes{suffix}={crate['libm'][0]}")


if __name__ == "__main__":
    main()
