//! # atomic-file
//!
//! Every output of violin-skeleton is written the same way (the output contract):
//!
//! - a regular file is written into a temporary file in the target's folder, flushed, given
//!   ordinary permissions (tempfile makes files 0600 and folders 0700), then renamed over the
//!   target, so a failure or a killed process leaves either the old file or the complete new
//!   one, and no temporary file behind;
//! - `-` is standard output, written directly;
//! - an existing special file (a FIFO, a character or block device, a socket) is opened and
//!   written directly, never replaced ([`Destination`]);
//! - a folder output is filled under a temporary name and renamed into place; an existing
//!   folder is replaced only when it holds nothing but files the writer itself makes
//!   ([`replace_dir_atomically`]);
//! - [`same_file`] tells a caller when an output would overwrite one of its inputs.
//!
//! ```
//! use std::io::Write;
//! let dir = tempfile::tempdir()?;
//! let path = dir.path().join("out.txt");
//! atomic_file::write_atomically(&path, |w| w.write_all(b"hello"))?;
//! assert_eq!(std::fs::read(&path)?, b"hello");
//! # Ok::<(), Box<dyn std::error::Error>>(())
//! ```

mod destination;
mod dir;
mod file;

pub use destination::{destination, is_stdout, same_file, Destination};
pub use dir::replace_dir_atomically;
pub use file::{
    make_ordinary, parent_dir, write_atomically, write_bytes_atomically, AtomicWriteError,
};
