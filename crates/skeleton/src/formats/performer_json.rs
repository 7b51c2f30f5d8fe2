//! The `performer` field of motion JSON: BODY_25 body, both hands, violin and bow.
//!
//! ```text
//! "performer": {"body_points": [25 names], "hand_points": [21 names],
//!               "instrument_points": [17 names],
//!               "body": [[[x, y] × 25] × T], "left_hand": …, "right_hand": …, "instrument": …,
//!               "body_3d": [[[x, y, z] × 25] × T], … (when the 3-D tracks exist)}
//! ```

use std::path::Path;

use serde::{Deserialize, Serialize};

use super::track_json::{column_order, to_track, RawTrack, Track};
use crate::error::{Result, SkeletonError};
use crate::performer::{PerformerPart, PerformerTrack};

#[derive(Serialize)]
pub(crate) struct PerformerOut<'a> {
    body_points: Vec<&'static str>,
    hand_points: Vec<&'static str>,
    instrument_points: Vec<&'static str>,
    body: Track<'a>,
    left_hand: Track<'a>,
    right_hand: Track<'a>,
    instrument: Track<'a>,
    #[serde(skip_serializing_if = "Option::is_none")]
    body_3d: Option<Track<'a>>,
    #[serde(skip_serializing_if = "Option::is_none")]
    left_hand_3d: Option<Track<'a>>,
    #[serde(skip_serializing_if = "Option::is_none")]
    right_hand_3d: Option<Track<'a>>,
    #[serde(skip_serializing_if = "Option::is_none")]
    instrument_3d: Option<Track<'a>>,
}

impl<'a> PerformerOut<'a> {
    pub(crate) fn new(p: &'a PerformerTrack) -> Self {
        use PerformerPart::*;
        PerformerOut {
            body_points: Body.point_names(),
            hand_points: LeftHand.point_names(),
            instrument_points: Instrument.point_names(),
            body: Track(p.track(Body)),
            left_hand: Track(p.track(LeftHand)),
            right_hand: Track(p.track(RightHand)),
            instrument: Track(p.track(Instrument)),
            body_3d: p.track_3d(Body).map(Track),
            left_hand_3d: p.track_3d(LeftHand).map(Track),
            right_hand_3d: p.track_3d(RightHand).map(Track),
            instrument_3d: p.track_3d(Instrument).map(Track),
        }
    }
}

#[derive(Deserialize)]
pub(crate) struct PerformerIn {
    body_points: Option<Vec<String>>,
    hand_points: Option<Vec<String>>,
    instrument_points: Option<Vec<String>>,
    body: RawTrack,
    left_hand: RawTrack,
    right_hand: RawTrack,
    instrument: RawTrack,
    body_3d: Option<RawTrack>,
    left_hand_3d: Option<RawTrack>,
    right_hand_3d: Option<RawTrack>,
    instrument_3d: Option<RawTrack>,
}

impl PerformerIn {
    /// The performer track of a file whose core track has `frames` frames.
    pub(crate) fn into_track(self, path: &Path, frames: usize) -> Result<PerformerTrack> {
        let names = [
            &self.body_points,
            &self.hand_points,
            &self.hand_points,
            &self.instrument_points,
        ];
        let mut orders = Vec::with_capacity(4);
        for (part, listed) in PerformerPart::ALL.iter().zip(names) {
            let known = part.point_names();
            orders.push(match listed {
                Some(n) => column_order(path, n, &known)?,
                None => (0..known.len()).collect(),
            });
        }
        let read = |raw: &RawTrack, i: usize, suffix: &str, dims: usize| {
            let part = PerformerPart::ALL[i];
            let field = format!("performer.{}{suffix}", part.name());
            if raw.len() != frames {
                return Err(SkeletonError::FileShape {
                    path: path.to_path_buf(),
                    what: format!("{field} has {} frames, frames has {frames}", raw.len()),
                });
            }
            to_track(path, &field, raw, &orders[i], &part.point_names(), dims)
        };
        let raw2 = [
            &self.body,
            &self.left_hand,
            &self.right_hand,
            &self.instrument,
        ];
        let mut px = Vec::with_capacity(4);
        for (i, raw) in raw2.into_iter().enumerate() {
            px.push(read(raw, i, "", 2)?);
        }
        let shape = |e: SkeletonError| SkeletonError::Format {
            path: path.to_path_buf(),
            reason: e.to_string(),
        };
        let px: [_; 4] = px.try_into().map_err(|_| SkeletonError::Format {
            path: path.to_path_buf(),
            reason: "performer: four tracks expected".into(),
        })?;
        let mut track = PerformerTrack::new(px).map_err(shape)?;
        let raw3 = [
            &self.body_3d,
            &self.left_hand_3d,
            &self.right_hand_3d,
            &self.instrument_3d,
        ];
        if raw3.iter().any(|r| r.is_some()) {
            let mut m = Vec::with_capacity(4);
            for (i, raw) in raw3.into_iter().enumerate() {
                let part = PerformerPart::ALL[i];
                let raw = raw.as_ref().ok_or_else(|| SkeletonError::MissingField {
                    path: path.to_path_buf(),
                    field: format!("performer.{}_3d", part.name()),
                    hint: "all four 3-D performer tracks, or none".into(),
                })?;
                m.push(read(raw, i, "_3d", 3)?);
            }
            let m: [_; 4] = m.try_into().map_err(|_| SkeletonError::Format {
                path: path.to_path_buf(),
                reason: "performer: four 3-D tracks expected".into(),
            })?;
            track = track.with_3d(m).map_err(shape)?;
        }
        Ok(track)
    }
}
