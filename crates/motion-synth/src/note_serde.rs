//! The JSON form of a played note: fingering fields flattened beside the times, strictly
//! all-or-none (serde's `flatten` on an `Option` would silently drop a malformed fingering).

use fingering::{Fingering, Placement, ViolinString};
use serde::{Deserialize, Serialize};

use crate::error::PerformanceError;
use crate::performance::PlayedNote;

/// A note as it appears in `analysis.json` and performance files.
#[derive(Debug, Clone, Copy, Serialize, Deserialize)]
pub(crate) struct NoteRecord {
    onset_s: f64,
    offset_s: f64,
    midi: u8,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    string: Option<ViolinString>,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    position: Option<u8>,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    finger: Option<u8>,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    placement: Option<Placement>,
}

impl TryFrom<NoteRecord> for PlayedNote {
    type Error = PerformanceError;
    fn try_from(r: NoteRecord) -> Result<PlayedNote, PerformanceError> {
        let fingering = match (r.string, r.position, r.finger) {
            (Some(string), Some(position), Some(finger)) => Some(Fingering::with_placement(
                string,
                position,
                finger,
                r.placement.unwrap_or_default(),
            )),
            (None, None, None) if r.placement.is_none() => None,
            // serde reports where in the file the note is.
            _ => return Err(PerformanceError::PartialFingering),
        };
        Ok(PlayedNote {
            onset_s: r.onset_s,
            offset_s: r.offset_s,
            midi: r.midi,
            fingering,
        })
    }
}

impl From<PlayedNote> for NoteRecord {
    fn from(n: PlayedNote) -> NoteRecord {
        let f = n.fingering;
        NoteRecord {
            onset_s: n.onset_s,
            offset_s: n.offset_s,
            midi: n.midi,
            string: f.map(|f| f.string),
            position: f.map(|f| f.position),
            finger: f.map(|f| f.finger),
            placement: f.map(|f| f.placement).filter(|p| !p.is_normal()),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn fingering_fields_sit_beside_the_times() {
        let n = PlayedNote {
            fingering: Some(Fingering::new(ViolinString::D, 1, 3)),
            ..PlayedNote::new(0.5, 1.0, 67)
        };
        let text = serde_json::to_string(&n).unwrap();
        assert_eq!(
            text,
            r#"{"onset_s":0.5,"offset_s":1.0,"midi":67,"string":2,"position":1,"finger":3}"#
        );
        assert_eq!(serde_json::from_str::<PlayedNote>(&text).unwrap(), n);
        let bare: PlayedNote =
            serde_json::from_str(r#"{"onset_s":0,"offset_s":1,"midi":60}"#).unwrap();
        assert_eq!(bare.fingering, None);
    }

    #[test]
    fn partial_or_bad_fingering_is_an_error() {
        let partial = r#"{"onset_s":0,"offset_s":1,"midi":60,"string":2}"#;
        let e = serde_json::from_str::<PlayedNote>(partial).unwrap_err();
        assert!(e.to_string().contains("part of its fingering"), "{e}");
        let bad_string =
            r#"{"onset_s":0,"offset_s":1,"midi":60,"string":7,"position":1,"finger":1}"#;
        assert!(serde_json::from_str::<PlayedNote>(bad_string).is_err());
    }
}
