//! The library API under any `f32`: a few thousand call sequences from a fixed seed
//! ([`fuzz_cases::ApiCase`]: NaN, infinities, subnormals, ±0, 10³⁸, random bit patterns and
//! ordinary magnitudes in every sphere, material, light, colour, camera and option field)
//! either fail with an `Error` when they are built or render without a panic, every way of
//! rendering giving the same pixels (`fuzz_cases::check_frame`). `MICRORAY_API_CASES` runs
//! more; `fuzz/` runs the same cases under libFuzzer.

mod common;
mod fuzz_cases;

use arbitrary::{Arbitrary, Unstructured};
use common::rng::Rng;
use fuzz_cases::{check_api, ApiCase, Reached};

#[test]
fn arbitrary_values_fail_cleanly_or_render_consistently() {
    let cases: u32 = std::env::var("MICRORAY_API_CASES")
        .ok()
        .and_then(|v| v.parse().ok())
        .unwrap_or(3000);
    let mut g = Rng(0x2545_f491_4f6c_dd1d);
    let (mut refused, mut rendered, mut lit, mut rejected) = (0, 0, 0, 0);
    for k in 0..cases {
        let bytes: Vec<u8> = (0..64 + g.next() % 2048).map(|_| g.next() as u8).collect();
        let Ok(case) = ApiCase::arbitrary(&mut Unstructured::new(&bytes)) else {
            continue;
        };
        let result = std::panic::catch_unwind(|| check_api(&case));
        let Ok((reached, r)) = result else {
            panic!("case {k} panicked: {case:?}");
        };
        rejected += r;
        match reached {
            Reached::Refused => refused += 1,
            Reached::Rendered => rendered += 1,
            Reached::RenderedLit => lit += 1,
        }
    }
    eprintln!("refused {refused}, rendered {rendered}, lit {lit}, values rejected {rejected}");
    // Every way out is taken, and most cases reach the renderer with lights and spheres.
    assert!(lit > cases / 3, "{lit} lit of {cases}");
    assert!(
        refused > cases / 50 && rendered > cases / 50,
        "{refused} / {rendered}"
    );
    assert!(rejected > cases, "{rejected} values rejected");
}
