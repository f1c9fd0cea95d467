# Sourced by run.sh and figures.sh (from examples/firmware): checks for QEMU and sets $objdump,
# the disassembler for the panic check: $OBJDUMP, LLVM's (PATH or rustup's llvm-tools), or GNU's.
command -v qemu-system-arm >/dev/null || { echo "error=qemu-system-arm not found" >&2; exit 3; }
objdump=${OBJDUMP:-}
if [ -z "$objdump" ]; then
  for c in llvm-objdump "$(rustc --print sysroot)"/lib/rustlib/*/bin/llvm-objdump arm-none-eabi-objdump; do
    if command -v "$c" >/dev/null 2>&1; then objdump=$c; break; fi
  done
fi
[ -n "$objdump" ] || { echo "error=no objdump (install llvm or binutils-arm-none-eabi)" >&2; exit 3; }
