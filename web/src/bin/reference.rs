//! The host's pixels for the page's test: frame `k` of `n` of a scene file (an orbit of
//! `degrees` without keyframes), computed by the same `render_rgba` as the page's module.
//!
//! `reference SCENE K N DEGREES OUT [--repeat R]` writes frame K's raw RGBA bytes to OUT and
//! prints `WIDTH HEIGHT`; with `--repeat`, it then renders R frames on one thread, K and the
//! ones after it as the page's animation does, and prints the median time of a frame (the
//! render alone, as the page times it).

use std::process::ExitCode;
use std::time::Instant;

use microray_web::Animation;

fn main() -> ExitCode {
    match run(std::env::args().skip(1).collect()) {
        Ok(()) => ExitCode::SUCCESS,
        Err(e) => {
            eprintln!("reference: {e}");
            ExitCode::from(2)
        }
    }
}

fn run(args: Vec<String>) -> Result<(), String> {
    let usage = "usage: reference SCENE K N DEGREES OUT [--repeat R]";
    let (positional, repeat) = match args.iter().position(|a| a == "--repeat") {
        Some(i) => {
            let r = args.get(i + 1).ok_or(usage)?;
            let r: u32 = r
                .parse()
                .map_err(|_| format!("--repeat: not a count: {r}"))?;
            ([&args[..i], &args[i + 2..]].concat(), r)
        }
        None => (args, 0),
    };
    let [scene, k, n, degrees, out] = <[String; 5]>::try_from(positional).map_err(|_| usage)?;
    let number = |name: &str, s: &str| format!("{name}: not a number: {s}");
    let k: u32 = k.parse().map_err(|_| number("K", &k))?;
    let n: u32 = n.parse().map_err(|_| number("N", &n))?;
    let degrees: f32 = degrees.parse().map_err(|_| number("DEGREES", &degrees))?;

    let text = std::fs::read_to_string(&scene).map_err(|e| format!("{scene}: {e}"))?;
    // The test's pixels come from the library's one function for the page's pixels.
    let (width, height, rgba) =
        microray_web::render_rgba(&text, k, n, degrees).map_err(|e| format!("{scene}: {e}"))?;
    std::fs::write(&out, &rgba).map_err(|e| format!("{out}: {e}"))?;
    println!("{width} {height}");

    if repeat > 0 {
        let mut animation = Animation::parse(&text)?;
        let mut buf = Vec::new();
        let mut ms: Vec<f64> = (0..repeat)
            .map(|i| {
                let start = Instant::now();
                animation.render_rgba((k + i) % n.max(1), n, degrees, &mut buf)?;
                Ok(start.elapsed().as_secs_f64() * 1e3)
            })
            .collect::<Result<_, String>>()?;
        ms.sort_by(f64::total_cmp);
        println!(
            "median {:.2} ms a frame over {repeat} renders (min {:.2}, max {:.2})",
            ms[ms.len() / 2],
            ms[0],
            ms[ms.len() - 1]
        );
    }
    Ok(())
}
