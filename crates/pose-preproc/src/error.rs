//! The error type of `pose-preproc`.

use std::path::PathBuf;

use skeleton::PoseLayout;

/// Everything that can go wrong reading an OpenPose directory, cleaning it or labelling it.
///
/// Every variant about a file or directory names it and says what to do.
#[derive(Debug, thiserror::Error)]
pub enum PosePreprocError {
    /// The directory does not exist.
    #[error("{dir}: directory not found; check the path")]
    NotFound {
        /// The path given.
        dir: PathBuf,
    },
    /// The path is a file, not a directory.
    #[error("{path}: not a directory; pass the folder of OpenPose *_keypoints.json files (openpose --write_json DIR)")]
    NotADirectory {
        /// The path given.
        path: PathBuf,
    },
    /// A file or directory could not be read.
    #[error("{path}: cannot read: {source}")]
    Io {
        /// The file or directory.
        path: PathBuf,
        /// The underlying error.
        source: std::io::Error,
    },
    /// The directory has no entries at all.
    #[error("{dir}: the directory is empty; run OpenPose with --write_json {dir} first")]
    EmptyDirectory {
        /// The directory.
        dir: PathBuf,
    },
    /// The directory has entries, but no `.json` file.
    #[error("{dir}: no JSON files among its {entries} entries; expected OpenPose *_keypoints.json files (openpose --write_json)")]
    NoJsonFiles {
        /// The directory.
        dir: PathBuf,
        /// How many entries it has.
        entries: usize,
    },
    /// A JSON file's name has no frame number to order it by.
    #[error("{file}: no frame number in the file name; OpenPose names its files NAME_000000000000_keypoints.json")]
    NoFrameNumber {
        /// The file.
        file: PathBuf,
    },
    /// Two files carry the same frame number (two videos in one directory?).
    #[error(
        "{file}: frame number {frame} is also the number of {other}; keep one video per directory"
    )]
    DuplicateFrame {
        /// The second file.
        file: PathBuf,
        /// The first file with that number.
        other: PathBuf,
        /// The frame number.
        frame: u64,
    },
    /// The frame numbers are far sparser than one video's (files of unrelated runs?).
    #[error("{dir}: frame numbers run from {first} to {last} but there are only {files} files; keep the frames of one video per directory")]
    SparseNumbering {
        /// The directory.
        dir: PathBuf,
        /// Lowest frame number.
        first: u64,
        /// Highest frame number.
        last: u64,
        /// Number of files.
        files: usize,
    },
    /// A file is not valid OpenPose JSON.
    #[error("{file}: malformed OpenPose JSON: {message}; re-run OpenPose or delete the file")]
    MalformedJson {
        /// The file.
        file: PathBuf,
        /// What the JSON parser said (with line and column).
        message: String,
    },
    /// A person's keypoint array has a length no OpenPose body model has.
    #[error("{file}: person {person} has {values} keypoint values ({keypoints} keypoints of {stride} values); expected 18 (COCO-18) or 25 (BODY_25) keypoints")]
    WrongKeypointCount {
        /// The file.
        file: PathBuf,
        /// Index of the person in `people`.
        person: usize,
        /// Number of values in the array.
        values: usize,
        /// Values per keypoint (3 for `pose_keypoints_2d`, 4 for `pose_keypoints_3d`).
        stride: usize,
        /// `values / stride`.
        keypoints: usize,
    },
    /// Files of one directory use different body models.
    #[error("{dir}: mixed layouts: {first_file} is {first:?} but {other_file} is {other:?}; process the output of one OpenPose run per directory")]
    MixedLayouts {
        /// The directory.
        dir: PathBuf,
        /// The first file read.
        first_file: PathBuf,
        /// Its layout.
        first: PoseLayout,
        /// A file with another layout.
        other_file: PathBuf,
        /// That layout.
        other: PoseLayout,
    },
    /// No frame has a plausible person.
    #[error("{dir}: no person detected in any of its {frames} frames; check that OpenPose saw the performer (and that --model_pose is BODY_25 or COCO)")]
    NoPerson {
        /// The directory.
        dir: PathBuf,
        /// Number of frames read.
        frames: usize,
    },
    /// One of the ten joints is never detected on the performer, so it cannot be filled.
    #[error("{dir}: joint {joint} of the performer is never detected with confidence ≥ {threshold}; the video must show the upper body and hips (or lower confidence_threshold)")]
    JointNeverDetected {
        /// The directory.
        dir: PathBuf,
        /// The joint's name.
        joint: &'static str,
        /// The confidence threshold used.
        threshold: f32,
    },
    /// The clip is too short to label (the zero-phase filter needs more frames).
    #[error("clip of {frames} frames is too short for bow-change labels; at least {needed} frames are needed")]
    ClipTooShort {
        /// Frames in the clip.
        frames: usize,
        /// Frames needed.
        needed: usize,
    },
    /// A track holds a NaN or infinite value.
    #[error(
        "the bowing wrist's track has a non-finite value at frame {frame}; clean the motion first"
    )]
    NonFinite {
        /// The first bad frame.
        frame: usize,
    },
    /// The performer's torso and shoulders are both under a pixel: no unit for the threshold.
    #[error("the performer's torso length ({torso_px:.2} px) and shoulder width are under 1 px; the skeleton has no usable size (use --axis y for a threshold in pixels)")]
    NoSize {
        /// The median torso length found, pixels.
        torso_px: f64,
    },
    /// A configuration value is out of range.
    #[error("invalid configuration: {0}")]
    InvalidConfig(String),
    /// A filter of `dsp-mel` failed.
    #[error(transparent)]
    Dsp(#[from] dsp_mel::DspError),
    /// Building or writing the motion failed.
    #[error(transparent)]
    Skeleton(#[from] skeleton::SkeletonError),
}

/// `Result` with [`PosePreprocError`].
pub type Result<T> = std::result::Result<T, PosePreprocError>;
