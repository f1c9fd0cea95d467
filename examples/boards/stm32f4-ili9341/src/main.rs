//! microray on an STM32F411 ("Black Pill") drawing onto an ILI9341 panel over SPI, rotated to
//! landscape: 320×240.
//!
//! `Frame::draw` traces each row as the display driver takes it: no framebuffer and no row
//! buffer (a 320×240 `Rgb565` frame would take 153 600 bytes, more than the chip's RAM).
#![no_std]
#![no_main]

mod scene;

use cortex_m_rt::entry;
use embedded_hal_bus::spi::ExclusiveDevice;
use mipidsi::interface::SpiInterface;
use mipidsi::models::ILI9341Rgb565;
use mipidsi::options::{ColorOrder, Orientation, Rotation};
use mipidsi::Builder;
use panic_halt as _;
use stm32f4xx_hal::gpio::{gpioa, gpiob, PA4, PA5, PA7, PB0, PB1, PB10};
use stm32f4xx_hal::pac::{self, SPI1};
use stm32f4xx_hal::prelude::*;
use stm32f4xx_hal::rcc::Config;

/// The wiring: the pin of each signal on a Black Pill. SCK and MOSI must be SPI1's (or change
/// `dp.SPI1` in `main`); the others may be any GPIO.
struct Wiring {
    sck: PA5,
    mosi: PA7,
    cs: PA4,
    dc: PB0,
    rst: PB1,
    backlight: PB10,
}

impl Wiring {
    fn new(a: gpioa::Parts, b: gpiob::Parts) -> Self {
        Wiring {
            sck: a.pa5,
            mosi: a.pa7,
            cs: a.pa4,
            dc: b.pb0,
            rst: b.pb1,
            backlight: b.pb10,
        }
    }
}

/// SPI clock: APB2 (100 MHz) / 4. Beyond the ILI9341 datasheet's 10 MHz write clock, as
/// common drivers run it; lower it if the picture is garbled. A frame's 153 600 bytes take
/// 49 ms at this rate, little next to the tracing.
const SPI_HZ: u32 = 25_000_000;
/// The Black Pill's crystal, and the F411's top system clock.
const HSE_HZ: u32 = 25_000_000;
const SYSCLK_HZ: u32 = 100_000_000;

/// The frame, in landscape: one pixel per panel pixel.
const WIDTH: u32 = 320;
const HEIGHT: u32 = 240;

#[entry]
fn main() -> ! {
    let dp = pac::Peripherals::take().unwrap();
    let cp = cortex_m::Peripherals::take().unwrap();
    let mut rcc = dp
        .RCC
        .freeze(Config::hse(HSE_HZ.Hz()).sysclk(SYSCLK_HZ.Hz()));
    let mut delay = cp.SYST.delay(&rcc.clocks);
    let pins = Wiring::new(dp.GPIOA.split(&mut rcc), dp.GPIOB.split(&mut rcc));

    let frame = scene::frame(WIDTH, HEIGHT);

    let spi = dp.SPI1.spi(
        (Some(pins.sck), SPI1::NoMiso, Some(pins.mosi)),
        embedded_hal::spi::MODE_0,
        SPI_HZ.Hz(),
        &mut rcc,
    );
    let spi = ExclusiveDevice::new_no_delay(spi, pins.cs.into_push_pull_output()).unwrap();
    let mut spi_buffer = [0u8; 512];
    let di = SpiInterface::new(spi, pins.dc.into_push_pull_output(), &mut spi_buffer);
    let mut display = Builder::new(ILI9341Rgb565, di)
        .orientation(Orientation::new().rotate(Rotation::Deg90)) // landscape: 320×240
        .color_order(ColorOrder::Bgr) // the usual ILI9341 modules' subpixel order
        .reset_pin(pins.rst.into_push_pull_output())
        .init(&mut delay)
        .unwrap();
    let mut backlight = pins.backlight.into_push_pull_output();
    backlight.set_high();

    frame.draw(&mut display).unwrap();
    loop {
        cortex_m::asm::wfi();
    }
}
