//! The error type of `skeleton`.

use std::path::PathBuf;

/// What can go wrong building, reading or writing motion.
#[derive(Debug, thiserror::Error)]
pub enum SkeletonError {
    /// An array does not have the shape a motion track needs.
    #[error("wrong shape: expected {expected}, got {got:?}")]
    Shape {
        /// What was expected, in words (e.g. "(frames, 10, 2)").
        expected: String,
        /// The shape given.
        got: Vec<usize>,
    },
    /// The frame rate is not a positive finite number.
    #[error("invalid frame rate {0}; use a positive number of frames per second")]
    InvalidFps(f64),
    /// A file could not be read or written.
    #[error("{path}: {source}")]
    Io {
        /// The file.
        path: PathBuf,
        /// The underlying error.
        source: std::io::Error,
    },
    /// A file's content is not what its format requires.
    #[error("{path}: {reason}")]
    Format {
        /// The file.
        path: PathBuf,
        /// What is wrong, and where.
        reason: String,
    },
    /// A coordinate (in a motion or a file) is NaN or infinite.
    #[error(
        "{path}: {location} is not a finite number; motion files must hold finite coordinates"
    )]
    NonFinite {
        /// The file (or `<memory>` for in-memory writers).
        path: PathBuf,
        /// Where: track, frame, joint and coordinate.
        location: String,
    },
    /// A field the format requires is absent.
    #[error("{path}: missing field `{field}`; {hint}")]
    MissingField {
        /// The file.
        path: PathBuf,
        /// The field's name.
        field: String,
        /// What the field should hold.
        hint: String,
    },
    /// A track in a file does not have the shape its format requires.
    #[error("{path}: wrong shape: {what}")]
    FileShape {
        /// The file.
        path: PathBuf,
        /// What was expected and what was found.
        what: String,
    },
    /// A joint (or instrument point) name that the product does not know.
    #[error("{path}: unknown joint name {name:?}; the joints are nose, neck, r_shoulder, r_elbow, r_wrist, l_shoulder, l_elbow, l_wrist, r_hip, l_hip")]
    UnknownJoint {
        /// The file.
        path: PathBuf,
        /// The unknown name.
        name: String,
    },
    /// A joint (or instrument point) the file should list is not there (or is listed twice).
    #[error("{path}: joint {name} is {problem}; list each of the 10 joints exactly once")]
    MissingJoint {
        /// The file.
        path: PathBuf,
        /// The joint's name.
        name: String,
        /// `missing` or `listed twice`.
        problem: String,
    },
    /// The motion has no frames: nothing to write, or a file holds none.
    #[error("{path}: the motion has no frames")]
    Empty {
        /// The file.
        path: PathBuf,
    },
    /// The file format cannot be told from the path.
    #[error("{path}: cannot tell the motion format from the extension; use .json, .csv, .npy, .glb or a directory (OpenPose)")]
    UnknownFormat {
        /// The path.
        path: PathBuf,
    },
    /// The motion lacks a track that the operation needs.
    #[error("the motion has no {track}; {hint}")]
    MissingTrack {
        /// The track (e.g. "3-D track").
        track: &'static str,
        /// What to do.
        hint: &'static str,
    },
    /// A node animation (for glTF export) is not well formed.
    #[error("invalid node animation: {reason}")]
    InvalidAnimation {
        /// What is wrong.
        reason: String,
    },
    /// Writing to a stream failed.
    #[error("write failed: {0}")]
    Write(#[from] std::io::Error),
    /// A canvas size (`--canvas WxH`) that is not a size or cannot hold a person.
    #[error("canvas {0}")]
    InvalidCanvas(String),
    /// A BVH text is malformed.
    #[error("BVH line {line}: {reason}")]
    BvhParse {
        /// 1-based line number.
        line: usize,
        /// What is wrong.
        reason: String,
    },
}

/// `Result` with [`SkeletonError`].
pub type Result<T> = std::result::Result<T, SkeletonError>;
