//! A decoder that panics on a corrupt file (a bug in a codec library, found by the
//! `input-fuzz` mutants: e.g. an assertion in the Vorbis codebook setup) becomes a
//! [`DspError::Corrupt`] for that file, never a crash.

use std::cell::Cell;
use std::panic::{catch_unwind, AssertUnwindSafe};
use std::path::Path;

use crate::error::{DspError, Result};

thread_local! {
    static GUARDED: Cell<bool> = const { Cell::new(false) };
}

/// `true` while this thread runs codec code under the guard. A program's panic hook can
/// stay silent then: the panic is turned into an error that names the file.
///
/// ```
/// // In a binary: print panics as usual, except the ones dsp-mel turns into errors.
/// let default = std::panic::take_hook();
/// std::panic::set_hook(Box::new(move |info| {
///     if !dsp_mel::inside_decoder_guard() {
///         default(info)
///     }
/// }));
/// ```
pub fn inside_decoder_guard() -> bool {
    GUARDED.with(Cell::get)
}

/// Runs codec code `f` for the file at `path`; a panic inside becomes a `Corrupt` error.
pub(crate) fn guarded<T>(path: &Path, f: impl FnOnce() -> Result<T>) -> Result<T> {
    let was = GUARDED.with(|g| g.replace(true));
    let outcome = catch_unwind(AssertUnwindSafe(f));
    GUARDED.with(|g| g.set(was));
    outcome.unwrap_or_else(|payload| {
        let message = payload
            .downcast_ref::<String>()
            .map(String::as_str)
            .or_else(|| payload.downcast_ref::<&str>().copied())
            .unwrap_or("no message");
        Err(DspError::Corrupt {
            path: path.into(),
            reason: format!("the decoder gave up on a damaged stream ({message})"),
        })
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_panic_becomes_an_error_and_the_flag_is_reset() {
        let quiet = std::panic::take_hook();
        std::panic::set_hook(Box::new(|_| {}));
        let r: Result<()> = guarded(Path::new("x.ogg"), || {
            assert!(inside_decoder_guard());
            panic!("codebook underspecified")
        });
        std::panic::set_hook(quiet);
        let e = r.unwrap_err().to_string();
        assert!(
            e.contains("x.ogg") && e.contains("codebook underspecified"),
            "{e}"
        );
        assert!(!inside_decoder_guard());
        assert_eq!(guarded(Path::new("x"), || Ok(3)).unwrap(), 3);
    }
}
