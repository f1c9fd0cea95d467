//! The module's exports to `main.js`: plain functions of numbers, no bindings generator. JS
//! writes the scene's text into a buffer this module owns, then reads the pixels and error
//! messages straight out of the module's memory. Nothing here dereferences a raw pointer: the
//! pointers only go out, and the contract below is JS's to keep.
//!
//! The pointer contract: a pointer returned by an export stays valid, and its bytes unchanged
//! by Rust, until the next call into the module. JS writes only into `text_buffer`'s bytes,
//! and only between calls, when Rust holds no reference to them.

#![allow(unsafe_code)]

use std::cell::RefCell;

use crate::Animation;

#[derive(Default)]
struct State {
    /// The scene text JS wrote, up to `load`.
    text: Vec<u8>,
    /// The last scene that loaded: a scene with errors leaves it in place.
    animation: Option<Animation>,
    rgba: Vec<u8>,
    error: String,
}

thread_local! {
    // The module runs on one thread (no atomics in this build): one state, no locking.
    static STATE: RefCell<State> = RefCell::new(State::default());
}

fn with<R>(f: impl FnOnce(&mut State) -> R) -> R {
    STATE.with(|s| f(&mut s.borrow_mut()))
}

/// A buffer of `len` zero bytes for JS to write the scene's UTF-8 text into, before `load`.
// SAFETY: the only symbol of this name in the module. The pointer is to `len` initialised
// bytes of a `Vec` that no Rust code touches until the next call (the contract above).
#[unsafe(no_mangle)]
pub extern "C" fn text_buffer(len: usize) -> *mut u8 {
    with(|s| {
        s.text.clear();
        s.text.resize(len, 0);
        s.text.as_mut_ptr()
    })
}

/// Reads the first `len` bytes of the text buffer as a scene: 0 if it loaded (it replaces the
/// previous scene), else 1 with the message at `error_ptr`/`error_len`, the previous scene
/// kept.
// SAFETY: the only symbol of this name in the module; takes and returns plain numbers.
#[unsafe(no_mangle)]
pub extern "C" fn load(len: usize) -> i32 {
    with(|s| {
        let loaded = s
            .text
            .get(..len)
            .ok_or_else(|| format!("{len} bytes of text, more than the buffer holds"))
            .and_then(|bytes| std::str::from_utf8(bytes).map_err(|e| e.to_string()))
            .and_then(Animation::parse);
        match loaded {
            Ok(animation) => {
                s.animation = Some(animation);
                s.error.clear();
                0
            }
            Err(e) => {
                s.error = e;
                1
            }
        }
    })
}

/// Renders frame `k` of `n` (an orbit of `degrees`, or the scene's keyframes) and returns
/// the `width() × height() × 4` RGBA bytes, or null with the message at `error_ptr`.
// SAFETY: the only symbol of this name in the module. The pointer is to the `Vec`'s
// initialised bytes, which no Rust code touches until the next call (the contract above).
#[unsafe(no_mangle)]
pub extern "C" fn render(k: u32, n: u32, degrees: f32) -> *const u8 {
    with(|s| {
        let State {
            animation,
            rgba,
            error,
            ..
        } = s;
        let rendered = match animation {
            Some(a) => a.render_rgba(k, n, degrees, rgba),
            None => Err("no scene loaded".to_string()),
        };
        match rendered {
            Ok(()) => rgba.as_ptr(),
            Err(e) => {
                *error = e;
                std::ptr::null()
            }
        }
    })
}

/// The loaded scene's width in pixels (0 before one loads).
// SAFETY: the only symbol of this name in the module; returns a number.
#[unsafe(no_mangle)]
pub extern "C" fn width() -> u32 {
    with(|s| s.animation.as_ref().map_or(0, Animation::width))
}

/// The loaded scene's height in pixels (0 before one loads).
// SAFETY: the only symbol of this name in the module; returns a number.
#[unsafe(no_mangle)]
pub extern "C" fn height() -> u32 {
    with(|s| s.animation.as_ref().map_or(0, Animation::height))
}

/// The last error's UTF-8 message, `error_len()` bytes.
// SAFETY: the only symbol of this name in the module. The pointer is to the `String`'s
// bytes, which no Rust code touches until the next call (the contract above).
#[unsafe(no_mangle)]
pub extern "C" fn error_ptr() -> *const u8 {
    with(|s| s.error.as_ptr())
}

/// The length in bytes of the last error's message.
// SAFETY: the only symbol of this name in the module; returns a number.
#[unsafe(no_mangle)]
pub extern "C" fn error_len() -> usize {
    with(|s| s.error.len())
}
