//! What the firmware binaries need from the board: an instruction clock (SysTick under QEMU
//! `-icount`, calibrated against a loop of known length), a painted stack to measure its
//! high-water mark, exit to QEMU with a status, and fault and panic handlers that report and
//! fail.

use core::arch::asm;
use core::panic::PanicInfo;
use core::ptr::{addr_of, read_volatile, write_volatile};
use core::sync::atomic::{AtomicU32, Ordering};

use cortex_m::peripheral::{syst::SystClkSource, SYST};
use cortex_m_rt::{exception, ExceptionFrame};
use cortex_m_semihosting::{debug, hprintln};

/// SysTick reload: the full 24 bits.
const RELOAD: u32 = 0x00FF_FFFF;
/// Completed SysTick periods; written only by the SysTick handler (Cortex-M0 has no atomic
/// read-modify-write, so load + store).
static WRAPS: AtomicU32 = AtomicU32::new(0);

#[exception]
fn SysTick() {
    WRAPS.store(WRAPS.load(Ordering::Relaxed) + 1, Ordering::Relaxed);
}

/// SysTick ticks since it was started, as one 64-bit count.
pub fn ticks() -> u64 {
    loop {
        let w = WRAPS.load(Ordering::SeqCst);
        let v = SYST::get_current();
        if WRAPS.load(Ordering::SeqCst) == w {
            return ((w as u64) << 24) | (RELOAD - v) as u64;
        }
    }
}

/// Exactly `2 n` instructions (`subs` and `bne` per iteration) for the calibration.
#[inline(never)]
fn spin(n: u32) {
    // SAFETY: register-only loop; touches no memory and no stack.
    unsafe {
        asm!("2:", "subs {0}, #1", "bne 2b", inout(reg) n => _, options(nomem, nostack));
    }
}

/// Starts SysTick on the core clock and returns its ticks per 2 000 000 instructions.
pub fn start_clock(mut syst: SYST) -> u64 {
    syst.set_clock_source(SystClkSource::Core);
    syst.set_reload(RELOAD);
    syst.clear_current();
    syst.enable_interrupt();
    syst.enable_counter();
    // After clear_current the counter reads 0 until it first reloads: wait for that.
    while SYST::get_current() == 0 {}
    let t = ticks();
    spin(1_000_000);
    ticks() - t
}

/// Ends the QEMU run with a success or failure status.
pub fn exit(ok: bool) -> ! {
    debug::exit(if ok {
        debug::EXIT_SUCCESS
    } else {
        debug::EXIT_FAILURE
    });
    #[allow(clippy::empty_loop)]
    loop {}
}

/// The pattern painted over the free stack.
const PAINT: u32 = 0xC0DE_CAFE;

extern "C" {
    /// End of `.bss`/`.uninit` (cortex-m-rt): the lowest address the stack could grow to.
    static __sheap: u32;
    /// The initial stack pointer (cortex-m-rt): the top of RAM.
    static _stack_start: u32;
}

/// Paints the unused stack, from the end of the statics up to 64 bytes below this function's
/// own stack pointer.
// Not every binary measures its stack.
#[allow(dead_code)]
#[inline(never)]
pub fn paint_stack() {
    let bottom = addr_of!(__sheap) as usize;
    let sp = cortex_m::register::msp::read() as usize;
    let mut p = bottom;
    while p + 64 < sp {
        // SAFETY: [bottom, sp − 64) is RAM that nothing uses yet (below the live stack, above
        // every static), and p is word-aligned.
        unsafe { write_volatile(p as *mut u32, PAINT) };
        p += 4;
    }
}

/// Stack bytes ever used: from the top of RAM down to the deepest overwritten painted word.
#[allow(dead_code)]
pub fn stack_high_water() -> usize {
    let (bottom, top) = (addr_of!(__sheap) as usize, addr_of!(_stack_start) as usize);
    let mut p = bottom;
    // SAFETY: reads of word-aligned RAM between the statics and the top of the stack.
    while p < top && unsafe { read_volatile(p as *const u32) } == PAINT {
        p += 4;
    }
    top - p
}

#[exception]
unsafe fn HardFault(ef: &ExceptionFrame) -> ! {
    hprintln!("error=hardfault pc={:#010x}", ef.pc());
    exit(false)
}

#[panic_handler]
fn panic(info: &PanicInfo) -> ! {
    hprintln!("error=panic: {}", info);
    exit(false)
}
