//! # pose-preproc
//!
//! OpenPose JSON directories → the violinist's cleaned 10-joint skeleton at 30 fps, and the
//! bow-change labels that train the bowing network (SPEC §3).
//!
//! Pipeline of [`preprocess_dir`] (defaults in [`PreprocConfig`]):
//! 1. [`read`]: files ordered by the frame number in their names; COCO-18 or BODY_25 detected
//!    from the keypoint count; our ten joints of every person kept (z dropped if present);
//! 2. [`performer`]: the most confident large person is chosen and followed, with hysteresis
//!    against bystanders and one-frame false detections;
//! 3. [`swap`]: left/right joints the pose estimator swapped for a few frames are swapped
//!    back; [`fill`]: joints below confidence 0.05 (or absent) are interpolated over gaps up to 15
//!    frames; longer gaps are held at the nearest valid value and reported;
//! 4. centring by the per-video mean of all kept joints ([`skeleton::Motion::center`]);
//! 5. median smoothing of every coordinate (window 3, edges repeated);
//! 6. [`labels`]: bow changes from the bowing wrist's coordinate along the bow axis
//!    ([`axis`]: the arm, the axis and the performer's size are found in the data).
//!
//! The result is a [`PoseTrack`]: the [`skeleton::Motion`], the bow-change frames and a
//! [`QualityReport`] (serde) saying what was found and filled.
//!
//! ```no_run
//! use pose_preproc::{preprocess_dir, PreprocConfig};
//! let track = preprocess_dir("take1_openpose".as_ref(), &PreprocConfig::default())?;
//! println!("bow changes at frames {:?}", track.bow_change_frames);
//! for gap in &track.quality.long_gaps {
//!     println!("{} missing for {} frames from frame {}", gap.joint.name(), gap.len, gap.start_frame);
//! }
//! # Ok::<(), pose_preproc::PosePreprocError>(())
//! ```

pub mod axis;
mod config;
mod corner;
mod error;
pub mod fill;
pub mod labels;
pub mod metrics;
pub mod performer;
mod pipeline;
mod quality;
pub mod read;
pub mod resample;
pub mod swap;

pub use axis::Arm;
pub use config::{
    AxisMode, BowArmChoice, ChangePoint, LabelConfig, PerformerConfig, PreprocConfig,
};
pub use error::{PosePreprocError, Result};
pub use labels::{bow_change_labels, bow_change_labels_checked, label_motion, BowLabels};
pub use pipeline::{preprocess_dir, preprocess_poses, PoseTrack};
pub use quality::{Gap, QualityReport};
pub use read::{read_openpose_dir, Detection, RawPoses};
