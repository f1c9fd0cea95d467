#!/usr/bin/env bash
# The board examples (examples/boards/*): each is its own workspace with a committed Cargo.lock.
# Checks formatting and clippy, builds the release firmware, and prints each ELF's sizes. There
# is no hardware: building and linking for the target is the check. After a change to
# microray's dependencies, `cargo build` in each crate (without --locked) refreshes its lock.
set -euo pipefail
cd "$(dirname "$0")/.."

rustup target add thumbv6m-none-eabi thumbv7em-none-eabihf
rustup component add clippy rustfmt

# Section sizes from the ELF32 section headers: flash = what is loaded, RAM = statics.
elf_sizes() {
  python3 - "$1" <<'PY'
import struct, sys
data = open(sys.argv[1], "rb").read()
shoff, = struct.unpack_from("<I", data, 0x20)
shentsize, shnum, shstrndx = struct.unpack_from("<HHH", data, 0x2E)
headers = [struct.unpack_from("<IIIIIIIIII", data, shoff + i * shentsize) for i in range(shnum)]
strtab = headers[shstrndx][4]
def name(h):
    start = strtab + h[0]
    return data[start:data.index(b"\0", start)].decode()
sizes = {name(h): h[5] for h in headers}
alloc = [h for h in headers if h[2] & 0x2]           # SHF_ALLOC
flash = sum(h[5] for h in alloc if h[1] != 8)        # not SHT_NOBITS: stored in flash
ram = sum(sizes.get(s, 0) for s in (".data", ".bss", ".uninit"))
print(f"text={sizes.get('.text', 0)} flash={flash} ram={ram}")
PY
}

for board in rp2040-st7789 stm32f4-ili9341; do
  dir=examples/boards/$board
  echo "== $dir"
  # Cargo reads .cargo/config.toml (the target, the linker script) from the directory it runs
  # in, not from the manifest's: so each command runs in the crate.
  (
    cd "$dir"
    cargo fmt --check
    cargo clippy --release --locked -- -D warnings
    start=$SECONDS
    cargo build --release --locked
    echo "build: $((SECONDS - start)) s"
    target=$(sed -n 's/^target = "\([^"]*\)".*/\1/p' .cargo/config.toml)
    elf=${CARGO_TARGET_DIR:-target}/$target/release/$board
    test -f "$elf"
    if command -v python3 >/dev/null; then
      echo "$board: $(elf_sizes "$elf")"
    fi
  )
done
