//! microray on an RP2040 (Raspberry Pi Pico) driving an ST7789 240×240 panel over SPI, with
//! both cores tracing.
//!
//! No framebuffer (240×240 `Rgb565` would take 115 200 bytes): the frame is traced in bands of
//! `BAND_ROWS` rows. Core 0 traces the even bands into a buffer of its own. Core 1 traces the odd
//! bands into two buffers that the SIO FIFO lends back and forth: core 0 lends both at the start,
//! core 1 sends a buffer's index once its band is traced, and core 0 sends the index back once
//! that band is on the panel. Core 0 sends every band to the panel, in order; meanwhile core 1
//! traces its next band.
//!
//! Floats: Cargo.toml enables rp2040-hal's `disable-intrinsics`. Without it, rp2040-hal routes
//! f32 `+ − × ÷`, int–float conversions and `sqrtf` to the boot ROM, which flushes subnormals
//! to zero and whose float-to-int conversion rounds towards −∞ (Rust's `as` truncates): not
//! the IEEE arithmetic that makes microray's pixels the host's. With it, every f32 operation
//! is compiler-builtins' IEEE soft float, the arithmetic of the QEMU Cortex-M0 that prints the
//! host's CRCs. The cost is speed: the ROM's routines are faster (README.md).
#![no_std]
#![no_main]

mod scene;

use core::cell::UnsafeCell;
use core::sync::atomic::{fence, Ordering};

use embedded_graphics::pixelcolor::{Rgb565, RgbColor};
use embedded_graphics::prelude::{DrawTarget, Point, Size};
use embedded_graphics::primitives::Rectangle;
use embedded_hal_bus::spi::ExclusiveDevice;
use hal::clocks::Clock;
use hal::fugit::RateExtU32;
use hal::gpio::{FunctionSpi, PinState};
use hal::multicore::{Multicore, Stack};
use hal::sio::Sio;
use hal::{pac, Timer};
use mipidsi::interface::SpiInterface;
use mipidsi::models::ST7789;
use mipidsi::options::ColorInversion;
use mipidsi::Builder;
use panic_halt as _;
use rp2040_hal as hal;

use scene::BoardFrame;

// The wiring: a Waveshare Pico-LCD-1.3 plugged onto a Pico. SCK and MOSI must be SPI1's pins
// (or change `pac.SPI1` in `main`); the others may be any GPIO. BL: the backlight.
hal::bsp_pins!(
    Gpio8 { name: lcd_dc },
    Gpio9 { name: lcd_cs },
    Gpio10 { name: lcd_sck },
    Gpio11 { name: lcd_mosi },
    Gpio12 { name: lcd_rst },
    Gpio13 { name: lcd_bl },
);
/// SPI clock: the RP2040's fastest (clk_peri / 2 at 125 MHz), the ST7789's shortest write
/// cycle (16 ns). Lower it for long wires.
const SPI_HZ: u32 = 62_500_000;
/// The Pico's crystal.
const XTAL_HZ: u32 = 12_000_000;

/// The second-stage boot loader for the Pico's W25Q080 flash, at the start of flash (memory.x).
#[link_section = ".boot2"]
#[used]
static BOOT2: [u8; 256] = rp2040_boot2::BOOT_LOADER_W25Q080;

/// The panel, and the frame: one pixel per panel pixel.
const WIDTH: u32 = 240;
const HEIGHT: u32 = 240;
/// Rows per band: 30 bands, each buffer 3 840 bytes.
const BAND_ROWS: u32 = 8;
const BAND_PIXELS: usize = (WIDTH * BAND_ROWS) as usize;
const BANDS: u32 = HEIGHT / BAND_ROWS;
const _: () = assert!(HEIGHT.is_multiple_of(BAND_ROWS), "whole bands only");

/// A band buffer of core 1's, lent between the cores through the SIO FIFO.
struct Band(UnsafeCell<[Rgb565; BAND_PIXELS]>);

// SAFETY: `CORE1_BANDS[i]` is only touched by the core that holds index `i`: core 1 from
// reading `i` off the FIFO to writing it back, core 0 from reading it to writing it back. The
// fences around the FIFO's words order the buffer's accesses (the RP2040 has no data cache).
unsafe impl Sync for Band {}

static CORE1_BANDS: [Band; 2] = [const { Band(UnsafeCell::new([Rgb565::BLACK; BAND_PIXELS])) }; 2];

/// Core 1's stack, 8 KiB: microray traces in under 2 KiB (docs/firmware.md).
static CORE1_STACK: Stack<2048> = Stack::new();

/// Core 1: traces the odd bands, in order, into the buffers that core 0 lends it.
fn core1_bands(frame: &'static BoardFrame) {
    // SAFETY: core 1 only uses its own ends of the inter-core FIFOs (the SIO's FIFO registers
    // are per core) and takes no other peripheral.
    let pac = unsafe { pac::Peripherals::steal() };
    let mut fifo = Sio::new(pac.SIO).fifo;
    for band in (1..BANDS).step_by(2) {
        let i = fifo.read_blocking() as usize;
        fence(Ordering::Acquire);
        // SAFETY: core 0 has lent buffer `i` and touches it again only after core 1 writes `i`
        // back (see `Band`).
        let buf = unsafe { &mut *CORE1_BANDS[i].0.get() };
        frame.render_rows(band * BAND_ROWS, buf).unwrap();
        fence(Ordering::Release);
        fifo.write_blocking(i as u32);
    }
}

#[hal::entry]
fn main() -> ! {
    let mut pac = pac::Peripherals::take().unwrap();
    let mut watchdog = hal::Watchdog::new(pac.WATCHDOG);
    let clocks = hal::clocks::init_clocks_and_plls(
        XTAL_HZ,
        pac.XOSC,
        pac.CLOCKS,
        pac.PLL_SYS,
        pac.PLL_USB,
        &mut pac.RESETS,
        &mut watchdog,
    )
    .ok()
    .unwrap();
    let mut timer = Timer::new(pac.TIMER, &mut pac.RESETS, &clocks);
    let mut sio = Sio::new(pac.SIO);
    let pins = Pins::new(
        pac.IO_BANK0,
        pac.PADS_BANK0,
        sio.gpio_bank0,
        &mut pac.RESETS,
    );

    // Core 1 starts tracing while core 0 sets up the panel.
    let frame = scene::frame(WIDTH, HEIGHT);
    {
        let mut mc = Multicore::new(&mut pac.PSM, &mut pac.PPB, &mut sio.fifo);
        let core1 = &mut mc.cores()[1];
        let stack = CORE1_STACK.take().unwrap();
        core1.spawn(stack, move || core1_bands(frame)).unwrap();
    }
    for i in 0..CORE1_BANDS.len() {
        sio.fifo.write_blocking(i as u32);
    }

    let sck = pins.lcd_sck.into_function::<FunctionSpi>();
    let mosi = pins.lcd_mosi.into_function::<FunctionSpi>();
    let spi = hal::Spi::<_, _, _, 8>::new(pac.SPI1, (mosi, sck)).init(
        &mut pac.RESETS,
        clocks.peripheral_clock.freq(),
        SPI_HZ.Hz(),
        embedded_hal::spi::MODE_0,
    );
    let cs = pins.lcd_cs.into_push_pull_output_in_state(PinState::High);
    let spi = ExclusiveDevice::new_no_delay(spi, cs).unwrap();
    let dc = pins.lcd_dc.into_push_pull_output();
    let rst = pins.lcd_rst.into_push_pull_output_in_state(PinState::High);
    let mut spi_buffer = [0u8; 512];
    let di = SpiInterface::new(spi, dc, &mut spi_buffer);
    let mut display = Builder::new(ST7789, di)
        .display_size(WIDTH as u16, HEIGHT as u16)
        .invert_colors(ColorInversion::Inverted) // 240×240 ST7789 panels show inverted colours
        .reset_pin(rst)
        .init(&mut timer)
        .unwrap();
    let _backlight = pins.lcd_bl.into_push_pull_output_in_state(PinState::High);

    let mut show = |band: u32, pixels: &[Rgb565]| {
        let rows = Rectangle::new(
            Point::new(0, (band * BAND_ROWS) as i32),
            Size::new(WIDTH, BAND_ROWS),
        );
        display
            .fill_contiguous(&rows, pixels.iter().copied())
            .unwrap();
    };
    let mut own = [Rgb565::BLACK; BAND_PIXELS];
    for band in 0..BANDS {
        if band % 2 == 0 {
            frame.render_rows(band * BAND_ROWS, &mut own).unwrap();
            show(band, &own);
        } else {
            let i = sio.fifo.read_blocking() as usize;
            fence(Ordering::Acquire);
            // SAFETY: core 1 wrote `i` after its last write to buffer `i` and touches it again
            // only after core 0 writes `i` back (see `Band`).
            let buf = unsafe { &*CORE1_BANDS[i].0.get() };
            show(band, buf);
            fence(Ordering::Release);
            sio.fifo.write_blocking(i as u32);
        }
    }
    loop {
        cortex_m::asm::wfi();
    }
}
